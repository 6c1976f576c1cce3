#!/usr/bin/env python3
"""Multigrid within bodies (la/petsc_segregated.hpp): a two-body case on CG + GAMG, run with GAMG's
aggregates kept within each body (the default) and across them (-vpc_K_within_fields false, in
PETSC_OPTIONS), must give the same answer to the solvers' tolerance, and the first must take
clearly fewer Krylov iterations (at most `--at-most` times the second's: across a frictionless
interface an aggregate on both sides moves them together, and the coarse space misses the sliding).

  within_bodies.py --vpcontact BIN --mpiexec MPIEXEC --work DIR --ranks P [--at-most 0.75] -- CASE [options...]

Iteration counts are the same from run to run (the partition is deterministic), so the bound is
not a timing. Prints "within bodies: PASSED" or what failed and "within bodies: FAILED".
Python standard library only.
"""
import os
import subprocess
import sys

import case_runs


def run(args, out, across):
    env = dict(os.environ)
    if across:
        env["PETSC_OPTIONS"] = (env.get("PETSC_OPTIONS", "") + " -vpc_K_within_fields false").strip()
    cmd = [args.mpiexec, "-n", str(args.ranks), args.vpcontact, "run", *args.case, "--engine", "petsc",
           "--linear-solver", "cg-gamg", "--output", out, "-q", "--no-vtu"]
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        print(f"run failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout}\n{r.stderr}")
        print("within bodies: FAILED")
        sys.exit(1)
    return case_runs.results(out)


def main():
    p = case_runs.parser(__doc__.splitlines()[0])
    p.add_argument("--at-most", type=float, default=0.75)
    args = case_runs.parse(p)
    within = run(args, os.path.join(args.work, "within"), across=False)
    across = run(args, os.path.join(args.work, "across"), across=True)
    problems = case_runs.disagreements(within, across)
    n_within, n_across = within[0]["linear_iterations"], across[0]["linear_iterations"]
    print(f"Krylov iterations: {n_within} within bodies, {n_across} across them")
    if not n_within <= args.at_most * n_across:
        problems.append(f"{n_within} iterations within bodies, not at most {args.at_most} x {n_across}")
    case_runs.report("within bodies", problems)


if __name__ == "__main__":
    main()
