"""What the scripts that run one case several times under mpiexec share (reproducible.py,
within_bodies.py, low_memory.py): their command line, --vpcontact BIN --mpiexec MPIEXEC --work DIR
--ranks P [their own options] -- CASE [run options...], and reading and comparing two runs' results.
Python standard library only."""
import argparse
import csv
import json
import os
import sys

COMPARED = ("total_contact_force", "max_von_mises", "beta_min")  # history.csv columns, to 1e-7 relative


def parser(description):
    """The shared options; a script adds its own before calling parse()."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--vpcontact", required=True)
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--ranks", type=int, default=2)
    return p


def parse(p):
    """The arguments, with the case and its run options (after "--") in args.case."""
    p.add_argument("case", nargs=argparse.REMAINDER)
    args = p.parse_args()
    if args.case and args.case[0] == "--":
        args.case = args.case[1:]
    return args


def results(out):
    """summary.json and history.csv's rows of the run written in `out`."""
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "history.csv")) as f:
        history = list(csv.DictReader(f))
    return summary, history


def disagreements(first, second):
    """What two runs' (summary, history) do not agree on, as lines: a step whose checks failed, the
    number of steps, a COMPARED column beyond 1e-7 relative."""
    problems = []
    for summary, _ in (first, second):
        if not summary["checks"]["all_steps_ok"]:
            problems.append("a step's checks failed")
    h1, h2 = first[1], second[1]
    if len(h1) != len(h2):
        problems.append(f"{len(h1)} steps against {len(h2)}")
    for a, b in zip(h1, h2):
        for col in COMPARED:
            x, y = float(a[col]), float(b[col])
            if abs(x - y) > 1e-7 * max(abs(x), abs(y), 1e-300):
                problems.append(f"step {a['step']}: {col} {x!r} against {y!r}")
    return problems


def report(name, problems):
    """Prints `problems` and "NAME: PASSED" or "NAME: FAILED" (what ctest looks for); exits 0 or 1."""
    for line in problems:
        print("  " + line)
    print(f"{name}: " + ("FAILED" if problems else "PASSED"))
    sys.exit(1 if problems else 0)
