#!/usr/bin/python3
"""The paper's figures from a vpcontact run's output directory.

Usage: /usr/bin/python3 scripts/vpcontact_plot.py OUTDIR [--format png] [--dpi 150]

Reads OUTDIR/summary.json (dimension, case, probe points), OUTDIR/probes.csv,
OUTDIR/history.csv and, when present, OUTDIR/solution.pvd with its
solution_NNNNN.vtu files, and writes figures into OUTDIR/figures/:

  d = 1  fig_4_2_displacement_stress   u(x), sigma(x) at t = 0.2, 0.4, 0.6, 0.8, 1 T  (VTU)
         fig_4_3_time_histories        u(t), sigma(t) at the probe points              (probes.csv)
         fig_4_4_damage                beta(x) at those times (VTU), beta(t) at the probes
  d = 2  fig_4_6_deformed_mesh         deformed mesh at the final time + initial boundary (VTU)
         fig_4_7_von_mises_damage      von Mises norm and damage on the deformed body     (VTU)
         probes                        u, von Mises, beta versus time at the probes       (probes.csv)
  d = 3  surface_von_mises, surface_damage   boundary of the deformed body, from above and below (VTU)
         contact_pressure              contact force on the bottom face z = zmin          (VTU)
         probes                        as for d = 2
  all    history                       total contact force, active nodes, min/max beta    (history.csv)

SPEC §4 (Fernandez & Sofonea 2003, Section 4) describes the figures. Only numpy
and matplotlib (Agg backend) are needed; the VTU reader below handles exactly
the layout src/io/vtu_writer.cpp writes: UnstructuredGrid, raw appended data
after a '_' marker, each block a UInt64 (or UInt32, per header_type) byte count
followed by little-endian values.

Prints the path of every figure written and, for every figure it cannot draw,
one line "skipped: NAME (why)". Exits 1 with a one-line message if OUTDIR is
not a readable vpcontact output directory.
"""

import argparse
import csv
import json
import os
import re
import sys
import xml.etree.ElementTree as ET

# Figure sizes in inches; the pixel size of a figure is round(size * dpi)
# (tests/plot/test_plot.sh checks it). Keep size * 150 integral.
FIGSIZES = {
    "fig_4_2_displacement_stress": (12.0, 4.8),
    "fig_4_3_time_histories": (12.0, 4.8),
    "fig_4_4_damage": (12.0, 4.8),
    "fig_4_6_deformed_mesh": (8.0, 7.2),
    "fig_4_7_von_mises_damage": (13.0, 5.6),
    "surface_von_mises": (13.0, 6.0),
    "surface_damage": (13.0, 6.0),
    "contact_pressure": (12.0, 5.6),
    "probes": (15.0, 4.8),
    "history": (12.0, 4.8),
}

# Fraction of the body's size the largest displacement is scaled to in
# deformed-configuration plots (the paper's displacements are tiny).
DEFORMATION_FRACTION = 0.08


class PlotError(Exception):
    """Anything wrong with the output directory; main() prints it on one line."""


# --------------------------------------------------------------------------
# Reading the output directory
# --------------------------------------------------------------------------

_VTK_DTYPES = {
    "Float64": "<f8", "Float32": "<f4",
    "Int64": "<i8", "Int32": "<i4", "Int16": "<i2", "Int8": "i1",
    "UInt64": "<u8", "UInt32": "<u4", "UInt16": "<u2", "UInt8": "u1",
}


class Vtu:
    """One VTU file: points (N, 3), cells (M, nodes per cell), cell type,
    point_data and cell_data: name -> array of shape (N,) / (M,) or (N, c) / (M, c)."""

    def __init__(self, points, cells, cell_type, point_data, cell_data):
        self.points = points
        self.cells = cells
        self.cell_type = cell_type
        self.point_data = point_data
        self.cell_data = cell_data

    def point(self, name):
        if name not in self.point_data:
            raise PlotError("point field '%s' not in VTU (has %s)" % (name, ", ".join(sorted(self.point_data))))
        return self.point_data[name]

    def cell(self, name):
        if name not in self.cell_data:
            raise PlotError("cell field '%s' not in VTU (has %s)" % (name, ", ".join(sorted(self.cell_data))))
        return self.cell_data[name]

    def has(self, name):
        return name in self.point_data or name in self.cell_data or (
            name == "von_mises" and "stress" in self.cell_data)

    def von_mises(self):
        """The cell field von_mises, or computed from stress (VTK order XX YY ZZ XY YZ XZ)."""
        import numpy as np

        if "von_mises" in self.cell_data:
            return self.cell_data["von_mises"]
        s = self.cell("stress")
        a, b, c = s[:, 0] - s[:, 1], s[:, 1] - s[:, 2], s[:, 2] - s[:, 0]
        return np.sqrt(np.maximum(0.5 * (a * a + b * b + c * c) + 3 * (s[:, 3:] ** 2).sum(axis=1), 0.0))

    def displacement(self):
        """The displacement field (N, 3); zeros when the run did not write it."""
        import numpy as np

        return self.point_data.get("displacement", np.zeros_like(self.points))


def _attrs(text):
    return dict(re.findall(r'([A-Za-z_:][\w:.-]*)\s*=\s*"([^"]*)"', text))


def read_vtu(path):
    """Reads a VTK XML UnstructuredGrid with raw appended data (vtu_writer.cpp's layout)."""
    import numpy as np

    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise PlotError("cannot read %s: %s" % (path, e.strerror))
    tag = raw.find(b"<AppendedData")
    if tag < 0:
        raise PlotError("%s: no <AppendedData> section (only raw appended VTU is supported)" % path)
    tag_end = raw.find(b">", tag)
    marker = raw.find(b"_", tag_end)
    if tag_end < 0 or marker < 0:
        raise PlotError("%s: no '_' marker after <AppendedData>" % path)
    base = marker + 1
    head = raw[:tag].decode("utf-8", errors="replace")
    m = re.search(r"<VTKFile\b([^>]*)>", head)
    if not m:
        raise PlotError("%s: not a VTK XML file" % path)
    file_attrs = _attrs(m.group(1))
    if file_attrs.get("type") != "UnstructuredGrid":
        raise PlotError("%s: VTKFile type is '%s', expected UnstructuredGrid" % (path, file_attrs.get("type")))
    if file_attrs.get("byte_order", "LittleEndian") != "LittleEndian":
        raise PlotError("%s: only LittleEndian data is supported" % path)
    if "compressor" in file_attrs:
        raise PlotError("%s: compressed VTU is not supported" % path)
    header = {"UInt64": "<u8", "UInt32": "<u4"}.get(file_attrs.get("header_type", "UInt32"))
    if header is None:
        raise PlotError("%s: unsupported header_type '%s'" % (path, file_attrs.get("header_type")))
    header_size = np.dtype(header).itemsize
    enc = _attrs(raw[tag:tag_end].decode("utf-8", errors="replace")).get("encoding", "raw")
    if enc != "raw":
        raise PlotError("%s: AppendedData encoding '%s' is not supported (only raw)" % (path, enc))
    m = re.search(r"<Piece\b([^>]*)>", head)
    if not m:
        raise PlotError("%s: no <Piece>" % path)
    piece = _attrs(m.group(1))
    n_points = int(piece.get("NumberOfPoints", -1))
    n_cells = int(piece.get("NumberOfCells", -1))

    def block(a):
        if a.get("format") != "appended":
            raise PlotError("%s: DataArray '%s' is not format=\"appended\"" % (path, a.get("Name", "?")))
        dtype = _VTK_DTYPES.get(a.get("type"))
        if dtype is None:
            raise PlotError("%s: unsupported DataArray type '%s'" % (path, a.get("type")))
        start = base + int(a["offset"])
        if start + header_size > len(raw):
            raise PlotError("%s: truncated file (DataArray '%s')" % (path, a.get("Name", "?")))
        nbytes = int(np.frombuffer(raw, header, count=1, offset=start)[0])
        item = np.dtype(dtype).itemsize
        if start + header_size + nbytes > len(raw) or nbytes % item:
            raise PlotError("%s: truncated or corrupt DataArray '%s'" % (path, a.get("Name", "?")))
        v = np.frombuffer(raw, dtype, count=nbytes // item, offset=start + header_size)
        nc = int(a.get("NumberOfComponents", 1))
        if v.size % nc:
            raise PlotError("%s: DataArray '%s' size %d is not a multiple of %d" % (path, a.get("Name"), v.size, nc))
        return v.reshape(-1, nc) if nc > 1 else v

    sections = {"PointData": {}, "CellData": {}, "Points": {}, "Cells": {}}
    current = None
    for m in re.finditer(r"<(/?)(PointData|CellData|Points|Cells|DataArray)\b([^>]*)>", head):
        closing, name, rest = m.group(1), m.group(2), m.group(3)
        if name == "DataArray":
            if current is None:
                continue
            a = _attrs(rest)
            sections[current][a.get("Name", "Points" if current == "Points" else "?")] = block(a)
        else:
            current = None if closing or rest.rstrip().endswith("/") else name

    if not sections["Points"]:
        raise PlotError("%s: no <Points>" % path)
    points = next(iter(sections["Points"].values()))
    if points.ndim != 2 or points.shape[0] != n_points:
        raise PlotError("%s: Points has shape %s, expected (%d, 3)" % (path, points.shape, n_points))
    for key in ("connectivity", "offsets", "types"):
        if key not in sections["Cells"]:
            raise PlotError("%s: <Cells> has no '%s' array" % (path, key))
    conn = sections["Cells"]["connectivity"].astype(np.int64)
    offsets = sections["Cells"]["offsets"].astype(np.int64)
    types = sections["Cells"]["types"]
    if offsets.size != n_cells or types.size != n_cells:
        raise PlotError("%s: %d offsets / %d types for %d cells" % (path, offsets.size, types.size, n_cells))
    sizes = np.diff(np.concatenate([[0], offsets]))
    if n_cells == 0 or np.any(sizes != sizes[0]) or np.any(types != types[0]):
        raise PlotError("%s: only meshes of a single simplex type are supported" % path)
    cells = conn.reshape(n_cells, int(sizes[0]))
    if cells.size and (cells.min() < 0 or cells.max() >= n_points):
        raise PlotError("%s: connectivity refers to nodes outside 0..%d" % (path, n_points - 1))
    for name, v in sections["PointData"].items():
        if v.shape[0] != n_points:
            raise PlotError("%s: point field '%s' has %d values for %d points" % (path, name, v.shape[0], n_points))
    for name, v in sections["CellData"].items():
        if v.shape[0] != n_cells:
            raise PlotError("%s: cell field '%s' has %d values for %d cells" % (path, name, v.shape[0], n_cells))
    return Vtu(points, cells, int(types[0]), sections["PointData"], sections["CellData"])


def read_csv(path):
    """A CSV with a header line -> dict column name -> float array (empty arrays when no rows)."""
    import numpy as np

    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise PlotError("cannot read %s: %s" % (path, e.strerror))
    if not rows:
        raise PlotError("%s is empty (no header line)" % path)
    names = rows[0]
    body = [r for r in rows[1:] if r]
    for i, r in enumerate(body):
        if len(r) != len(names):
            raise PlotError("%s line %d: %d fields, header has %d" % (path, i + 2, len(r), len(names)))
    try:
        data = np.array(body, dtype=float).reshape(len(body), len(names))
    except ValueError:
        raise PlotError("%s: non-numeric value in the data rows" % path)
    return {n: data[:, j] for j, n in enumerate(names)}


def list_solutions(outdir, probes):
    """[(t, path)] sorted by t, from solution.pvd; without a PVD, from the
    solution_NNNNN.vtu files with t looked up by step in probes.csv."""
    pvd = os.path.join(outdir, "solution.pvd")
    out = []
    if os.path.isfile(pvd):
        try:
            root = ET.parse(pvd).getroot()
        except ET.ParseError as e:
            raise PlotError("%s: not valid XML (%s)" % (pvd, e))
        for ds in root.iter("DataSet"):
            f = os.path.join(outdir, ds.get("file", ""))
            if not os.path.isfile(f):
                raise PlotError("%s lists %s, which does not exist" % (pvd, ds.get("file")))
            out.append((float(ds.get("timestep", "nan")), f))
    else:
        steps = dict(zip(probes["step"].astype(int), probes["t"])) if "step" in probes else {}
        for name in sorted(os.listdir(outdir)):
            m = re.fullmatch(r"solution_(\d+)\.vtu", name)
            if m and int(m.group(1)) in steps:
                out.append((float(steps[int(m.group(1))]), os.path.join(outdir, name)))
    out.sort(key=lambda e: e[0])
    return out


class Run:
    """Everything read from one output directory."""

    def __init__(self, outdir):
        self.outdir = outdir
        if not os.path.isdir(outdir):
            raise PlotError("%s: no such directory" % outdir)
        summary = os.path.join(outdir, "summary.json")
        if not os.path.isfile(summary):
            raise PlotError("%s not found: is this a vpcontact output directory?" % summary)
        try:
            with open(summary) as f:
                self.summary = json.load(f)
        except (OSError, ValueError) as e:
            raise PlotError("cannot read %s: %s" % (summary, e))
        self.dim = int(self.summary.get("dimension", 0))
        if self.dim not in (1, 2, 3):
            raise PlotError("%s: 'dimension' is %r, expected 1, 2 or 3" % (summary, self.summary.get("dimension")))
        self.case = str(self.summary.get("case", "?"))
        self.final_time = float(self.summary.get("final_time", 1.0))
        self.time_step = float(self.summary.get("time_step", 0.0))
        self.probe_points = [tuple(p) for p in self.summary.get("probes", [])]
        for name in ("probes.csv", "history.csv"):
            p = os.path.join(outdir, name)
            if not os.path.isfile(p):
                raise PlotError("%s not found: is this a complete vpcontact output directory?" % p)
        self.probes = read_csv(os.path.join(outdir, "probes.csv"))
        self.history = read_csv(os.path.join(outdir, "history.csv"))
        for name, table in (("probes.csv", self.probes), ("history.csv", self.history)):
            if "t" not in table:
                raise PlotError("%s has no column 't'" % os.path.join(outdir, name))
        self.solutions = list_solutions(outdir, self.probes)
        self._cache = {}

    def vtu(self, path):
        if path not in self._cache:
            self._cache[path] = read_vtu(path)
        return self._cache[path]

    def final_vtu(self):
        t, path = self.solutions[-1]
        return t, self.vtu(path)

    def snapshots(self, fractions=(0.2, 0.4, 0.6, 0.8, 1.0)):
        """The VTU files nearest the times fraction * T: [(t, path, [targets])],
        one entry per distinct file, and whether every target was matched exactly."""
        times = [t for t, _ in self.solutions]
        tol = max(1e-9 * self.final_time, 0.5 * self.time_step if self.time_step > 0 else 0.0)
        picked = []
        exact = True
        for fr in fractions:
            target = fr * self.final_time
            i = min(range(len(times)), key=lambda j: abs(times[j] - target))
            if abs(times[i] - target) > tol:
                exact = False
            if picked and picked[-1][1] == self.solutions[i][1]:
                picked[-1][2].append(target)
            else:
                picked.append((times[i], self.solutions[i][1], [target]))
        return picked, exact


# --------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------

def fmt_t(t):
    return "%.4g" % t


def snapshot_label(t, targets, exact):
    if exact:
        return "t = %s s" % fmt_t(t)
    return "t = %s s (nearest output to t = %s)" % (fmt_t(t), ", ".join(fmt_t(x) for x in targets))


def nice_scale(value):
    """The largest 1, 2 or 5 x 10^k not above value (value > 0)."""
    import math

    k = math.floor(math.log10(value))
    for m in (5, 2, 1):
        if m * 10.0 ** k <= value * (1 + 1e-12):
            return m * 10.0 ** k
    return 10.0 ** k


def deformation_scale(points, u):
    """Scale factor s so that max |s u| is about DEFORMATION_FRACTION of the body's size."""
    import numpy as np

    size = float(np.max(np.ptp(points, axis=0)))
    umax = float(np.max(np.linalg.norm(u, axis=1))) if len(u) else 0.0
    if umax <= 0 or size <= 0:
        return 1.0, umax
    return nice_scale(DEFORMATION_FRACTION * size / umax), umax


def scale_text(s):
    return "%g" % s


def boundary_edges(tris):
    """Edges (pairs of node indices) that belong to exactly one triangle."""
    import numpy as np

    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    uniq, counts = np.unique(e, axis=0, return_counts=True)
    return uniq[counts == 1]


def boundary_faces(tets, points=None):
    """(faces (F, 3), owning tet (F,)) for the faces that belong to exactly one
    tetrahedron; with points, each face is ordered so that its normal
    (b - a) x (c - a) points out of the body."""
    import numpy as np

    local = [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)]  # face nodes, then the opposite node
    faces = np.concatenate([tets[:, list(f[:3])] for f in local])
    opposite = np.concatenate([tets[:, f[3]] for f in local])
    owner = np.tile(np.arange(len(tets)), len(local))
    key = np.sort(faces, axis=1)
    _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    sel = first[counts == 1]
    faces, opposite, owner = faces[sel], opposite[sel], owner[sel]
    if points is not None:
        a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
        inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), points[opposite] - a) > 0
        faces[inward] = faces[inward][:, [0, 2, 1]]
    return faces, owner


def edge_loops(edges):
    """Polylines (lists of node indices) through a set of edges (closed loops are closed)."""
    adj = {}
    for a, b in edges:
        adj.setdefault(int(a), []).append(int(b))
        adj.setdefault(int(b), []).append(int(a))
    seen = set()
    loops = []
    for a, b in edges:
        e = (min(a, b), max(a, b))
        if e in seen:
            continue
        seen.add(e)
        line = [int(a), int(b)]
        while True:
            last, prev = line[-1], line[-2]
            nxt = [n for n in adj[last] if (min(last, n), max(last, n)) not in seen]
            if not nxt:
                break
            n = nxt[0] if nxt[0] != prev or len(nxt) == 1 else nxt[1]
            seen.add((min(last, n), max(last, n)))
            line.append(n)
        loops.append(line)
    return loops


def probe_label(p, dim):
    return "x = " + ("%.4g m" % p[0] if dim == 1 else "(" + ", ".join("%.4g" % c for c in p[:dim]) + ") m")


def stress_units(dim):
    return {1: "N/m", 2: "N/m²", 3: "N/m²"}[dim]


def force_units(dim):
    # 1D: the contact force is -sigma(L) (N/m in the paper's units); 2D: force
    # per unit thickness of the plane-stress slab; 3D: a force.
    return {1: "N/m", 2: "N/m", 3: "N"}[dim]


# --------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------

class Plotter:
    def __init__(self, run, fmt, dpi):
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        self.plt = plt
        self.run = run
        self.fmt = fmt
        self.dpi = dpi
        self.figdir = os.path.join(run.outdir, "figures")
        os.makedirs(self.figdir, exist_ok=True)
        self.written = []
        self.skipped = []

    def figure(self, name, constrained=True, **kw):
        return self.plt.figure(figsize=FIGSIZES[name], constrained_layout=constrained, **kw)

    def save(self, fig, name):
        path = os.path.join(self.figdir, "%s.%s" % (name, self.fmt))
        fig.savefig(path, dpi=self.dpi, format=self.fmt)
        self.plt.close(fig)
        self.written.append(path)
        print(path)

    def skip(self, name, why):
        self.skipped.append(name)
        print("skipped: %s.%s (%s)" % (name, self.fmt, why))

    def missing(self, vtu, *fields):
        """A reason string if the VTU lacks one of fields, else None."""
        lacking = [f for f in fields if not vtu.has(f)]
        if not lacking:
            return None
        return "the VTU files have no %s field: the run wrote a selection of fields" % " / ".join(
            "'%s'" % f for f in lacking)

    def no_vtu_reason(self):
        return "no solution.pvd or solution_*.vtu in %s: was the run made with --no-vtu?" % self.run.outdir

    def title(self, text):
        return "%s — %s" % (self.run.case, text)

    # ---- d = 1 -----------------------------------------------------------

    def rod_fields(self, vtu):
        """x of the nodes (sorted), u there, beta there; cell edges and sigma per cell (sorted by x)."""
        import numpy as np

        x = vtu.points[:, 0]
        order = np.argsort(x)
        u = vtu.point("displacement")[order, 0] if vtu.has("displacement") else None
        beta = vtu.point("damage")[order] if vtu.has("damage") else None
        cells = vtu.cells
        xl = np.minimum(x[cells[:, 0]], x[cells[:, 1]])
        xr = np.maximum(x[cells[:, 0]], x[cells[:, 1]])
        corder = np.argsort(xl)
        sig = vtu.cell("stress")[corder, 0] if vtu.has("stress") else None
        return x[order], u, beta, xl[corder], xr[corder], sig

    def empty_panel(self, ax, why, name):
        ax.text(0.5, 0.5, "not drawn:\n" + why, ha="center", va="center", transform=ax.transAxes, color="0.4")
        print("note: %s: a panel left empty (%s)" % (name, why.replace("\n", " ")))

    def snapshot_colors(self, n):
        cmap = self.plt.get_cmap("viridis")
        return [cmap(0.9 * i / max(n - 1, 1)) for i in range(n)]

    def fig_4_2(self):
        name = "fig_4_2_displacement_stress"
        if not self.run.solutions:
            return self.skip(name, self.no_vtu_reason())
        import numpy as np

        snaps, exact = self.run.snapshots()
        fig = self.figure(name)
        ax_u, ax_s = fig.subplots(1, 2)
        for (t, path, targets), c in zip(snaps, self.snapshot_colors(len(snaps))):
            x, u, _, xl, xr, sig = self.rod_fields(self.run.vtu(path))
            label = snapshot_label(t, targets, exact)
            if u is not None:
                ax_u.plot(x, u, color=c, label=label)
            if sig is not None:
                ax_s.plot(np.column_stack([xl, xr]).ravel(), np.repeat(sig, 2), color=c, label=label)
        for ax, ylabel, title in ((ax_u, "displacement u [m]", "(a) displacement field"),
                                  (ax_s, "stress σ [N/m]", "(b) stress field (P0, per element)")):
            ax.set_xlabel("x [m]")
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.grid(True, alpha=0.4)
        ax_s.axhline(0.0, color="k", lw=0.6)
        legend_title = None if exact else "only %d VTU outputs: nearest times" % len(self.run.solutions)
        for ax, field in ((ax_u, "displacement"), (ax_s, "stress")):
            if [l for l in ax.lines if not l.get_label().startswith("_")]:
                ax.legend(fontsize="small", title=legend_title, title_fontsize="small")
            else:
                self.empty_panel(ax, "no '%s' field in the VTU files" % field, name)
        fig.suptitle(self.title("Fig. 4.2: displacement and stress along the rod"))
        self.save(fig, name)

    def fig_4_3(self):
        name = "fig_4_3_time_histories"
        pr = self.run.probes
        fig = self.figure(name)
        ax_u, ax_s = fig.subplots(1, 2)
        t = pr["t"]
        for i, p in enumerate(self.run.probe_points):
            c = "C%d" % (i % 10)
            if "p%d_ux" % i in pr:
                ax_u.plot(t, pr["p%d_ux" % i], color=c, label=probe_label(p, 1))
            if "p%d_sigma11" % i in pr:
                ax_s.plot(t, pr["p%d_sigma11" % i], color=c, label=probe_label(p, 1) + " (its element)")
        for ax, ylabel, title in ((ax_u, "displacement u [m]", "(a) evolution of the displacement"),
                                  (ax_s, "stress σ [N/m]", "(b) evolution of the stress")):
            ax.set_xlabel("time t [s]")
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.grid(True, alpha=0.4)
            if self.run.probe_points:
                ax.legend(fontsize="small")
        ax_s.axhline(0.0, color="k", lw=0.6)
        fig.suptitle(self.title("Fig. 4.3: time histories at the probe points"))
        self.save(fig, name)

    def fig_4_4(self):
        name = "fig_4_4_damage"
        pr = self.run.probes
        fig = self.figure(name)
        ax_x, ax_t = fig.subplots(1, 2)
        if self.run.solutions:
            snaps, exact = self.run.snapshots()
            for (t, path, targets), c in zip(snaps, self.snapshot_colors(len(snaps))):
                x, _, beta, _, _, _ = self.rod_fields(self.run.vtu(path))
                if beta is not None:
                    ax_x.plot(x, beta, color=c, label=snapshot_label(t, targets, exact))
            legend_title = None if exact else "only %d VTU outputs: nearest times" % len(self.run.solutions)
            if ax_x.lines:
                ax_x.legend(fontsize="small", title=legend_title, title_fontsize="small")
            else:
                self.empty_panel(ax_x, "no 'damage' field in the VTU files", name)
        else:
            self.empty_panel(ax_x, "no VTU files in the output directory\n(was the run made with --no-vtu?)", name)
        for i, p in enumerate(self.run.probe_points):
            if "p%d_beta" % i in pr:
                ax_t.plot(pr["t"], pr["p%d_beta" % i], color="C%d" % (i % 10), label=probe_label(p, 1))
        ax_x.set_xlabel("x [m]")
        ax_x.set_title("(a) damage function at several times")
        ax_t.set_xlabel("time t [s]")
        ax_t.set_title("(b) evolution of the damage function")
        if self.run.probe_points:
            ax_t.legend(fontsize="small")
        for ax in (ax_x, ax_t):
            ax.set_ylabel("damage β [-]")
            ax.grid(True, alpha=0.4)
        fig.suptitle(self.title("Fig. 4.4: damage (β = 1 undamaged, β = 0 fully damaged)"))
        self.save(fig, name)

    # ---- d = 2 -----------------------------------------------------------

    def deformed_2d(self, vtu):
        import matplotlib.tri as mtri

        xy = vtu.points[:, :2]
        u = vtu.displacement()[:, :2]
        s, umax = deformation_scale(xy, u)
        y = xy + s * u
        return mtri.Triangulation(y[:, 0], y[:, 1], vtu.cells), s, umax, xy

    def fig_4_6(self):
        name = "fig_4_6_deformed_mesh"
        if not self.run.solutions:
            return self.skip(name, self.no_vtu_reason())
        import numpy as np

        t, vtu = self.run.final_vtu()
        why = self.missing(vtu, "displacement")
        if why:
            return self.skip(name, why)
        tri, s, umax, xy = self.deformed_2d(vtu)
        fig = self.figure(name)
        ax = fig.subplots()
        ax.triplot(tri, color="C0", lw=0.5)
        for k, loop in enumerate(edge_loops(boundary_edges(vtu.cells))):
            ax.plot(xy[loop, 0], xy[loop, 1], "k--", lw=1.2, label="initial boundary" if k == 0 else None)
        f = np.linalg.norm(vtu.point_data.get("contact_force", np.zeros((len(xy), 3))), axis=1)  # optional
        active = f > 0
        if np.any(active):
            ax.plot(tri.x[active], tri.y[active], "o", color="C3", ms=4,
                    label="nodes in contact (force > 0): %d" % np.count_nonzero(active))
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=2, fontsize="small")
        ax.set_title(self.title("Fig. 4.6: deformed mesh at t = %s s and initial boundary\n"
                                "displacements magnified × %s (max |u| = %.3g m)"
                                % (fmt_t(t), scale_text(s), umax)), fontsize="medium")
        self.save(fig, name)

    def fig_4_7(self):
        name = "fig_4_7_von_mises_damage"
        if not self.run.solutions:
            return self.skip(name, self.no_vtu_reason())
        t, vtu = self.run.final_vtu()
        if not vtu.has("von_mises") and not vtu.has("damage"):
            return self.skip(name, self.missing(vtu, "von_mises", "damage"))
        tri, s, _, _ = self.deformed_2d(vtu)
        fig = self.figure(name)
        ax_v, ax_b = fig.subplots(1, 2)
        ax_v.set_title("(a) von Mises norm of σ (per element)")
        ax_b.set_title("(b) damage field β")
        if vtu.has("von_mises"):
            pc = ax_v.tripcolor(tri, facecolors=vtu.von_mises(), cmap="jet")
            fig.colorbar(pc, ax=ax_v, label="von Mises norm |σ|_VM [N/m²]")
        else:
            ax_v.triplot(tri, color="0.85", lw=0.3)
            self.empty_panel(ax_v, self.missing(vtu, "von_mises"), name)
        if vtu.has("damage"):
            pc = ax_b.tripcolor(tri, vtu.point("damage"), shading="gouraud", cmap="jet")
            fig.colorbar(pc, ax=ax_b, label="damage β [-]")
        else:
            ax_b.triplot(tri, color="0.85", lw=0.3)
            self.empty_panel(ax_b, self.missing(vtu, "damage"), name)
        for ax in (ax_v, ax_b):
            ax.set_aspect("equal")
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
        where = ("on the deformed configuration (displacements × %s)" % scale_text(s) if vtu.has("displacement")
                 else "on the undeformed configuration (no displacement field in the VTU files)")
        fig.suptitle(self.title("Fig. 4.7: at t = %s s %s" % (fmt_t(t), where)))
        self.save(fig, name)

    # ---- d = 3 -----------------------------------------------------------

    def surface_3d(self, field, name, title, label):
        if not self.run.solutions:
            return self.skip(name, self.no_vtu_reason())
        import numpy as np
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection
        import matplotlib.colors as mcolors

        t, vtu = self.run.final_vtu()
        if vtu.cells.shape[1] != 4:
            raise PlotError("%s: expected tetrahedra in a 3D output, found cells with %d nodes"
                            % (self.run.solutions[-1][1], vtu.cells.shape[1]))
        why = self.missing(vtu, field)
        if why:
            return self.skip(name, why)
        s, umax = deformation_scale(vtu.points, vtu.displacement())
        y = vtu.points + s * vtu.displacement()
        faces, owner = boundary_faces(vtu.cells, y)
        normals = np.cross(y[faces[:, 1]] - y[faces[:, 0]], y[faces[:, 2]] - y[faces[:, 0]])
        if field == "von_mises":
            values = vtu.von_mises()[owner]
        else:
            values = vtu.point("damage")[faces].mean(axis=1)
        norm = mcolors.Normalize(vmin=float(values.min()), vmax=float(values.max()))
        cmap = self.plt.get_cmap("jet")
        fig = self.figure(name, constrained=False)
        lo, hi = y.min(axis=0), y.max(axis=0)
        views = ((25, -60, "(a) from above"), (-25, -60, "(b) from below: the contact face z = 0"))
        for k, (elev, azim, what) in enumerate(views):
            ax = fig.add_subplot(1, 2, k + 1, projection="3d")
            # Back-face culling: mplot3d's painter's sort alone mis-orders a closed surface.
            e, a = np.radians(elev), np.radians(azim)
            eye = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
            front = normals @ eye > 0
            poly = Poly3DCollection(y[faces[front]], facecolors=cmap(norm(values[front])), edgecolors="k",
                                    linewidths=0.15)
            ax.add_collection3d(poly)
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_zlim(lo[2], hi[2])
            ax.set_box_aspect(tuple(np.maximum(hi - lo, 1e-12)))
            ax.view_init(elev=elev, azim=azim)
            for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
                axis.set_major_locator(self.plt.MaxNLocator(5))
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
            ax.set_zlabel("z [m]")
            fig.text(0.215 + 0.43 * k, 0.015, what, ha="center", va="bottom", fontsize="large")
        sm = self.plt.cm.ScalarMappable(norm=norm, cmap=cmap)
        sm.set_array([])
        fig.subplots_adjust(left=0.0, right=0.86, bottom=0.1, top=0.88, wspace=0.05)
        cax = fig.add_axes([0.89, 0.15, 0.018, 0.62])
        fig.colorbar(sm, cax=cax, label=label)
        where = ("on the deformed boundary (displacements × %s, max |u| = %.3g m)" % (scale_text(s), umax)
                 if vtu.has("displacement") else "on the undeformed boundary (no displacement field in the VTU files)")
        fig.suptitle(self.title("%s at t = %s s\n%s" % (title, fmt_t(t), where)))
        self.save(fig, name)

    def contact_pressure(self):
        name = "contact_pressure"
        if not self.run.solutions:
            return self.skip(name, self.no_vtu_reason())
        import numpy as np
        import matplotlib.tri as mtri

        t, vtu = self.run.final_vtu()
        if vtu.cells.shape[1] != 4:
            raise PlotError("%s: expected tetrahedra in a 3D output" % self.run.solutions[-1][1])
        why = self.missing(vtu, "contact_force")
        if why:
            return self.skip(name, why)
        p = vtu.points
        zmin = p[:, 2].min()
        tol = 1e-9 * max(float(np.ptp(p[:, 2])), 1.0)
        faces, _ = boundary_faces(vtu.cells, p)
        bottom = faces[np.all(np.abs(p[faces, 2] - zmin) <= tol, axis=1)]
        where = "the bottom face z = %g" % zmin
        if len(bottom) == 0:
            # A curved body (no flat bottom): the boundary faces that look down,
            # seen from below, i.e. projected on the plane (x, y).
            a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
            n = np.cross(b - a, c - a)
            down = n[:, 2] < -0.3 * np.linalg.norm(n, axis=1)
            bottom = faces[down]
            where = "the downward-facing boundary, projected on (x, y)"
        if len(bottom) == 0:
            return self.skip(name, "no boundary faces look down (-z)")
        f = np.linalg.norm(vtu.point("contact_force"), axis=1)
        nodes = np.unique(bottom)
        active = nodes[f[nodes] > 0]
        tri = mtri.Triangulation(p[:, 0], p[:, 1], bottom)
        fig = self.figure(name)
        ax_f, ax_z = fig.subplots(1, 2)
        # (a) the whole bottom face: every node, the ones in contact larger.
        ax_f.triplot(tri, color="0.8", lw=0.4)
        sc = ax_f.scatter(p[nodes, 0], p[nodes, 1], c=f[nodes], s=8 + 60 * (f[nodes] > 0), cmap="viridis",
                          edgecolors="k", linewidths=0.3, zorder=3)
        fig.colorbar(sc, ax=ax_f, label="nodal contact force |λ| [N]")
        ax_f.set_title("(a) lower boundary: %d nodes in contact, total force %.4g N" % (len(active), float(f.sum())),
                       fontsize="medium")
        # (b) zoom on the contact zone: the nodal force interpolated over the
        # faces whose three nodes are all in contact (elsewhere: mesh only).
        in_contact = np.zeros(len(p), dtype=bool)
        in_contact[active] = True
        ax_z.triplot(tri, color="0.6", lw=0.4)
        contact_faces = bottom[np.all(in_contact[bottom], axis=1)]
        if len(contact_faces):
            ctri = mtri.Triangulation(p[:, 0], p[:, 1], contact_faces)
            pc = ax_z.tripcolor(ctri, f, shading="gouraud", cmap="viridis", vmin=0.0, vmax=float(f.max()))
            ax_z.triplot(ctri, color="w", lw=0.4, alpha=0.6)
            fig.colorbar(pc, ax=ax_z, label="nodal contact force |λ| [N] (P1 interpolation)")
        title = "(b) contact zone"
        if len(active):
            a = p[active]
            x0, x1, y0, y1 = a[:, 0].min(), a[:, 0].max(), a[:, 1].min(), a[:, 1].max()
            pad = 0.3 * max(x1 - x0, y1 - y0, 1e-3 * float(np.ptp(p[:, 0])))
            ax_z.set_xlim(x0 - pad, x1 + pad)
            ax_z.set_ylim(y0 - pad, y1 + pad)
            ax_z.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], "r:", lw=1.2,
                      label="bounding box of the nodes in contact")
            ax_z.legend(fontsize="small", loc="upper right")
            if len(active) <= 40:
                for k in active:
                    ax_z.annotate("%.3g" % f[k], (p[k, 0], p[k, 1]), xytext=(4, 4), textcoords="offset points",
                                  fontsize="small",
                                  bbox=dict(boxstyle="round,pad=0.15", fc="w", ec="none", alpha=0.8))
            box = (x1 - x0) * (y1 - y0)
            if box > 0:
                title += ": mean pressure over the box ≈ %.4g N/m²" % (float(f.sum()) / box)
        ax_z.set_title(title, fontsize="medium")
        for ax in (ax_f, ax_z):
            ax.set_aspect("equal")
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
        fig.suptitle(self.title("contact forces on %s at t = %s s (undeformed coordinates)" % (where, fmt_t(t))))
        self.save(fig, name)

    # ---- CSV figures for d = 2, 3 and all ------------------------------------

    def probes_figure(self):
        name = "probes"
        pr = self.run.probes
        d = self.run.dim
        fig = self.figure(name)
        ax_u, ax_v, ax_b = fig.subplots(1, 3)
        styles = ["-", "--", ":"]
        t = pr["t"]
        for i, p in enumerate(self.run.probe_points):
            c = "C%d" % (i % 10)
            for k, comp in enumerate("xyz"[:d]):
                col = "p%d_u%s" % (i, comp)
                if col in pr:
                    ax_u.plot(t, pr[col], color=c, ls=styles[k],
                              label="%s  u_%s" % (probe_label(p, d), comp))
            if "p%d_von_mises" % i in pr:
                ax_v.plot(t, pr["p%d_von_mises" % i], color=c, label=probe_label(p, d) + " (its element)")
            if "p%d_beta" % i in pr:
                ax_b.plot(t, pr["p%d_beta" % i], color=c, label=probe_label(p, d))
        for ax, ylabel, title in ((ax_u, "displacement [m]", "displacement components"),
                                  (ax_v, "von Mises norm [N/m²]", "von Mises norm of σ"),
                                  (ax_b, "damage β [-]", "damage β")):
            ax.set_xlabel("time t [s]")
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.grid(True, alpha=0.4)
            if self.run.probe_points:
                ax.legend(fontsize="x-small")
        fig.suptitle(self.title("time histories at the probe points"))
        self.save(fig, name)

    def history_figure(self):
        name = "history"
        h = self.run.history
        fig = self.figure(name)
        ax_f, ax_b = fig.subplots(1, 2)
        t = h["t"]
        lines = []
        if "total_contact_force" in h:
            lines += ax_f.plot(t, h["total_contact_force"], "C0", label="total contact force")
        ax_f.set_ylabel("total contact force [%s]" % force_units(self.run.dim))
        if "n_active" in h:
            ax_n = ax_f.twinx()
            lines += ax_n.step(t, h["n_active"], "C1--", where="post", label="active contact nodes")
            ax_n.set_ylabel("active contact nodes")
            ax_n.yaxis.set_major_locator(self.plt.MaxNLocator(integer=True))
            ax_n.set_ylim(bottom=0, top=max(1.0, float(h["n_active"].max()) * 1.15) if len(t) else 1.0)
        if lines:
            ax_f.legend(lines, [l.get_label() for l in lines], fontsize="small", loc="upper left")
        ax_f.set_title("contact")
        for col, style, label in (("beta_min", "C2", "min β"), ("beta_max", "C4--", "max β")):
            if col in h:
                ax_b.plot(t, h[col], style, label=label)
        ax_b.set_ylabel("damage β [-]")
        ax_b.set_title("damage extremes over the mesh")
        ax_b.legend(fontsize="small")
        for ax in (ax_f, ax_b):
            ax.set_xlabel("time t [s]")
            ax.grid(True, alpha=0.4)
        ok = h.get("ok")
        note = ""
        if ok is not None and len(ok) and not (ok == 1).all():
            note = " — %d step(s) NOT ok" % int((ok != 1).sum())
        fig.suptitle(self.title("per-step history" + note))
        self.save(fig, name)

    def all(self):
        d = self.run.dim
        if d == 1:
            self.fig_4_2()
            self.fig_4_3()
            self.fig_4_4()
        elif d == 2:
            self.fig_4_6()
            self.fig_4_7()
            self.probes_figure()
        else:
            self.surface_3d("von_mises", "surface_von_mises", "von Mises norm of σ (value of the owning tet)",
                            "von Mises norm |σ|_VM [N/m²]")
            self.surface_3d("damage", "surface_damage", "damage β (mean of the face's nodes)", "damage β [-]")
            self.contact_pressure()
            self.probes_figure()
        self.history_figure()


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="vpcontact_plot.py",
        description="Draw the paper's figures (Fernandez & Sofonea 2003, Sec. 4) from a vpcontact output "
                    "directory into OUTDIR/figures/.")
    ap.add_argument("outdir", metavar="OUTDIR", help="a directory written by 'vpcontact run'")
    ap.add_argument("--format", default="png", choices=["png", "pdf", "svg"], help="figure format (default png)")
    ap.add_argument("--dpi", type=float, default=150.0, help="resolution in dots per inch (default 150)")
    args = ap.parse_args(argv)
    prog = "vpcontact_plot"
    if not args.dpi > 0:
        print("%s: --dpi must be > 0 (got %g)" % (prog, args.dpi), file=sys.stderr)
        return 2
    try:
        import numpy
        import matplotlib
        del numpy, matplotlib
    except ImportError as e:
        print("%s: %s: install python3-numpy and python3-matplotlib and run with /usr/bin/python3"
              % (prog, e), file=sys.stderr)
        return 1
    outdir = os.path.normpath(args.outdir)
    try:
        run = Run(outdir)
        plotter = Plotter(run, args.format, args.dpi)
        plotter.all()
    except PlotError as e:
        print("%s: %s" % (prog, e), file=sys.stderr)
        return 1
    except OSError as e:
        print("%s: %s" % (prog, e), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
