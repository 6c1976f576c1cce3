#!/usr/bin/python3
"""Log-log plots of a `vpcontact converge` output directory.

Usage: /usr/bin/python3 scripts/vpcontact_converge_plot.py DIR [-q] [--dpi 150]

For every DIR/convergence_SEQ.csv (SEQ = hk, h, k) writes DIR/convergence_SEQ.png:
left, the errors of each level (max over n of the energy norm of u, the L2 norms
of u, sigma and beta, and (k sum_n |grad e_beta|^2)^1/2) against h (against k for
the k sequence), with reference slopes 1/2, 1 and 2; right, the differences of
consecutive levels, whose slopes are free of the bias of a reference only one
level finer. For DIR/solvers.csv writes DIR/solvers.png: iterations per step of
the active-set and penalty-duality solvers against the number of unknowns.

Only numpy and matplotlib (Agg backend) are needed. Prints the path of every
figure written; exits 1 with a one-line message if DIR holds no CSV of vpcontact
converge.
"""

import argparse
import csv
import math
import os
import sys

NORMS = [
    ("u_energy", r"$\max_n |u_n - u_n^*|_E$", "o"),
    ("u_l2", r"$\max_n |u_n - u_n^*|_{L^2}$", "s"),
    ("sigma_l2", r"$\max_n |\sigma_n - \sigma_n^*|_{L^2}$", "^"),
    ("beta_l2", r"$\max_n |\beta_n - \beta_n^*|_{L^2}$", "D"),
    ("beta_grad", r"$(k\sum_n |\nabla(\beta_n - \beta_n^*)|^2_{L^2})^{1/2}$", "v"),
]
SEQUENCE_TITLES = {
    "hk": "h and k halved together",
    "h": "h halved, k fixed",
    "k": "k halved, h fixed",
}


def read_csv(path):
    """Rows of a CSV written by vpcontact converge (lines starting with # are comments)."""
    comments = []
    lines = []
    with open(path, newline="") as f:
        for line in f:
            if line.startswith("#"):
                comments.append(line[1:].strip())
            elif line.strip():
                lines.append(line)
    rows = list(csv.DictReader(lines))
    meta = {}
    for c in comments:
        for item in c.split():
            if "=" in item:
                key, value = item.split("=", 1)
                meta[key] = value
    return meta, rows


def number(s):
    try:
        v = float(s)
    except (TypeError, ValueError):
        return math.nan
    return v


def slope_guides(ax, x, ys, slopes):
    """Dashed reference lines of the given slopes through the middle of the data."""
    import numpy as np

    finite = [y for y in ys if np.all(np.isfinite(y)) and np.all(y > 0)]
    if not finite or len(x) < 2:
        return
    lo = min(np.min(y) for y in finite)
    hi = max(np.max(y) for y in finite)
    x0, x1 = x[0], x[-1]
    anchors = np.geomspace(hi, lo, len(slopes) + 2)[1:-1]
    for s, y0 in zip(slopes, anchors):
        # line through (x0, y0) with slope s in log-log coordinates
        ax.plot([x0, x1], [y0, y0 * (x1 / x0) ** s], color="0.55", linestyle="--", linewidth=0.9)
        ax.annotate(
            "slope {}".format(s),
            xy=(x1, y0 * (x1 / x0) ** s),
            xytext=(3, 0),
            textcoords="offset points",
            fontsize=8,
            color="0.35",
            va="center",
        )


def plot_convergence(path, dpi):
    import numpy as np
    import matplotlib.pyplot as plt

    meta, rows = read_csv(path)
    levels = [r for r in rows if r["level"] != "ref"]
    if len(levels) < 2:
        raise ValueError("fewer than two levels in {}".format(path))
    seq = meta.get("sequence", "hk")
    by_k = seq == "k"
    x = np.array([number(r["k" if by_k else "h"]) for r in levels])
    against = meta.get("against", "")
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 6.4))
    panels = [
        ("err", "errors against " + ("the exact solution" if against == "exact" else "the reference")),
        ("diff", "differences of consecutive levels $|w_l - w_{l+1}|$"),
    ]
    for ax, (prefix, title) in zip(axes, panels):
        ys = []
        series = {key: np.array([number(r["{}_{}".format(prefix, key)]) for r in levels]) for key, _, _ in NORMS}
        largest = max([np.nanmax(y) for y in series.values() if np.any(np.isfinite(y))] + [0.0])
        at_roundoff = []
        for index, (key, label, marker) in enumerate(NORMS):
            y = series[key]
            ok = np.isfinite(y) & (y > 0)
            if ok.sum() < 2:
                continue
            if np.nanmax(y) < 1e-9 * largest:
                # identically zero up to round-off (e.g. sigma in 1D, which statics alone fixes)
                at_roundoff.append(label)
                continue
            rate_key = ("diff_rate_" if prefix == "diff" else "rate_") + key
            rates = [number(r[rate_key]) for r in levels]
            last = [v for v, good in zip(rates, ok) if good and math.isfinite(v)]
            suffix = "  (last rate {:.2f})".format(last[-1]) if last else ""
            ax.loglog(x[ok], y[ok], marker=marker, color="C{}".format(index), label=label + suffix)
            ys.append(y[ok])
        slope_guides(ax, x, ys, [0.5, 1, 2])
        if at_roundoff:
            ax.text(0.02, 0.02, "at round-off, not shown: " + ", ".join(at_roundoff), transform=ax.transAxes,
                    fontsize=7.5, color="0.35")
        ax.set_xlabel("time step k" if by_k else "mesh size h (largest cell diameter)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", linewidth=0.3)
        ax.set_xticks(x)
        ax.set_xticklabels(["{:.3g}".format(v) for v in x], fontsize=8)
        ax.minorticks_off()
        ax.invert_xaxis()
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    case = meta.get("case", "")
    fig.suptitle("{}: {}".format(case, SEQUENCE_TITLES.get(seq, seq)), fontsize=12)
    fig.tight_layout()
    out = os.path.splitext(path)[0] + ".png"
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out


def plot_solvers(path, dpi):
    import numpy as np
    import matplotlib.pyplot as plt

    _, rows = read_csv(path)
    if not rows:
        raise ValueError("no rows in {}".format(path))
    dofs = np.array([number(r["n_free_dofs"]) for r in rows])
    nodes = np.array([number(r["n_nodes"]) for r in rows])
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 4.8))
    for ax, (name, x, xlabel) in zip(
        axes,
        [("contact", dofs, "free displacement unknowns"), ("damage", nodes, "damage unknowns (nodes)")],
    ):
        for solver, style, color in [("as", "o-", "C0"), ("pd", "s--", "C2")]:
            mean = np.array([number(r["{}_{}_mean".format(name, solver)]) for r in rows])
            mx = np.array([number(r["{}_{}_max".format(name, solver)]) for r in rows])
            label = "active set" if solver == "as" else "penalty-duality"
            ax.loglog(x, np.maximum(mean, 1e-1), style, color=color, label=label + " (mean per step)")
            ax.loglog(x, np.maximum(mx, 1e-1), style, color=color, alpha=0.35, label=label + " (max per step)")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("iterations per step")
        ax.set_title("{} inequality {}".format(name, "(3.9)" if name == "contact" else "(3.8)"), fontsize=10)
        ax.grid(True, which="both", linewidth=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("solver iterations versus mesh size", fontsize=12)
    fig.tight_layout()
    out = os.path.join(os.path.dirname(path), "solvers.png")
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir")
    parser.add_argument("-q", "--quiet", action="store_true")
    parser.add_argument("--dpi", type=int, default=150)
    args = parser.parse_args(argv)
    if not os.path.isdir(args.dir):
        print("vpcontact_converge_plot: '{}' is not a directory".format(args.dir), file=sys.stderr)
        return 1
    try:
        import matplotlib

        matplotlib.use("Agg")
    except ImportError:
        print("vpcontact_converge_plot: matplotlib is missing (install python3-matplotlib)", file=sys.stderr)
        return 1
    jobs = []
    for seq in ("hk", "h", "k"):
        p = os.path.join(args.dir, "convergence_{}.csv".format(seq))
        if os.path.isfile(p):
            jobs.append((plot_convergence, p))
    p = os.path.join(args.dir, "solvers.csv")
    if os.path.isfile(p):
        jobs.append((plot_solvers, p))
    if not jobs:
        print("vpcontact_converge_plot: no convergence_*.csv or solvers.csv in '{}'".format(args.dir), file=sys.stderr)
        return 1
    for fn, p in jobs:
        out = fn(p, args.dpi)
        if not args.quiet:
            print("  wrote {}".format(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
