#!/usr/bin/python3
"""Figures of issue 51's adaptive runs (docs/verification.md §8j), from a run's output directory:

  scripts/adapt_figures.py OUTDIR FIGDIR [XMIN XMAX YMIN YMAX]   # vpcontact run hertz-2d-adapt -o OUTDIR

meshes.png: the mesh of each VTU file of the run (solution.pvd's order) coloured by the cell field
`level` (bisections below the coarse cell), in the window given (default: the whole mesh); the
files' steps and cell counts in the titles. A 3D run's meshes are drawn by their top surface (the
faces on the largest z, seen from above, coloured by their cell's level), the window in x and y.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vpcontact_plot as vp  # noqa: E402  (the figures script's VTU reader)


def faces_seen(v):
    """The polygons to draw (xy) and their levels: a 2D mesh's cells, a 3D mesh's faces on its top z."""
    cells = np.asarray(v.cells)
    level = np.asarray(v.cell_data["level"])
    if cells.shape[1] == 3:
        return v.points[cells][:, :, :2], level
    z = v.points[:, 2]
    top = z.max()
    on_top = np.abs(z - top) <= 1e-9 * max(1.0, abs(top))
    polys, levels = [], []
    for cell, lev in zip(cells, level):
        face = [i for i in cell if on_top[i]]
        if len(face) == 3:
            polys.append(v.points[face][:, :2])
            levels.append(lev)
    return np.array(polys), np.array(levels)


def main(argv):
    if len(argv) not in (3, 7):
        sys.exit(__doc__)
    out, figs = argv[1], argv[2]
    window = [float(v) for v in argv[3:7]] if len(argv) == 7 else None
    with open(os.path.join(out, "solution.pvd")) as f:
        entries = re.findall(r'timestep="([^"]*)"[^>]*file="([^"]*)"', f.read())
    if not entries:
        sys.exit("adapt_figures.py: no VTU file in %s/solution.pvd" % out)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    n = len(entries)
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5 * cols, 3.2 * rows), squeeze=False)
    top = 0
    vtus = [vp.read_vtu(os.path.join(out, file)) for _, file in entries]
    for v in vtus:
        top = max(top, int(np.max(v.cell_data["level"])))
    for ax, (t, file), v in zip(axes.flat, entries, vtus):
        polys, level = faces_seen(v)
        pc = PolyCollection(polys, array=level, cmap="viridis", edgecolors="k", linewidths=0.15)
        pc.set_clim(0, max(top, 1))
        ax.add_collection(pc)
        if window:
            ax.set_xlim(window[0], window[1])
            ax.set_ylim(window[2], window[3])
        else:
            ax.autoscale_view()
        ax.set_aspect("equal")
        ax.set_title("t = %.3g: %d cells" % (float(t), len(v.cells)), fontsize=9)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.colorbar(pc, ax=axes, shrink=0.8, label="level (bisections below the coarse cell)")
    os.makedirs(figs, exist_ok=True)
    fig.savefig(os.path.join(figs, "meshes.png"), dpi=130)
    print(os.path.join(figs, "meshes.png"))


if __name__ == "__main__":
    main(sys.argv)
