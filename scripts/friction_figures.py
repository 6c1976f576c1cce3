#!/usr/bin/python3
"""Figures of issue 28's frictional cases (docs/verification.md), from a run's output directory:

  scripts/friction_figures.py cattaneo-mindlin OUTDIR FIGDIR   # vpcontact run cattaneo-mindlin-2d -o OUTDIR
  scripts/friction_figures.py cattaneo-mindlin-pair OUTDIR FIGDIR   # vpcontact run cattaneo-mindlin-pair-2d -o OUTDIR
  scripts/friction_figures.py ironing OUTDIR FIGDIR            # vpcontact run ironing-3d -o OUTDIR
  scripts/friction_figures.py punch OUTDIR FIGDIR              # vpcontact run punch-3d -o OUTDIR

cattaneo-mindlin: traction.png, the tangential traction q(x) = |lambda_tau|/|Gamma3|_i at every
tangential step against Cattaneo-Mindlin's mu p0 [sqrt(1 - x^2/a^2) - (c/a) sqrt(1 - x^2/c^2)], with
a, p0 from Hertz with the computed P and c/a = sqrt(1 - Q/(mu P)); stick_zone.png, c/a against
Q/(mu P); cattaneo-mindlin-pair the same between two bodies of one material (E* = E/(2(1 - nu^2)),
nu = 0.3; the nodes of y = 0 are the slave block's, a master node there is left out). ironing: tangential_force.png, the drag and normal forces (the bottom's reactions, which
balance the contact forces, and history.csv's tangential force) against t; beta_track.png, beta along the track's centre line at the
surface and below it at the end of the run. punch: the same for punch-3d (the pair's drag and normal force; beta in the block).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vpcontact_plot as vp  # noqa: E402  (the figures script's VTU and CSV readers)


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _solutions(outdir):
    return vp.list_solutions(outdir, vp.read_csv(os.path.join(outdir, "probes.csv")))


def contact_nodes(vtu):
    """x, lambda_nu, lambda_tau (first tangent), tributary measure of the nodes of y = 0."""
    lam = vtu.point_data["contact_lambda"].reshape(len(vtu.points), -1)
    p = vtu.point_data["contact_pressure"]
    on = np.abs(vtu.points[:, 1]) < 1e-12
    x, ln, lt, pr = vtu.points[on, 0], lam[on, 0], lam[on, 1], p[on]
    order = np.argsort(x)
    x, ln, lt, pr = x[order], ln[order], lt[order], pr[order]
    # A contact pair's master node at y = 0 (the disc's, under the slave block's node): no row of
    # its own, so no force; its twin on the slave side has them.
    keep = np.array([l != 0 or not np.any((x == xi) & (ln != 0)) for xi, l in zip(x, ln)], dtype=bool)
    x, ln, lt, pr = x[keep], ln[keep], lt[keep], pr[keep]
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(ln > 0, np.abs(lt) * pr / np.where(ln > 0, ln, 1), 0.0)
    return x, ln, lt, q


def cattaneo_mindlin(outdir, figdir, R=1.0, mu=0.5, E=1000.0, nu=0.49, bodies=1):
    """bodies: 1, an elastic body on a rigid cylinder; 2, two elastic bodies of one material."""
    plt = _pyplot()
    E_star = E / (bodies * (1 - nu * nu))
    sols = _solutions(outdir)
    a = p0 = P = None
    curves, zone = [], []
    for t, path in sols:
        vtu = vp.read_vtu(path)
        if "contact_lambda" not in vtu.point_data:
            continue
        x, ln, lt, q = contact_nodes(vtu)
        if t <= 1 + 1e-9:
            if ln.sum() <= 0:
                continue
            P = ln.sum()
            a = np.sqrt(4 * P * R / (np.pi * E_star))
            p0 = 2 * P / (np.pi * a)
            continue
        Q = abs(lt.sum())
        ratio = Q / (mu * ln.sum())
        c = a * np.sqrt(max(0.0, 1 - ratio))
        status = vtu.point_data.get("contact_status")
        if status is not None:  # the run's own stick/slip/free status (1: stick), at contact_nodes' nodes
            on = np.abs(vtu.points[:, 1]) < 1e-12
            xs_on, st_on = vtu.points[on, 0], status[on]
            stick = np.array([np.any((xs_on == xi) & (np.abs(st_on - 1) < 0.5)) for xi in x], dtype=bool)
        else:
            stick = (ln > 0) & (np.abs(lt) < mu * ln * (1 - 1e-9))
        c_num = 0.0
        if stick.any():  # the edges midway between the outermost sticking nodes and the next nodes out
            lo, hi = x[stick].min(), x[stick].max()
            left = 0.5 * (lo + (x[x < lo].max() if (x < lo).any() else lo))
            right = 0.5 * (hi + (x[x > hi].min() if (x > hi).any() else hi))
            c_num = 0.5 * (right - left) / a
        curves.append((t, ratio, c, x, q))
        zone.append((ratio, c / a, c_num))
    if a is None or not curves:
        raise SystemExit("%s: no frictional output at t <= 1 and after (run with every = 1)" % outdir)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    xs = np.linspace(-a, a, 400)
    for i, (t, ratio, c, x, q) in enumerate(curves):
        colour = plt.cm.viridis(i / max(1, len(curves) - 1))
        exact = np.sqrt(1 - xs**2 / a**2)
        if c > 0:
            exact -= np.where(np.abs(xs) < c, (c / a) * np.sqrt(np.clip(1 - xs**2 / c**2, 0, None)), 0)
        ax.plot(xs / a, exact, "-", color=colour, lw=1)
        inside = np.abs(x) <= 1.3 * a
        ax.plot(x[inside] / a, q[inside] / (mu * p0), "o", ms=3, color=colour, label="Q/(mu P) = %.2f" % ratio)
    ax.set_xlabel("x / a")
    ax.set_ylabel("q / (mu p0)")
    ax.set_title("Cattaneo-Mindlin: tangential traction (dots: vpcontact, lines: theory)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    os.makedirs(figdir, exist_ok=True)
    fig.savefig(os.path.join(figdir, "traction.png"), dpi=120)
    fig, ax = plt.subplots(figsize=(5, 4))
    r = np.linspace(0, 1, 200)
    ax.plot(r, np.sqrt(1 - r), "-", label="sqrt(1 - Q/(mu P))")
    z = np.array(zone)
    ax.plot(z[:, 0], z[:, 2], "o", label="vpcontact (stick nodes)")
    ax.set_xlabel("Q / (mu P)")
    ax.set_ylabel("c / a")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "stick_zone.png"), dpi=120)
    for ratio, theory, num in zone:
        print("Q/(mu P) = %.4f: c/a theory %.4f, computed %.4f" % (ratio, theory, num))


def drag_and_track(outdir, figdir, name, drag, normal, mu, y_track, z_top, track):
    """The drag and normal forces against t (history.csv columns `drag`, `normal`, in absolute value;
    the tangential force too where it is another column), and beta at the end along the line
    y = y_track at the surface z = z_top and the two node layers below it, over the points of the
    cells whose centroid lies below z_top (the damaged body, not one resting on it)."""
    plt = _pyplot()
    h = vp.read_csv(os.path.join(outdir, "history.csv"))
    t = h["t"]
    d, n = np.abs(h[drag]), np.abs(h[normal])
    fig, ax = plt.subplots(figsize=(6, 4))
    if drag != "tangential_force_x" and "tangential_force_x" in h:  # Σ λ_τ along the tangents
        ax.plot(t, np.abs(h["tangential_force_x"]), "s", ms=5, mfc="none", label="|tangential force x|")
    ax.plot(t, d, "-o", ms=3, label="drag |%s|" % drag)
    ax.plot(t, n, "-", label="normal |%s|" % normal)
    ax.plot(t, mu * n, "--", label="mu x normal")
    ax.set_xlabel("t")
    ax.set_ylabel("force")
    ax.set_title("%s: drag and normal force" % name)
    ax.legend(fontsize="small")
    fig.tight_layout()
    os.makedirs(figdir, exist_ok=True)
    fig.savefig(os.path.join(figdir, "tangential_force.png"), dpi=120)
    _, path = _solutions(outdir)[-1]
    vtu = vp.read_vtu(path)
    beta = vtu.point_data["beta"]
    pts = vtu.points
    cells = np.asarray(vtu.cells)
    inside = np.zeros(len(pts), dtype=bool)
    inside[np.unique(cells[pts[cells][:, :, 2].mean(axis=1) < z_top - 1e-9])] = True
    fig, ax = plt.subplots(figsize=(6, 4))
    for depth in sorted(set(np.round(z_top - pts[inside, 2], 9)))[:3]:
        line = inside & (np.abs(pts[:, 1] - y_track) < 1e-9) & (np.abs(z_top - pts[:, 2] - depth) < 1e-9)
        order = np.argsort(pts[line, 0])
        ax.plot(pts[line, 0][order], beta[line][order], "-o", ms=3, label="depth %.3g" % depth)
    ax.set_xlabel("x (%s)" % track)
    ax.set_ylabel("beta")
    ax.set_title("%s: beta along the track (y = %g) at T" % (name, y_track))
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "beta_track.png"), dpi=120)
    print("drag / normal at the end: %.4f; min beta %.4f" % (d[-1] / n[-1], beta[inside].min()))


def ironing(outdir, figdir):
    drag_and_track(outdir, figdir, "ironing-3d", "reaction_bottom_x", "reaction_bottom_z", 0.3, 0.0,
                   vp.read_vtu(_solutions(outdir)[-1][1]).points[:, 2].max(), "track: -0.5 to 0.5")


def punch(outdir, figdir):
    drag_and_track(outdir, figdir, "punch-3d", "tangential_force_pair_punch.bottom_x", "force_pair_punch.bottom", 0.3,
                   0.5, 0.5, "the punch's centre: 0.45 to 0.95")


def main(argv):
    figures = {
        "cattaneo-mindlin": cattaneo_mindlin,
        "cattaneo-mindlin-pair": lambda o, f: cattaneo_mindlin(o, f, nu=0.3, bodies=2),
        "ironing": ironing,
        "punch": punch,
    }
    if len(argv) != 4 or argv[1] not in figures:
        raise SystemExit(__doc__)
    figures[argv[1]](argv[2], argv[3])


if __name__ == "__main__":
    main(sys.argv)
