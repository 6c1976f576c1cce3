#!/usr/bin/env python3
"""One process against `mpirun -np 2` on every shipped case (issue 48 item 18; docs/parallel.md,
"Two ranks against one process"): the median over repeats of each run's wall time, and how far
the two histories are apart.

    /usr/bin/python3 bench/ranks_vs_one.py --vpcontact build/app/vpcontact --repeats 3 [--cases a,b]

Each repeat runs `vpcontact run CASE --no-vtu -q` (one process: the program's own choice, CHOLMOD
or CG + GAMG) and `mpirun -np 2 --bind-to core vpcontact run CASE --no-vtu -q` (the PETSc engine,
auto's choice of solvers) one after the other, so that both see the same machine. Wall times:
`run` is the program's own (summary.json's timing_seconds.wall: case, mesh, set-up, steps,
output), `process` the whole command's (mpirun's launch of two processes included), and `work` the run's
less the seconds it spent starting MPI and PETSc (timing_seconds.mpi_start: what mpirun adds to any
program, about 0.3 s here), the work both routes do. The ratio is of `work`.
The histories are compared column by column: |a - b| against the column's largest magnitude
(the documented agreement of the engines is 1e-10; docs/parallel.md).
Prints a Markdown table and, with --csv, every run.
"""
import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMP_NUM_THREADS": "1"}


def shipped_cases(vpcontact):
    out = subprocess.run([vpcontact, "cases"], check=True, capture_output=True, text=True).stdout
    names = []
    for line in out.splitlines():
        word = line.strip().split(" ")[0] if line.strip() else ""
        if word and not word.endswith(":") and os.path.exists(os.path.join("cases", word + ".toml")):
            names.append(word)
    return names


def run_once(cmd, out_dir, env):
    shutil.rmtree(out_dir, ignore_errors=True)
    start = time.perf_counter()
    proc = subprocess.run(cmd + ["-o", out_dir], capture_output=True, text=True, env=env)
    process = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stdout}{proc.stderr}")
    with open(os.path.join(out_dir, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out_dir, "history.csv")) as f:
        history = list(csv.reader(line for line in f if not line.startswith("#")))
    t = summary["timing_seconds"]
    return {"process": process, "run": t["wall"], "work": t["wall"] - t.get("mpi_start", 0.0),
            "contact_solver": summary.get("contact_solver", ""), "history": history,
            "route": route(summary)}


FRICTION_RESIDUALS = ("friction_bound", "friction_stick_slip", "friction_slip_direction")


def route(summary):
    """How a run went: rank 0 alone (the serial engine under mpirun) or the PETSc engine, and its solvers."""
    engine = summary.get("engine", "")
    linear = summary.get("linear_solver", "cholmod" if engine != "petsc" else "")
    return f"{'PETSc, ' + linear if engine == 'petsc' else 'rank 0 alone, CHOLMOD'}; {summary.get('contact_solver', '')}"


def history_difference(a, b):
    """The largest |a - b| over the value columns, relative to the column's largest magnitude (the
    reactions: to the largest force), as tests/mpi/equivalence.py compares them; the solvers'
    residuals (round-off-sized) and iteration counts are left out. inf where the headers, the rows
    or a count (n_active, n_stick, ...) differ."""
    if len(a) != len(b) or a[0] != b[0]:
        return float("inf")
    head, worst = a[0], 0.0
    forces = [k for k, c in enumerate(head) if c.startswith("reaction_") or c == "total_contact_force"]
    largest = lambda rows, k: max((abs(float(r[k])) for r in rows[1:]), default=0.0)
    for j, name in enumerate(head):
        if ("residual" in name or "iterations" in name or name in FRICTION_RESIDUALS or name == "error_estimate"
                or name.startswith("contact_") and name != "contact_area"):
            continue
        xa, xb = [r[j] for r in a[1:]], [r[j] for r in b[1:]]
        if all(x.lstrip("-").isdigit() for x in xa + xb):
            if xa != xb:
                return float("inf")
            continue
        xa, xb = [float(x) for x in xa], [float(x) for x in xb]
        scale = max(largest(a, k) for k in forces) if name.startswith("reaction_") else max(map(abs, xa), default=0.0)
        if scale > 0:
            worst = max(worst, max(abs(p - q) for p, q in zip(xa, xb)) / scale)
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vpcontact", required=True)
    ap.add_argument("--mpiexec", default="mpirun")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cases", default="",
                    help="comma-separated, each a case and its options (default: every shipped case)")
    ap.add_argument("--csv", default="")
    args = ap.parse_args()
    vpc = os.path.realpath(args.vpcontact)
    cases = args.cases.split(",") if args.cases else shipped_cases(vpc)
    env = dict(os.environ, **MPI_ENV)
    work = tempfile.mkdtemp(prefix="ranks_vs_one_")
    rows, every = [], []
    try:
        for case in cases:
            one, two = [], []
            for rep in range(args.repeats):
                one.append(run_once([vpc, "run", *case.split(), "--no-vtu", "-q"], os.path.join(work, "one"), env))
                two.append(run_once([args.mpiexec, "-np", "2", "--bind-to", "core", vpc, "run", *case.split(), "--no-vtu", "-q"],
                                    os.path.join(work, "two"), env))
                for kind, r in (("one", one[-1]), ("two", two[-1])):
                    every.append([case, kind, rep, f"{r['run']:.3f}", f"{r['work']:.3f}", f"{r['process']:.3f}",
                                  r["route"]])
            med = lambda runs, key: statistics.median(r[key] for r in runs)
            row = {"case": case, "one_run": med(one, "run"), "two_run": med(two, "run"),
                   "one_work": med(one, "work"), "two_work": med(two, "work"),
                   "one_process": med(one, "process"), "two_process": med(two, "process"),
                   "route": two[0]["route"],
                   "difference": history_difference(one[0]["history"], two[0]["history"])}
            rows.append(row)
            print(f"{case}: {row['one_work']:.2f} s against {row['two_work']:.2f} s on 2 ranks "
                  f"({row['two_work'] / max(row['one_work'], 1e-9):.2f}x; with MPI's start {row['two_run']:.2f} s), "
                  f"histories {row['difference']:.1e}, {two[0]['route']}", file=sys.stderr, flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("| case | one process (s) | 2 ranks (s) | ratio | 2 ranks with MPI's start (s) | whole command, one / 2 ranks (s) | route on 2 ranks | histories apart |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['case']} | {r['one_work']:.2f} | {r['two_work']:.2f} | {r['two_work'] / max(r['one_work'], 1e-9):.2f} | "
              f"{r['two_run']:.2f} | {r['one_process']:.2f} / {r['two_process']:.2f} | {r['route']} | {r['difference']:.1e} |")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["case", "ranks", "repeat", "run_seconds", "work_seconds", "process_seconds", "route"])
            w.writerows(every)


if __name__ == "__main__":
    main()
