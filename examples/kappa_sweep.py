"""A sweep of the damage diffusion kappa on the paper's 2D example: min beta at the final
time against kappa, plotted into OUTDIR/kappa_sweep.png.

    PYTHONPATH=build/python /usr/bin/python3 examples/kappa_sweep.py [OUTDIR] [--files] [--n N --steps S]

--files writes each run's output (OUTDIR/kappa_K/), as `vpcontact run paper-2d --kappa K -o ...`
does; without it the runs write nothing and only their numbers are kept. --n and --steps make the
runs smaller (CI runs the example so).
"""
import argparse
import os
import time

import vpcontact

ap = argparse.ArgumentParser()
ap.add_argument("outdir", nargs="?", default="output/kappa-sweep")
ap.add_argument("--kappa", type=float, nargs="+", default=[0.01, 0.1, 1.0, 10.0, 100.0])
ap.add_argument("--files", action="store_true", help="write each run's files, as the command line does")
ap.add_argument("--n", type=int, help="cells per edge (default: the case's)")
ap.add_argument("--steps", type=int, help="time steps (default: the case's)")
args = ap.parse_args()
os.makedirs(args.outdir, exist_ok=True)

t0 = time.perf_counter()
beta_min = []
for kappa in args.kappa:
    case = vpcontact.Case("paper-2d", n=args.n, steps=args.steps, kappa=kappa)
    output = os.path.join(args.outdir, "kappa_%g" % kappa) if args.files else None
    sim = vpcontact.Simulation(case, output).run()
    beta_min.append(sim.report["beta_min"])
    print("kappa = %-8g min beta = %.6f" % (kappa, beta_min[-1]))
print("%d runs in %.3f s" % (len(args.kappa), time.perf_counter() - t0))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(5, 3.5))
ax.semilogx(args.kappa, beta_min, "o-")
ax.set_xlabel(r"damage diffusion $\kappa$")
ax.set_ylabel(r"min $\beta$ at $t = T$")
ax.set_title("paper-2d: damage against diffusion")
fig.tight_layout()
figure = os.path.join(args.outdir, "kappa_sweep.png")
fig.savefig(figure, dpi=120)
print(figure)
