"""Checks of scripts/vpcontact_plot.py that need its internals; run by test_plot.sh.

  check_plot.py reader DIR...      every solution_*.vtu in DIR: rewritten raw and
                                   zlib-compressed (several blocks, a partial last
                                   one; UInt64 and UInt32 headers), read back: the
                                   same arrays as the original
  check_plot.py layout DIR         draws DIR's figures and checks, before saving, that
                                   every colour bar lies within its plot's height and
                                   no legend overlaps a plot's data area or its x label
  check_plot.py texts DIR          draws DIR's figures and prints every text of each,
                                   one per line: FIGURE<TAB>KIND<TAB>TEXT (KIND: title,
                                   suptitle, xlabel, ylabel, zlabel, legend, colorbar)
  check_plot.py drawn DIR          draws DIR's figures and prints what some of them draw, one
                                   per line: FIGURE<TAB>WHAT<TAB>VALUE:
                                   deformed_mesh / von_mises_beta  scale  s, the least-squares
                                     fit of the drawn nodes y = x + s u (1: true scale)
                                   contact_pressure  nodes  the nodes of the pressure map's
                                     triangles (VTU point indices, comma-separated)
                                   friction  x  the x data of its first panel's curves, each
                                     curve's comma-separated, curves separated by ';'
"""

import glob
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
import vtu_tools  # noqa: E402
vp = vtu_tools.vp


def fail(msg):
    print("check_plot: FAIL: " + msg, file=sys.stderr)
    sys.exit(1)


def same(a, b, what):
    import numpy as np

    if set(a.point_data) != set(b.point_data) or set(a.cell_data) != set(b.cell_data):
        fail("%s: fields differ: %s / %s" % (what, sorted(a.point_data), sorted(b.point_data)))
    pairs = [("points", a.points, b.points), ("cells", a.cells, b.cells)]
    pairs += [(k, a.point_data[k], b.point_data[k]) for k in a.point_data]
    pairs += [(k, a.cell_data[k], b.cell_data[k]) for k in a.cell_data]
    for name, x, y in pairs:
        if x.shape != y.shape or x.dtype != y.dtype or not np.array_equal(x, y):
            fail("%s: array '%s' differs (%s %s / %s %s)" % (what, name, x.shape, x.dtype, y.shape, y.dtype))
    if a.cell_type != b.cell_type:
        fail("%s: cell type differs" % what)


def reader(dirs):
    n = 0
    for d in dirs:
        files = sorted(glob.glob(os.path.join(d, "solution_*.vtu")))
        if not files:
            fail("no solution_*.vtu in %s" % d)
        for f in files:
            ref = vp.read_vtu(f)
            tmp = f + ".check.vtu"
            for compress, block, header in ((False, 0, "<u8"), (True, 1000, "<u8"), (True, 1 << 20, "<u4"),
                                            (True, 4096, "<u4")):
                vtu_tools.write_vtu(tmp, ref, compress=compress, block_bytes=block or 32768, header=header)
                with open(tmp, "rb") as fh:
                    head = fh.read(400)
                if compress != (b'compressor="vtkZLibDataCompressor"' in head):
                    fail("%s: the helper did not write the layout asked for" % tmp)
                same(ref, vp.read_vtu(tmp), "%s (compressed=%s, block=%d, header=%s)" % (f, compress, block, header))
                n += 1
            # A corrupt compressed file: a clear PlotError, not a crash.
            vtu_tools.write_vtu(tmp, ref, compress=True, block_bytes=1000)
            raw = bytearray(open(tmp, "rb").read())
            raw[-200] ^= 0xFF
            open(tmp, "wb").write(bytes(raw))
            try:
                vp.read_vtu(tmp)
            except vp.PlotError:
                pass
            else:
                fail("%s: a corrupted compressed block was read without an error" % tmp)
            os.remove(tmp)
    print("check_plot: reader: %d rewritten files read back identical" % n)


def layout(outdir):
    run = vp.Run(outdir)
    checked = []

    class Checking(vp.Plotter):
        def save(self, fig, key):
            fig.canvas.draw()
            r = fig.canvas.get_renderer()
            for ax in fig.axes:
                for cax in getattr(ax, "child_axes", []):
                    a, c = ax.get_window_extent(r), cax.get_window_extent(r)
                    tol = 1.0  # pixel
                    if c.y0 < a.y0 - tol or c.y1 > a.y1 + tol:
                        fail("%s: colour bar spans y %.0f..%.0f px, its plot %.0f..%.0f px"
                             % (self.name(key), c.y0, c.y1, a.y0, a.y1))
                    if c.height < 0.9 * a.height:
                        fail("%s: colour bar %.0f px tall for a plot %.0f px tall"
                             % (self.name(key), c.height, a.height))
                    checked.append((self.name(key), "colour bar", round(c.height), round(a.height)))
                leg = ax.get_legend()
                if leg is not None and key in ("deformed_mesh", "contact_pressure"):
                    lb, ab = leg.get_window_extent(r), ax.get_window_extent(r)
                    xl = ax.xaxis.label.get_window_extent(r)
                    if lb.overlaps(ab) or lb.overlaps(xl):
                        fail("%s: the legend overlaps the plot or its x label" % self.name(key))
                    checked.append((self.name(key), "legend outside", 0, 0))
            vp.Plotter.save(self, fig, key)

    Checking(run, "png", 100).all()
    if not any(c[1] == "colour bar" for c in checked):
        fail("%s: no colour bar was checked" % outdir)
    for c in checked:
        print("check_plot: layout: %s: %s %s" % (c[0], c[1], "%d px in %d px" % (c[2], c[3]) if c[2] else ""))


def texts(outdir):
    run = vp.Run(outdir)
    lines = []

    class Listing(vp.Plotter):
        def save(self, fig, key):
            name = self.name(key)
            if fig._suptitle is not None:
                lines.append((name, "suptitle", fig._suptitle.get_text()))
            for ax in fig.axes:
                for kind, text in (("title", ax.get_title()), ("xlabel", ax.get_xlabel()), ("ylabel", ax.get_ylabel()),
                                   ("zlabel", ax.get_zlabel() if hasattr(ax, "get_zlabel") else "")):
                    if text:
                        lines.append((name, kind, text))
                leg = ax.get_legend()
                if leg is not None:
                    lines.extend((name, "legend", t.get_text()) for t in leg.get_texts())
                lines.extend((name, "colorbar", c.get_ylabel()) for c in getattr(ax, "child_axes", []) if c.get_ylabel())
            vp.Plotter.save(self, fig, key)

    Listing(run, "png", 60).all()
    for name, kind, text in lines:
        print("%s\t%s\t%s" % (name, kind, text.replace("\n", " ")))


def drawn(outdir):
    import numpy as np

    run = vp.Run(outdir)
    lines = []

    class Recording(vp.Plotter):
        def deformed_2d(self, vtu):
            tri, s, umax, xy = vp.Plotter.deformed_2d(self, vtu)
            self.last_deformed = (np.column_stack([tri.x, tri.y]), xy, vtu.displacement()[:, :2])
            return tri, s, umax, xy

        def save(self, fig, key):
            name = self.name(key)
            if key in ("deformed_mesh", "von_mises_beta"):
                y, x, u = self.last_deformed
                lines.append((name, "scale", "%.6g" % (float(((y - x) * u).sum()) / float((u * u).sum()))))
            elif key == "contact_pressure":
                tris = [c._triangulation for c in fig.axes[0].collections if hasattr(c, "_triangulation")]
                nodes = np.unique(np.concatenate([t.triangles.ravel() for t in tris]))
                lines.append((name, "nodes", ",".join(str(int(n)) for n in nodes)))
            elif key == "friction":
                xs = [l.get_xdata() for l in fig.axes[0].get_lines() if not l.get_label().startswith("_")]
                lines.append((name, "x", ";".join(",".join("%.17g" % v for v in x) for x in xs)))
            vp.Plotter.save(self, fig, key)

    Recording(run, "png", 60).all()
    for name, what, value in lines:
        print("%s\t%s\t%s" % (name, what, value))


if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] not in ("reader", "layout", "texts", "drawn"):
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    if sys.argv[1] == "reader":
        reader(sys.argv[2:])
    elif sys.argv[1] == "texts":
        texts(sys.argv[2])
    elif sys.argv[1] == "drawn":
        drawn(sys.argv[2])
    else:
        layout(sys.argv[2])
