#!/usr/bin/env python3
"""Error-controlled steps against a fine fixed grid (issue 26, docs/verification.md §4b).

For each grid (N=STEPS fixed, or a tolerance), runs CASE through the Python module and prints a
markdown row: steps (+ rejected), the sum of the error estimates over the run, the errors at T of
the contact force (relative), min beta (absolute), u and sigma (L2 over the nodes / cells, relative
to the reference's largest norm over t = 0.1, ..., 1), and the largest of these over t = 0.1, ..., 1
(error-controlled runs end steps there: time.breakpoints).

  PYTHONPATH=build/python python3 scripts/error_control_table.py CASE "{SETS}" N_REF N=50 1e-2 1e-3
"""
import ast
import sys
import time

import numpy as np
import vpcontact

TIMES = [round(0.1 * i, 12) for i in range(1, 11)]


def run(case, sets):
    c = vpcontact.Case(case)
    c.set(sets)
    sim = vpcontact.Simulation(c)
    out, n, rejected, estimate, t0 = {}, 0, 0, 0.0, time.time()
    while not sim.done:
        sim.step()
        r = sim.report
        n += 1
        rejected += r["rejected"]
        estimate += r["error_estimate"]
        for t in TIMES:
            if abs(sim.t - t) < 1e-9:
                out[t] = dict(F=r["total_contact_force"], b=r["beta_min"], u=np.array(sim.u), s=np.array(sim.sigma))
    return out, n, rejected, estimate, time.time() - t0


def errors(a, r, s_max, u_max):
    return dict(F=abs(a["F"] - r["F"]) / max(abs(r["F"]), 1e-300), b=abs(a["b"] - r["b"]),
                u=np.linalg.norm(a["u"] - r["u"]) / u_max, s=np.linalg.norm(a["s"] - r["s"]) / s_max)


def main():
    case, sets, n_ref = sys.argv[1], ast.literal_eval(sys.argv[2]), int(sys.argv[3])
    ref, *_ = run(case, {**sets, "time.steps": n_ref})
    s_max = max(np.linalg.norm(ref[t]["s"]) for t in TIMES) or 1.0
    u_max = max(np.linalg.norm(ref[t]["u"]) for t in TIMES) or 1.0
    print(f"{case} {sets}: reference N = {n_ref}; at T: F = {ref[1.0]['F']:.6g}, min beta = {ref[1.0]['b']:.6g}")
    print("| grid | steps (+rejected) | sum of estimates | F at T | min beta at T | u at T | sigma at T | largest over t | s |")
    for spec in sys.argv[4:]:
        fixed = spec.startswith("N=")
        grid = {"time.steps": int(spec[2:])} if fixed else \
            {"time.tolerance": float(spec), "time.breakpoints": [0.1 * i for i in range(1, 10)]}
        a, n, rejected, estimate, seconds = run(case, {**sets, **grid})
        at_T = errors(a[1.0], ref[1.0], s_max, u_max)
        largest = max(max(errors(a[t], ref[t], s_max, u_max).values()) for t in TIMES)
        print(f"| {spec} | {n} (+{rejected}) | {estimate:.2e} | " + " | ".join(f"{at_T[k]:.1e}" for k in "Fbus") +
              f" | {largest:.1e} | {seconds:.1f} |", flush=True)


if __name__ == "__main__":
    main()
