#!/usr/bin/env python3
"""CG + GAMG's Galerkin products formed row by row where memory asks for it (run/solver_plan.cpp,
docs/parallel.md "Where the memory goes"): a case on CG + GAMG refused under a tiny --memory-limit
names the row-by-row estimate, the smaller; with a limit just above it the plan takes the
row-by-row products and says so; and that run gives the default run's answer to the solvers'
tolerance.

  low_memory.py --vpcontact BIN --mpiexec MPIEXEC --work DIR --ranks P -- CASE [options...]

Prints "low memory: PASSED" or what failed and "low memory: FAILED". Python standard library only.
"""
import os
import re
import subprocess
import sys

import case_runs

UNITS = {"B": 1, "KiB": 2**10, "MiB": 2**20, "GiB": 2**30, "TiB": 2**40}


def run(args, out, *extra):
    cmd = [args.mpiexec, "-n", str(args.ranks), args.vpcontact, "run", *args.case, "--engine", "petsc",
           "--linear-solver", "cg-gamg", "--output", out, "--no-vtu", *extra]
    return subprocess.run(cmd, capture_output=True, text=True), cmd


def finished(args, out, *extra):
    r, cmd = run(args, out, *extra)
    if r.returncode != 0:
        print(f"run failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout}\n{r.stderr}")
        print("low memory: FAILED")
        sys.exit(1)
    return r.stdout + r.stderr, case_runs.results(out)


def main():
    args = case_runs.parse(case_runs.parser(__doc__.splitlines()[0]))
    refused, _ = run(args, os.path.join(args.work, "refused"), "--memory-limit", "1K", "-q")
    said = refused.stdout + refused.stderr
    m = re.search(r"cg-gamg would need about ([0-9.]+) (B|KiB|MiB|GiB|TiB) of memory \(([^)]*\([^)]*\)[^)]*)\)", said)
    if refused.returncode == 0 or not m or "multigrid set-up (products row by row)" not in m.group(3):
        print(f"not refused as expected (exit {refused.returncode}):\n{said}")
        print("low memory: FAILED")
        sys.exit(1)
    smallest = float(m.group(1)) * UNITS[m.group(2)]
    limit = str(int(1.05 * smallest))  # above the row-by-row estimate, below the default's
    print(f"refused under 1K, naming {m.group(1)} {m.group(2)}; next limit {limit} bytes")
    said, low = finished(args, os.path.join(args.work, "row_by_row"), "--memory-limit", limit)
    _, default = finished(args, os.path.join(args.work, "default"), "-q")
    problems = case_runs.disagreements(low, default)
    if "Galerkin products formed row by row" not in said:
        problems.append("the plan under the limit did not take the row-by-row products:\n" + said)
    print(f"Krylov iterations: {low[0]['linear_iterations']} row by row, {default[0]['linear_iterations']} by default")
    case_runs.report("low memory", problems)


if __name__ == "__main__":
    main()
