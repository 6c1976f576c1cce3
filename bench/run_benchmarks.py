#!/usr/bin/env python3
"""Runs vpcontact-bench over sizes and repeats and prints the tables of
docs/performance.md (medians over repeats), plus a CSV of every run.

    /usr/bin/python3 bench/run_benchmarks.py --bench build/bench/vpcontact-bench \
        --case paper-2d --sizes 40,80,160,320,640 --repeats 3 --csv out.csv

Each run is a separate process, so its peak resident memory is its own. With
--cli build/app/vpcontact it also times whole `vpcontact run CASE --n N --no-vtu -q`
processes (start, case and mesh, setup, steps, CSV/summary/checkpoints, exit).
"""
import argparse
import csv
import json
import os
import statistics
import tempfile
import time
import subprocess
import sys


def run(bench, case, n, steps, extra):
    cmd = [bench, case, "--n", str(n), "--steps", str(steps)] + extra
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def run_cli(vpcontact, case, n, steps):
    """Wall time (s) and peak resident memory (bytes) of one whole `vpcontact run`."""
    with tempfile.TemporaryDirectory() as out:
        cmd = [vpcontact, "run", case, "--n", str(n), "--steps", str(steps), "--no-vtu", "-q", "-o", out]
        t0 = time.perf_counter()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.perf_counter() - t0
        if status != 0:
            sys.exit(f"{' '.join(cmd)} failed (status {status})")
        return {"wall": wall, "peak_rss_bytes": usage.ru_maxrss * 1024}


def med(rows, key):
    return statistics.median(r[key] for r in rows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench", default="build/bench/vpcontact-bench")
    ap.add_argument("--case", default="paper-2d")
    ap.add_argument("--sizes", default="40,80,160")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--vtu-every", type=int, default=0, help="also time runs writing VTU every m steps")
    ap.add_argument("--csv", default="")
    ap.add_argument("--cli", default="", help="path of vpcontact: also time whole `vpcontact run` processes")
    a = ap.parse_args()

    all_rows = []
    results = []
    for n in [int(s) for s in a.sizes.split(",")]:
        rows = [run(a.bench, a.case, n, a.steps, []) for _ in range(a.repeats)]
        vtu = [run(a.bench, a.case, n, a.steps, ["--vtu-every", str(a.vtu_every)]) for _ in range(a.repeats)] \
            if a.vtu_every > 0 else []
        cli = [run_cli(a.cli, a.case, n, a.steps) for _ in range(a.repeats)] if a.cli else []
        all_rows += rows + vtu
        results.append((n, rows, vtu, cli))
        print(f"# {a.case} n={n}: done", file=sys.stderr)

    ms = lambda x: f"{1e3 * x:.2f}"
    print(f"\n#### {a.case}: setup (seconds, median of {a.repeats})\n")
    print("| n | unknowns u / β | contact nodes | assembly | factor K | factor M+kκA | contact setup | setup total |")
    print("|---|---|---|---|---|---|---|---|")
    for n, rows, _, _ in results:
        r = rows[0]
        print(f"| {n} | {r['dofs']} / {r['damage_dofs']} | {r['contact_nodes']} | {med(rows, 'assembly'):.3f} | "
              f"{med(rows, 'factor_K'):.3f} | {med(rows, 'factor_H'):.3f} | {med(rows, 'contact_setup'):.3f} | "
              f"{med(rows, 'setup'):.3f} |")
    print(f"\n#### {a.case}: per step (milliseconds, median over steps, then over {a.repeats} runs)\n")
    print("| n | one solve with K's factor | step | step / solve | sources G, φ | damage | contact | stress | "
          "output | iterations (contact, damage) | steps total (s) | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n, rows, _, _ in results:
        solve, step = med(rows, "solve"), med(rows, "step_median")
        print(f"| {n} | {ms(solve)} | {ms(step)} | {step / solve:.2f} | {ms(med(rows, 'sources'))} | "
              f"{ms(med(rows, 'damage'))} | {ms(med(rows, 'contact'))} | {ms(med(rows, 'stress'))} | "
              f"{ms(med(rows, 'output'))} | {max(r['max_contact_iterations'] for r in rows)}, "
              f"{max(r['max_damage_iterations'] for r in rows)} | {med(rows, 'steps_total'):.3f} | "
              f"{med(rows, 'wall'):.3f} |")
    print(f"\n#### {a.case}: memory (MB)\n")
    print("| n | factors (K, M+kκA) | mesh + matrices + state | peak resident | peak / (factors + model) |")
    print("|---|---|---|---|---|")
    for n, rows, _, _ in results:
        f, m, p = med(rows, "factor_bytes"), med(rows, "model_bytes"), med(rows, "peak_rss_bytes")
        print(f"| {n} | {f / 1e6:.1f} | {m / 1e6:.1f} | {p / 1e6:.1f} | {p / (f + m):.2f} |")
    if a.vtu_every > 0:
        print(f"\n#### {a.case}: writing VTU every {a.vtu_every} step(s) (milliseconds per step, median)\n")
        print("| n | step without output | VTU output per step | output / step |")
        print("|---|---|---|---|")
        for n, rows, vtu, _ in results:
            step = med(rows, "step_median")
            out = med(vtu, "output")
            print(f"| {n} | {ms(step)} | {ms(out)} | {out / step:.2f} |")
    if a.cli:
        print(f"\n#### {a.case}: whole `vpcontact run {a.case} --n N --no-vtu -q` ({a.steps} steps, median of {a.repeats})\n")
        print("| n | wall (s) | peak resident (MB) | peak / (factors + model) |")
        print("|---|---|---|---|")
        for n, rows, _, cli in results:
            f, m = med(rows, "factor_bytes"), med(rows, "model_bytes")
            p = med(cli, "peak_rss_bytes")
            print(f"| {n} | {med(cli, 'wall'):.3f} | {p / 1e6:.1f} | {p / (f + m):.2f} |")
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(all_rows[0].keys()))
            w.writeheader()
            w.writerows(all_rows)


if __name__ == "__main__":
    main()
