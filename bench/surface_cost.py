#!/usr/bin/env python3
"""What a contact law's surface history costs (issue 50): a case run with its wear (or, later, its
adhesion) and again with the coefficient 0 on the same contact set and solver path, alternately,
`--repeats` times each; prints per-step time of the contact phase and of the whole step, contact
iterations and active-set sizes, and the ratio with/without (medians). Table in docs/performance.md.

    /usr/bin/python3 bench/surface_cost.py --vpcontact build/app/vpcontact --case wear-ironing-3d \\
        --set "mesh.cells=[70, 35, 17]" --steps 10 --off contact.wear_coefficient=0 --repeats 3
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile


def one_run(vpcontact, case, sets, steps):
    with tempfile.TemporaryDirectory() as out:
        cmd = [vpcontact, "run", case, "--steps", str(steps), "--no-vtu", "-q", "-o", out, "--checkpoint-every", "0"]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        with open(os.path.join(out, "history.csv")) as f:
            rows = list(csv.DictReader(f))
    steps_done = len(rows)
    timing = summary["timing_seconds"]
    step_time = sum(timing[k] for k in ("sources", "damage", "contact", "stress"))
    return {
        "unknowns": summary["unknowns"]["displacement_free"],
        "contact_nodes": summary["unknowns"]["contact_nodes"],
        "contact_per_step": timing["contact"] / steps_done,
        "step": step_time / steps_done,
        "iterations": sum(int(r["contact_iterations"]) for r in rows) / steps_done,
        "active": max(int(r["n_active"]) for r in rows),
        "active_mean": sum(int(r["n_active"]) for r in rows) / steps_done,
        "worn_volume": float(rows[-1].get("worn_volume", "nan")),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vpcontact", default="build/app/vpcontact")
    ap.add_argument("--case", default="wear-ironing-3d")
    ap.add_argument("--set", action="append", default=[], help="--set for both runs")
    ap.add_argument("--off", action="append", default=None,
                    help="--set that turns the history's effect off (default contact.wear_coefficient=0: the "
                         "coefficient 0, the same solver path)")
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    a.off = a.off or ["contact.wear_coefficient=0"]
    runs = {"on": [], "off": []}
    for _ in range(a.repeats):  # alternately: a busy spell of the machine hits both
        runs["on"].append(one_run(a.vpcontact, a.case, a.set, a.steps))
        runs["off"].append(one_run(a.vpcontact, a.case, a.set + a.off, a.steps))
    med = {k: {q: statistics.median(r[q] for r in v) for q in v[0]} for k, v in runs.items()}
    on, off = med["on"], med["off"]
    print(f"{a.case} {' '.join(a.set)}: {on['unknowns']} unknowns, {on['contact_nodes']} contact nodes, {a.steps} steps, "
          f"medians of {a.repeats}")
    print("| run | contact phase per step | whole step | contact iterations per step | active nodes (largest, mean) | worn volume |")
    print("|---|---|---|---|---|---|")
    for k in ("on", "off"):
        m = med[k]
        print(f"| {'with' if k == 'on' else 'coefficient 0'} | {m['contact_per_step']:.3f} s | {m['step']:.3f} s | "
              f"{m['iterations']:.2f} | {m['active']:.0f}, {m['active_mean']:.1f} | {m['worn_volume']:.4g} |")
    print(f"ratio with/without: contact phase {on['contact_per_step'] / off['contact_per_step']:.3f}, whole step "
          f"{on['step'] / off['step']:.3f}, iterations {on['iterations'] / off['iterations']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
