#!/usr/bin/python3
"""Hertz sphere contact (3D, quarter model): measured P, a and p(r) of vpcontact runs against Hertz.

Usage:
  /usr/bin/python3 scripts/hertz_study.py OUTDIR [OUTDIR ...] [--ref P_REF] [--fit K]
                                          [--E 1000] [--nu 0.3] [--R 1] [--factor F] [--csv FILE]

OUTDIR is a vpcontact output directory of hertz-3d, hertz-3d-adapt or a uniform-box copy of it
(a rigid sphere of radius R pressed into the top z = 0 of the block, centred on the z axis). Per
directory it reads summary.json (free displacement dofs, wall time, symmetry planes), the last row
of history.csv (total_contact_force) and, if present, the last solution_NNNNN.vtu (point field
contact_pressure; read with scripts/vpcontact_plot.py's read_vtu), and prints one row:

  N        unknowns: summary.json "unknowns"/"displacement_free" (the set-up printout's
           "free displacement dofs"; history.csv's column `unknowns` when it has one)
  P        the whole sphere's force: F x the last total_contact_force, F = 2 per symmetry plane
           x = 0 or y = 0 in summary.json (4 for the quarter model; --factor overrides)
  e_P      |P - P_ref| / P_ref (with --ref); dP = P / P_ref - 1, its sign
  a        Hertz's contact radius from P: a = (3 P R / (4 E*))^(1/3), E* = E / (1 - nu^2)
  r_in     the largest r = sqrt(x^2 + y^2) of a top node (z = 0) with contact_pressure > 0
  r_out    the next node outward: the smallest r > r_in of a top node without pressure
  a_h      (r_in + r_out) / 2
  h_loc    the local mesh size there: the mean length of the top face's mesh edges that join a
           node with pressure to one without (the edges the contact boundary crosses)
  e_a      (a_h - a) / h_loc
  a_ax     the same midpoint along the two symmetry lines y = 0 and x = 0 of the top (the last
           node with pressure and the next node on the line; their mean), h_ax the mean spacing
           there, e_a_ax = (a_ax - a) / h_ax
  p0       Hertz's peak pressure 3 P / (2 pi a^2); e_p0 = p(r = 0) / p0 - 1 (the node on the axis)
  e_p      RMS over top nodes with r < 0.9 a of p / p0 - sqrt(1 - r^2 / a^2)
  wall     summary.json's wall seconds (output = the part spent writing VTU and checkpoints)

--fit K fits e_P = C N^(-r) (least squares in log-log) to the last K directories given (in the
order given; needs --ref), prints C, r, the residuals, and the N the fit needs for e_P = 0.5 %,
0.25 % and 0.1 %; it also prints the Richardson extrapolation of the last three P in
h ~ N^(-1/3): P = P_inf + C' h^q through the three points (q from the ratio of the differences).

Example (a uniform sequence against a reference):
  /usr/bin/python3 scripts/hertz_study.py /tmp/hs/u40 /tmp/hs/u56 /tmp/hs/u80 --ref 1.5641 --fit 3
Only numpy is needed. Exits 1 with a one-line message if a directory cannot be read.
"""

import argparse
import csv
import glob
import json
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vpcontact_plot as vp  # noqa: E402  (read_vtu)

TOP_TOL = 1e-9  # |z| below this: a node of the top face z = 0


class StudyError(Exception):
    pass


def last_vtu(outdir):
    """The final state's VTU: the solution_NNNNN.vtu with the largest NNNNN, or None."""
    files = glob.glob(os.path.join(outdir, "solution_*.vtu"))
    numbered = [(int(m.group(1)), f) for f in files for m in [re.search(r"solution_(\d+)\.vtu$", f)] if m]
    return max(numbered)[1] if numbered else None


def read_history_last(outdir):
    """history.csv's last row (column name -> number), read by vpcontact_plot.read_csv."""
    path = os.path.join(outdir, "history.csv")
    try:
        columns = vp.read_csv(path)
    except vp.PlotError as e:
        raise StudyError(str(e))
    if not columns or not len(next(iter(columns.values()))):
        raise StudyError("%s has no rows" % path)
    return {name: values[-1] for name, values in columns.items()}


def symmetry_factor(summary):
    """2 per symmetry plane x = 0 or y = 0 (the planes through the sphere's axis)."""
    f = 1
    for plane in summary.get("symmetry_planes", []):
        if plane.get("axis") in ("x", "y") and abs(float(plane.get("coordinate", 1.0))) < 1e-12:
            f *= 2
    return f


def hertz_a(P, R, Estar):
    return (3.0 * P * R / (4.0 * Estar)) ** (1.0 / 3.0)


def top_edges(cells, top):
    """Unique mesh edges with both nodes on the top face, as an (m, 2) array."""
    cells = cells[top[cells].sum(axis=1) >= 2]
    k = cells.shape[1]
    pairs = [(i, j) for i in range(k) for j in range(i + 1, k)]
    e = np.concatenate([cells[:, [i, j]] for i, j in pairs])
    e = e[top[e[:, 0]] & top[e[:, 1]]]
    e.sort(axis=1)
    return np.unique(e, axis=0)


def axis_midpoint(x, p, on_line):
    """Along one symmetry line: (last node with pressure, next node, midpoint, spacing) or None."""
    idx = np.flatnonzero(on_line)
    idx = idx[np.argsort(x[idx])]
    active = p[idx] > 0
    if not active.any():
        return None
    last = np.flatnonzero(active)[-1]
    if last + 1 >= idx.size:
        return None
    r_in, r_out = x[idx[last]], x[idx[last + 1]]
    return r_in, r_out, 0.5 * (r_in + r_out), r_out - r_in


def measure(outdir, E, nu, R, factor=None):
    path = os.path.join(outdir, "summary.json")
    try:
        with open(path) as f:
            summary = json.load(f)
    except (OSError, ValueError) as e:
        raise StudyError("cannot read %s: %s" % (path, e))
    last = read_history_last(outdir)
    row = {"dir": outdir, "case": summary.get("case", "?")}
    if "unknowns" in last:
        row["N"] = int(float(last["unknowns"]))
    else:
        row["N"] = int(summary["unknowns"]["displacement_free"])
    timing = summary.get("timing_seconds", {})
    row["wall"] = timing.get("wall", float("nan"))
    row["wall_output"] = timing.get("output", float("nan"))
    f = factor if factor is not None else symmetry_factor(summary)
    row["factor"] = f
    P = f * float(last["total_contact_force"])
    Estar = E / (1.0 - nu * nu)
    a = hertz_a(P, R, Estar)
    p0 = 3.0 * P / (2.0 * math.pi * a * a)
    row.update(P=P, a=a, p0=p0)

    vtu = last_vtu(outdir)
    row["vtu"] = vtu
    if vtu is None:
        return row
    try:
        v = vp.read_vtu(vtu)
    except vp.PlotError as e:
        raise StudyError(str(e))
    if "contact_pressure" not in v.point_data:
        raise StudyError("%s has no point field contact_pressure" % vtu)
    xyz = v.points
    p = np.asarray(v.point_data["contact_pressure"], dtype=float)
    top = np.abs(xyz[:, 2]) < TOP_TOL
    r = np.hypot(xyz[:, 0], xyz[:, 1])
    act = top & (p > 0)
    row["n_active"] = int(act.sum())
    if not act.any():
        return row

    # contact radius: the largest active r and the next top node outward without pressure
    r_in = r[act].max()
    outside = top & ~(p > 0) & (r > r_in)
    r_out = r[outside].min() if outside.any() else float("nan")
    e = top_edges(v.cells, top)
    crossing = (p[e[:, 0]] > 0) != (p[e[:, 1]] > 0)
    lengths = np.linalg.norm(xyz[e[crossing, 0]] - xyz[e[crossing, 1]], axis=1)
    h_loc = lengths.mean() if lengths.size else float("nan")
    a_h = 0.5 * (r_in + r_out)
    row.update(r_in=r_in, r_out=r_out, a_h=a_h, h_loc=h_loc, e_a=(a_h - a) / h_loc)

    # the same along the symmetry lines y = 0 (x axis) and x = 0 (y axis) of the top
    ax = [axis_midpoint(xyz[:, 0], p, top & (np.abs(xyz[:, 1]) < TOP_TOL)),
          axis_midpoint(xyz[:, 1], p, top & (np.abs(xyz[:, 0]) < TOP_TOL))]
    ax = [t for t in ax if t is not None]
    if ax:
        a_ax = float(np.mean([t[2] for t in ax]))
        h_ax = float(np.mean([t[3] for t in ax]))
        row.update(a_ax=a_ax, h_ax=h_ax, e_a_ax=(a_ax - a) / h_ax)

    # pressure: the node on the axis, the largest, and the RMS of the profile's error
    centre = top & (r < TOP_TOL)
    if centre.any():
        row["e_p0"] = p[centre].max() / p0 - 1.0
    inner = top & (r < 0.9 * a)
    d = p[inner] / p0 - np.sqrt(1.0 - (r[inner] / a) ** 2)
    row["e_p"] = float(np.sqrt(np.mean(d * d)))
    row["n_inner"] = int(inner.sum())
    return row


COLUMNS = [  # key, header, format
    ("N", "N", "%d"), ("P", "P", "%.6f"), ("e_P", "e_P", "%.3f%%"), ("dP", "dP", "%+.3f%%"), ("a", "a(P)", "%.5f"),
    ("r_in", "r_in", "%.5f"), ("r_out", "r_out", "%.5f"), ("a_h", "a_h", "%.5f"),
    ("h_loc", "h_loc", "%.5f"), ("e_a", "e_a", "%+.3f"), ("a_ax", "a_ax", "%.5f"),
    ("h_ax", "h_ax", "%.5f"), ("e_a_ax", "e_a_ax", "%+.3f"), ("p0", "p0", "%.3f"),
    ("e_p0", "e_p0", "%+.2f%%"), ("e_p", "e_p", "%.2f%%"), ("n_active", "active", "%d"),
    ("wall", "wall", "%.1f"), ("wall_output", "(output)", "%.1f"),
]
PERCENT = {"e_P", "dP", "e_p0", "e_p"}


def fmt(row, key, f):
    if key not in row or row[key] is None or (isinstance(row[key], float) and math.isnan(row[key])):
        return "-"
    v = row[key] * 100.0 if key in PERCENT else row[key]
    return f % v


def power_fit(N, e):
    """Least squares of log e = log C - r log N: (C, r, relative residuals e_fit/e - 1)."""
    A = np.vstack([np.ones(len(N)), -np.log(N)]).T
    (logC, rate), *_ = np.linalg.lstsq(A, np.log(e), rcond=None)
    C = math.exp(logC)
    fitted = C * np.asarray(N, dtype=float) ** (-rate)
    return C, rate, fitted / np.asarray(e) - 1.0


def richardson3(h, P):
    """P = P_inf + C h^q through three (h, P): (P_inf, C, q), or None if the differences change sign."""
    h = np.asarray(h, dtype=float)
    P = np.asarray(P, dtype=float)
    d1, d2 = P[0] - P[1], P[1] - P[2]
    if d1 * d2 <= 0:
        return None
    ratio = d1 / d2

    def g(q):
        return (h[0] ** q - h[1] ** q) / (h[1] ** q - h[2] ** q) - ratio

    lo, hi = 1e-3, 20.0
    if g(lo) * g(hi) > 0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(lo) * g(mid) <= 0:
            hi = mid
        else:
            lo = mid
    q = 0.5 * (lo + hi)
    C = d2 / (h[1] ** q - h[2] ** q)
    return P[2] - C * h[2] ** q, C, q


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdirs", nargs="+", metavar="OUTDIR")
    ap.add_argument("--ref", type=float, help="reference P for e_P")
    ap.add_argument("--fit", type=int, default=0, metavar="K",
                    help="fit e_P = C N^(-r) to the last K directories (needs --ref) and Richardson-extrapolate the last three P")
    ap.add_argument("--E", type=float, default=1000.0)
    ap.add_argument("--nu", type=float, default=0.3)
    ap.add_argument("--R", type=float, default=1.0)
    ap.add_argument("--factor", type=float, help="P = factor x the total contact force (default: 2 per symmetry plane x = 0, y = 0)")
    ap.add_argument("--csv", help="also write the rows to this CSV file")
    args = ap.parse_args(argv)

    rows = []
    try:
        for d in args.outdirs:
            rows.append(measure(d, args.E, args.nu, args.R, args.factor))
    except (StudyError, KeyError) as e:
        print("hertz_study: %s" % e, file=sys.stderr)
        return 1
    if args.ref:
        for row in rows:
            row["dP"] = row["P"] / args.ref - 1.0
            row["e_P"] = abs(row["dP"])

    print("Hertz: E* = %.6g, R = %g; P = %s x total_contact_force; e_P against %s"
          % (args.E / (1 - args.nu ** 2), args.R, "/".join(sorted({"%g" % r["factor"] for r in rows})),
             "P_ref = %.6f" % args.ref if args.ref else "(no --ref)"))
    print("\t".join(["dir"] + [h for _, h, _ in COLUMNS]))
    for row in rows:
        print("\t".join([os.path.basename(os.path.normpath(row["dir"]))] + [fmt(row, k, f) for k, _, f in COLUMNS]))

    if args.csv:
        keys = ["dir"] + [k for k, _, _ in COLUMNS]
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(keys)
            for row in rows:
                w.writerow([row.get(k, "") for k in keys])

    if args.fit:
        sel = rows[-args.fit:]
        N = np.array([r["N"] for r in sel], dtype=float)
        P = np.array([r["P"] for r in sel])
        if args.ref:
            e = np.array([r["e_P"] for r in sel])
            signs = {np.sign(r["dP"]) for r in sel}
            if np.any(e <= 0):
                print("fit: an e_P is zero; no power law")
            elif len(signs) > 1:
                print("fit: P - P_ref changes sign over these levels; no power law")
            else:
                C, rate, res = power_fit(N, e)
                print("fit e_P = C N^(-r) over N = %s: C = %.4g, r = %.4f (h-order %.3f)"
                      % (", ".join("%d" % n for n in N), C, rate, 3 * rate))
                print("  residuals (fit / measured - 1): %s" % ", ".join("%+.2f%%" % (100 * x) for x in res))
                for target in (0.005, 0.0025, 0.001):
                    print("  e_P = %.2f%%: N = %.3g" % (100 * target, (C / target) ** (1.0 / rate)))
        if len(sel) >= 3:
            rich = richardson3(N[-3:] ** (-1.0 / 3.0), P[-3:])
            if rich is None:
                print("Richardson (last three P, h ~ N^(-1/3)): the differences change sign; no extrapolation")
            else:
                Pinf, C2, q = rich
                print("Richardson (last three P, h ~ N^(-1/3)): P_inf = %.6f, order q = %.3f in h (r = %.3f in N), C = %.4g"
                      % (Pinf, q, q / 3, C2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
