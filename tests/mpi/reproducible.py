#!/usr/bin/env python3
"""Run-to-run reproducibility of the PETSc engine: the same case run twice on the same number of
ranks must write the same files, byte for byte (VTU pieces, history.csv, probes.csv), and the same
summary.json but for its timings, memory, date and command line.

  reproducible.py --vpcontact BIN --mpiexec MPIEXEC --work DIR --ranks P -- CASE [run options...]

What it guards: the partition (PTScotch's threads once made it differ from run to run, and with
it the last bits of every result and the Krylov iteration counts) and anything else that would
make two identical runs disagree. Prints "reproducible: PASSED" or the differences and
"reproducible: FAILED". Python standard library only.
"""
import filecmp
import json
import os
import subprocess
import sys

import case_runs

VOLATILE = {"timing_seconds", "setup_seconds", "memory_bytes", "vpcontact"}  # timings, memory; version, command line, date


def run(args, out):
    cmd = [args.mpiexec, "-n", str(args.ranks), args.vpcontact, "run", *args.case, "--engine", "petsc",
           "--output", out, "-q"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        print(f"run failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout}\n{r.stderr}")
        print("reproducible: FAILED")
        sys.exit(1)


def stable(summary_path):
    with open(summary_path) as f:
        d = json.load(f)
    return {k: v for k, v in d.items() if k not in VOLATILE}


def main():
    args = case_runs.parse(case_runs.parser(__doc__.splitlines()[0]))
    outs = [os.path.join(args.work, f"run{i}") for i in (1, 2)]
    for out in outs:
        run(args, out)
    names = sorted(f for f in os.listdir(outs[0]) if not f.startswith("checkpoint"))
    problems = []
    if names != sorted(f for f in os.listdir(outs[1]) if not f.startswith("checkpoint")):
        problems.append("the two runs wrote different files")
    for name in names:
        a, b = (os.path.join(o, name) for o in outs)
        if name == "summary.json":
            sa, sb = stable(a), stable(b)
            for key in sorted(set(sa) | set(sb)):
                if sa.get(key) != sb.get(key):
                    problems.append(f"summary.json: {key}: {sa.get(key)} against {sb.get(key)}")
        elif not os.path.exists(b) or not filecmp.cmp(a, b, shallow=False):
            problems.append(f"{name} differs")
    print(f"{len(names)} files compared")
    case_runs.report("reproducible", problems)


if __name__ == "__main__":
    main()
