#!/usr/bin/env python3
"""The peel's h and k table (docs/verification.md §8i): peel-2d at three meshes (h halved) with the
steps halved alongside (k = h-proportional, the scheme being O(h + k)), and its force on the lifted
end and the debonding front (where alpha crosses 1/2 along the bottom) at fixed openings, each with
the Richardson extrapolation of its last three levels and the observed order.

    PYTHONPATH=build/python /usr/bin/python3 bench/peel_convergence.py [--levels 4]
"""
import argparse
import math

import numpy as np
import vpcontact


def front(sim):
    """x where the bonding along the bottom first reaches 1/2 (linear between nodes; -inf: none below)."""
    alpha = np.asarray(sim.surface["bonding"])
    x = np.asarray(sim.points)[np.asarray(sim.contact_nodes), 0]
    order = np.argsort(x)
    x, alpha = x[order], alpha[order]
    for i in range(1, len(x)):
        if alpha[i - 1] < 0.5 <= alpha[i]:
            return x[i - 1] + (0.5 - alpha[i - 1]) * (x[i] - x[i - 1]) / (alpha[i] - alpha[i - 1])
    return x[0] if alpha[0] >= 0.5 else float("nan")


def run(level, times):
    case = vpcontact.Case("peel-2d")
    case.set({"mesh.cells": [40 * 2 ** level, 2 * 2 ** level], "time.steps": 50 * 2 ** level})
    sim = vpcontact.Simulation(case)
    out = {}
    while not sim.done:
        sim.step()
        for t in times:
            if abs(sim.t - t) < 1e-9:
                out[t] = (float(sim.report["reaction_left_y"]), front(sim))
    return out, len(np.asarray(sim.contact_nodes))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--levels", type=int, default=4)
    args = ap.parse_args()
    times = [0.5, 1.0]
    rows = [run(level, times) for level in range(args.levels)]
    for t in times:
        for k, name in ((0, "force on the lifted end"), (1, "front x (alpha = 1/2)")):
            values = [r[0][t][k] for r in rows]
            print("t = %g, %s:" % (t, name))
            for level, v in enumerate(values):
                print("  cells %4d x %2d, %4d steps: %.8g" % (40 * 2 ** level, 2 * 2 ** level, 50 * 2 ** level, v))
            a, b, c = values[-3:]
            if (b - a) * (c - b) > 0:
                p = math.log(abs((b - a) / (c - b)), 2)
                ext = c + (c - b) / (2 ** p - 1)
                print("  order %.2f, extrapolated %.8g; errors %s" % (p, ext, ", ".join("%.3g" % abs(v - ext) for v in values)))
            else:
                print("  not monotone: no extrapolation")


if __name__ == "__main__":
    main()
