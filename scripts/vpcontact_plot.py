#!/usr/bin/python3
"""Figures from a vpcontact run's output directory.

Usage: /usr/bin/python3 scripts/vpcontact_plot.py OUTDIR [--format png|pdf|svg] [--dpi 150]

Reads OUTDIR/summary.json (case name, dimension, probe points), OUTDIR/probes.csv,
OUTDIR/history.csv and, when present, OUTDIR/solution.pvd with its
solution_NNNNN.vtu files, and writes figures into OUTDIR/figures/.

File names. The paper's examples (summary.json "case" = "paper-1d" in 1D or
"paper-2d" in 2D; SPEC §4, Fernandez & Sofonea 2003, Section 4) get the
paper's figure names and "Fig. 4.x" in their titles; every other case gets
the neutral name:

  d  paper's name                  other cases          contents
  1  fig_4_2_displacement_stress   displacement_stress  u(x), sigma(x) at t = 0.2, 0.4, 0.6, 0.8, 1 T  (VTU)
  1  fig_4_3_time_histories        time_histories       u(t), sigma(t) at the probe points             (probes.csv)
  1  fig_4_4_damage                beta                 beta(x) at those times (VTU), beta(t) at the probes
  2  fig_4_6_deformed_mesh         deformed_mesh        deformed mesh at the final time, initial boundary,
                                                        nodes in contact, the rigid obstacles          (VTU)
  2  fig_4_7_von_mises_damage      von_mises_beta       |sigma|_VM (per element) and beta on the deformed body (VTU)
  3                                surface_von_mises    |sigma|_VM on the deformed boundary, from above and below (VTU)
  3                                surface_beta         beta on the deformed boundary, from above and below   (VTU)
  3                                contact_pressure     the point field contact_pressure on Gamma_3's face (the lower
                                                        boundary, or the top face where only it touches) or, with
                                                        contact pairs, on the pair's slave side, with the nodes in
                                                        contact and the force there; and against the distance from
                                                        the centre of pressure (on the case's symmetry planes it
                                                        touches)                                      (VTU)
  2,3  probes                      probes               u, von Mises, beta versus time at the probes   (probes.csv)
  all  history                     history              total contact force, active nodes, min/max beta (history.csv)
  all  friction                    friction             with friction: the tangential force (total, per obstacle
                                                        and per pair) and the normal force against t; stick/slip
                                                        nodes and the dissipation per step            (history.csv)
  2,3  surface_<name>              surface_<name>       a contact law's per-node state (summary.json surface_state:
                                                        Archard's worn depth `wear`, ...) along the contact surface
                                                        at the output times, and its integral over Gamma_3 against
                                                        t (history.csv)                               (VTU)
  all  time_steps                  time_steps           the step size k(t), the error estimate per step and the
                                                        rejected steps, when the steps are not uniform, and the
                                                        tolerance of error-controlled steps   (history.csv)

summary.json also gives the labels' units ("units": [case] units; SI where absent), the
symmetry planes, the obstacles' positions at the output times and the bodies.

Deformed configurations: one body is drawn with its displacements magnified (the paper's are
tiny; the rigid obstacles' motions with them); several bodies (touching through contact pairs)
at true scale, as a magnification would carry each body's rigid motion into the others: the 2D
deformed mesh then shows |u| in colour.

The 2D field figures follow the domain's aspect ratio (a wide domain puts
the two fields one above the other); colour bars are as tall as their plot;
fields use viridis.

VTU files: UnstructuredGrid with appended data, raw (each block a UInt64 or
UInt32 byte count, per header_type, then little-endian values) or compressed
by vtkZLibDataCompressor. The damage field is read from the point field
'beta', or 'damage' in outputs written before it was renamed. Only numpy and
matplotlib (Agg backend) are needed.

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

# The figures, by key: the file name for the paper's cases (with the
# paper's figure number, used in the title) and the neutral file name used
# for every other case. See the module docstring.
PAPER_FIGURES = {
    "displacement_stress": ("fig_4_2_displacement_stress", "4.2"),
    "time_histories": ("fig_4_3_time_histories", "4.3"),
    "beta_1d": ("fig_4_4_damage", "4.4"),
    "deformed_mesh": ("fig_4_6_deformed_mesh", "4.6"),
    "von_mises_beta": ("fig_4_7_von_mises_damage", "4.7"),
}
NEUTRAL_NAMES = {
    "displacement_stress": "displacement_stress",
    "time_histories": "time_histories",
    "beta_1d": "beta",
    "deformed_mesh": "deformed_mesh",
    "von_mises_beta": "von_mises_beta",
    "surface_von_mises": "surface_von_mises",
    "surface_beta": "surface_beta",
    "contact_pressure": "contact_pressure",
    "probes": "probes",
    "history": "history",
    "time_steps": "time_steps",
    "friction": "friction",
}
# The paper's examples (SPEC §4), by the case name summary.json records, and their dimension.
PAPER_CASES = {"paper-1d": 1, "paper-2d": 2}

# Figure sizes in inches of the figures whose layout does not depend on the
# domain; the pixel size of a figure is round(size * dpi) (tests/plot checks
# it). Keep size * 150 integral. deformed_mesh and von_mises_beta follow the
# domain's aspect ratio (deformed_mesh_size, field_pair_layout).
FIGSIZES = {
    "displacement_stress": (12.0, 4.8),
    "time_histories": (12.0, 4.8),
    "beta_1d": (12.0, 4.8),
    "surface_von_mises": (13.0, 6.0),
    "surface_beta": (13.0, 6.0),
    "contact_pressure": (13.0, 5.6),
    "probes": (15.0, 4.8),
    "history": (12.0, 4.8),
    "time_steps": (12.0, 4.8),
    "friction": (12.0, 4.8),
    "surface_state": (12.0, 4.8),
}

# Sequential, perceptually uniform, readable in grey and by colour-blind readers.
FIELD_CMAP = "viridis"
BETA_LABEL = r"damage $\beta$ [-]"

# The units of the labels: [case] units (summary.json "units"; the solver never uses
# units). The known systems put units in the labels; other text (units the user
# describes) leaves them out and is shown in the titles; outputs without "units": SI.
UNIT_SYSTEMS = {
    "SI": {"length": "m", "force": "N", "stress": "N/m$^2$", "time": "s", "energy": "J"},
    "mm-N-MPa": {"length": "mm", "force": "N", "stress": "MPa", "time": "s", "energy": "mJ"},  # N mm = mJ
}


class Units:
    """The units of one run's labels. Quantities: length, time, force, stress, energy, and
    line (force per length: the rod's stress, a 2D force per unit thickness) and
    line_energy (energy per length: a 2D work per unit thickness)."""

    def __init__(self, name="SI"):
        self.name = name
        self.system = UNIT_SYSTEMS.get(name)

    def of(self, q):
        if self.system is None:
            return None
        if q == "line":
            return "%s/%s" % (self.system["force"], self.system["length"])
        if q == "line_energy":
            return "%s/%s" % (self.system["energy"], self.system["length"])
        return self.system[q]

    def br(self, q):
        """' [unit]' after a label, or nothing."""
        u = self.of(q)
        return " [%s]" % u if u else ""

    def after(self, q):
        """' unit' after a number, or nothing."""
        u = self.of(q)
        return " %s" % u if u else ""


# The units of the run being drawn (Plotter sets them from summary.json).
UNITS = Units()


def vm_label():
    return r"$|\sigma|_{\mathrm{VM}}$" + UNITS.br("stress")


def pressure_label():
    return r"contact pressure $p$" + UNITS.br("stress")

# Fraction of the body's size the largest displacement is scaled to in
# deformed-configuration plots (the paper's displacements are tiny).
DEFORMATION_FRACTION = 0.08


def paper_case(run):
    """Whether run is one of the paper's examples (its figures get the paper's names)."""
    return PAPER_CASES.get(run.case) == run.dim


def figure_name(key, paper):
    # surface_<name>: a contact law's state, named after it
    return PAPER_FIGURES[key][0] if paper and key in PAPER_FIGURES else NEUTRAL_NAMES.get(key, key)


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
        if name == "beta":
            return "beta" in self.point_data or "damage" in self.point_data
        return name in self.point_data or name in self.cell_data or (
            name == "von_mises" and "stress" in self.cell_data)

    def beta(self):
        """The damage field beta: point field 'beta', or 'damage' as written before it was renamed."""
        return self.point("beta" if "beta" in self.point_data else "damage")

    def scalar(self, name):
        """A point field with one component as an (N,) array."""
        v = self.point(name)
        if v.ndim != 1:
            raise PlotError("point field '%s' has %d components, expected 1" % (name, v.shape[1]))
        return v

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


def _header_ints(raw, start, header, count, what):
    """count integers of the numpy type header at byte start of raw."""
    import numpy as np

    size = np.dtype(header).itemsize
    if start < 0 or start + count * size > len(raw):
        raise PlotError("%s: truncated file (block header)" % what)
    return [int(x) for x in np.frombuffer(raw, header, count=count, offset=start)]


def appended_raw(raw, start, header, what):
    """An uncompressed block: [byte count] then the bytes."""
    import numpy as np

    (nbytes,) = _header_ints(raw, start, header, 1, what)
    begin = start + np.dtype(header).itemsize
    if begin + nbytes > len(raw):
        raise PlotError("%s: truncated or corrupt data (%d bytes announced)" % (what, nbytes))
    return raw[begin:begin + nbytes]


def appended_zlib(raw, start, header, what):
    """A vtkZLibDataCompressor block: [n_blocks, block size, size of the last
    block (0: a full block), compressed size of each block], then the blocks,
    each compressed by zlib on its own."""
    import numpy as np
    import zlib

    size = np.dtype(header).itemsize
    n, block, last = _header_ints(raw, start, header, 3, what)
    if n == 0:
        return b""
    sizes = _header_ints(raw, start + 3 * size, header, n, what)
    pos = start + (3 + n) * size
    if pos + sum(sizes) > len(raw):
        raise PlotError("%s: truncated compressed data (%d bytes announced)" % (what, sum(sizes)))
    parts = []
    for c in sizes:
        try:
            parts.append(zlib.decompress(raw[pos:pos + c]))
        except zlib.error as e:
            raise PlotError("%s: corrupt compressed block (%s)" % (what, e))
        pos += c
    data = b"".join(parts)
    expected = block * (n - 1) + (last if last else block)
    if len(data) != expected:
        raise PlotError("%s: %d bytes after decompression, the header announces %d" % (what, len(data), expected))
    return data


def read_vtu(path):
    """Reads a VTK XML UnstructuredGrid with appended data (vtu_writer.cpp's
    layout), raw or compressed by vtkZLibDataCompressor."""
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
    compressor = file_attrs.get("compressor")
    if compressor not in (None, "vtkZLibDataCompressor"):
        raise PlotError("%s: compressor '%s' is not supported (only vtkZLibDataCompressor)" % (path, compressor))
    header = {"UInt64": "<u8", "UInt32": "<u4"}.get(file_attrs.get("header_type", "UInt32"))
    if header is None:
        raise PlotError("%s: unsupported header_type '%s'" % (path, file_attrs.get("header_type")))
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
        what = "%s: DataArray '%s'" % (path, a.get("Name", "?"))
        data = (appended_zlib if compressor else appended_raw)(raw, start, header, what)
        item = np.dtype(dtype).itemsize
        if len(data) % item:
            raise PlotError("%s: %d bytes, not a multiple of %d" % (what, len(data), item))
        v = np.frombuffer(data, dtype)
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
        # The case's symmetry planes [(axis 0/1/2, coordinate)], its rigid obstacles with
        # their positions at the output times, and the error control's tolerance (None:
        # fixed steps), as summary.json gives them; outputs of earlier versions have none.
        try:
            self.symmetry_planes = [("xyz".index(p["axis"]), float(p["coordinate"]))
                                    for p in self.summary.get("symmetry_planes", [])]
            self.obstacles = list(self.summary.get("obstacles", []))
        except (KeyError, TypeError, ValueError) as e:
            raise PlotError("%s: unreadable symmetry_planes or obstacles (%s)" % (summary, e))
        tol = self.summary.get("tolerance")
        self.tolerance = float(tol) if isinstance(tol, (int, float)) else None
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
        # The bodies, by the index the VTU cell field `body` gives them (summary.json "bodies":
        # the case's [mesh] first, then each [[body]]; absent for one body), and the slave part of
        # each contact pair (history.csv's force_pair_<slave> columns).
        try:
            self.bodies = [str(b["name"]) for b in self.summary.get("bodies", [])]
        except (KeyError, TypeError) as e:
            raise PlotError("%s: unreadable bodies (%s)" % (summary, e))
        self.pair_slaves = [c[len("force_pair_"):] for c in self.history if c.startswith("force_pair_")]
        # The contact laws' per-node state (summary.json "surface_state": name, width, meaning, history).
        try:
            self.surface_state = [dict(name=str(v["name"]), width=int(v["width"]), meaning=str(v.get("meaning", "")),
                                       history=str(v.get("history", "")), history_mean=bool(v.get("history_mean", False)))
                                  for v in self.summary.get("surface_state", [])]
        except (KeyError, TypeError, ValueError) as e:
            raise PlotError("%s: unreadable surface_state (%s)" % (summary, e))
        self._cache = {}

    def several_bodies(self):
        """Whether the case has bodies that touch each other (contact pairs between them): drawn
        at true scale, as a magnified displacement would carry their rigid motions into each other."""
        return len(self.bodies) > 1

    def slave_body(self, slave):
        """The index of the body a pair's slave part is on: "<body>.<part>" for a [[body]]'s part,
        the case's [mesh] (0) for a plain name (a body's name has no '.': docs/cases.md)."""
        head = slave.split(".", 1)[0]
        return self.bodies.index(head) if "." in slave and head in self.bodies[1:] else 0

    def history_at(self, col, t):
        """history.csv's column col at the step of time t (the nearest), None without it."""
        import numpy as np

        h = self.history
        if col not in h or not len(h["t"]):
            return None
        return float(h[col][int(np.argmin(np.abs(h["t"] - t)))])

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
        return "t = %s%s" % (fmt_t(t), UNITS.after("time"))
    return "t = %s%s (nearest output to t = %s)" % (fmt_t(t), UNITS.after("time"), ", ".join(fmt_t(x) for x in targets))


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


def in_contact(vtu):
    """Nodes in contact: contact_pressure > 0, or a non-zero contact_force (older outputs)."""
    import numpy as np

    if "contact_pressure" in vtu.point_data:
        return vtu.scalar("contact_pressure") > 0
    if "contact_force" in vtu.point_data:
        return np.linalg.norm(vtu.point("contact_force"), axis=1) > 0
    return np.zeros(len(vtu.points), dtype=bool)


def contact_boundary(points, cells, pressure):
    """(faces, description) of the boundary where the 3D body made of the tetrahedra cells
    touches: its flat bottom face z = zmin, or its top face z = zmax when only that has nodes
    in contact (a body indented from above), or for a curved body the faces that look down."""
    import numpy as np

    p = points
    z = p[np.unique(cells), 2]
    tol = 1e-9 * max(float(np.ptp(z)), 1.0)
    faces, _ = boundary_faces(cells, p)
    zmin, zmax = z.min(), z.max()
    bottom, top = (faces[np.all(np.abs(p[faces, 2] - z0) <= tol, axis=1)] for z0 in (zmin, zmax))

    def touched(f):
        return bool(np.any(pressure[np.unique(f)] > 0))

    if touched(top) and not touched(bottom):
        return top, "the top face $z$ = %g" % zmax
    if len(bottom):
        return bottom, "the bottom face $z$ = %g" % zmin
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    n = np.cross(b - a, c - a)
    down = n[:, 2] < -0.3 * np.linalg.norm(n, axis=1)
    return faces[down], "the downward-facing boundary, projected on $(x, y)$"


def centre_of_pressure(xy, pressure, planes, tol):
    """The pressure-weighted centre (x_c, y_c) of the nodes xy (n, 2) in contact. A
    contact zone that touches one of the case's symmetry planes planes [(axis, c)] is
    half (or a quarter) of the real zone, mirrored there: its centre's coordinate along
    that axis is the plane's. Other sides of the mesh are not symmetry planes."""
    import numpy as np

    centre = (xy * pressure[:, None]).sum(axis=0) / pressure.sum()
    for axis, c in planes:
        if axis < 2 and np.any(np.abs(xy[:, axis] - c) <= tol):
            centre[axis] = c
    return centre


def plot_aspect(tri, xy):
    """Height / width of what a 2D plot shows: the deformed mesh and the initial body."""
    import numpy as np

    x = np.concatenate([tri.x, xy[:, 0]])
    y = np.concatenate([tri.y, xy[:, 1]])
    w, h = float(np.ptp(x)), float(np.ptp(y))
    return min(max(h / w if w > 0 else 1.0, 0.05), 20.0)


def _inches(v):
    """Rounded to 0.1 inch (so that pixel sizes at the usual dpi are whole numbers)."""
    return round(v * 10.0) / 10.0


def deformed_mesh_size(aspect, colorbar=False):
    """Figure size for one equal-aspect plot of height/width aspect: the data
    box at most 6.4 in wide and 6.4 in tall, plus room for the labels, the
    legend, the two-line title and a colour bar."""
    w = 6.4 if aspect <= 1 else 6.4 / aspect
    h = w * aspect
    bar = 1.0 if colorbar else 0.0
    return (_inches(max(w + 1.2 + bar, 6.5 + bar)), _inches(h + 1.6))


def field_pair_layout(aspect):
    """(figure size, rows) for two equal-aspect field plots with colour bars:
    side by side, or one above the other for a wide domain (aspect < 0.6)."""
    if aspect < 0.6:
        w = 8.0
        h = w * aspect
        return (_inches(w + 2.4), _inches(2 * (h + 1.0) + 0.6)), 2
    h = 4.8 if aspect <= 1.2 else 6.0
    w = h / aspect
    if w > 5.6:
        w, h = 5.6, 5.6 * aspect
    return (_inches(2 * (w + 2.0)), _inches(h + 1.5)), 1


def probe_label(p, dim):
    where = "%.4g" % p[0] if dim == 1 else "(" + ", ".join("%.4g" % c for c in p[:dim]) + ")"
    return "x = " + where + UNITS.after("length")


def force_quantity(dim):
    # 1D: the contact force is -sigma(L) (N/m in the paper's units); 2D: force
    # per unit thickness of the plane-stress slab; 3D: a force.
    return {1: "line", 2: "line", 3: "force"}[dim]


def work_quantity(dim):
    # A force of force_quantity(dim) times a length: in 1D (N/m) m = N, in 2D a work per
    # unit thickness (J/m), in 3D a work (J).
    return {1: "force", 2: "line_energy", 3: "energy"}[dim]


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
        self.paper = paper_case(run)
        global UNITS
        UNITS = Units(str(run.summary.get("units", "SI")))
        self.figdir = os.path.join(run.outdir, "figures")
        os.makedirs(self.figdir, exist_ok=True)
        self.written = []
        self.skipped = []

    def name(self, key):
        """The file name (without extension) of figure key for this run."""
        return figure_name(key, self.paper)

    def figure(self, key, size=None, constrained=True):
        return self.plt.figure(figsize=size or FIGSIZES[key], constrained_layout=constrained)

    def save(self, fig, key):
        path = os.path.join(self.figdir, "%s.%s" % (self.name(key), self.fmt))
        # zlib level 3 instead of 6: a fifth less time for the whole script, files 6 % larger.
        extra = {"pil_kwargs": {"compress_level": 3}} if self.fmt == "png" else {}
        fig.savefig(path, dpi=self.dpi, format=self.fmt, **extra)
        self.plt.close(fig)
        self.written.append(path)
        print(path)

    def skip(self, key, why):
        self.skipped.append(key)
        print("skipped: %s.%s (%s)" % (self.name(key), self.fmt, why))

    def missing(self, vtu, *fields):
        """A reason string if the VTU lacks one of fields, else None."""
        lacking = [f for f in fields if not vtu.has(f)]
        if not lacking:
            return None
        return "the VTU files have no %s field: the run wrote a selection of fields" % " / ".join(
            "'%s'" % f for f in lacking)

    def no_vtu_reason(self):
        return "no solution.pvd or solution_*.vtu in %s: was the run made with --no-vtu?" % self.run.outdir

    def title(self, key, text):
        """'case — Fig. 4.x: text' for the paper's cases, 'case — text' otherwise."""
        fig_no = PAPER_FIGURES.get(key, (None, None))[1] if self.paper else None
        units = " (units: %s)" % UNITS.name if UNITS.system is None and UNITS.name else ""
        return "%s — %s%s%s" % (self.run.case, "Fig. %s: " % fig_no if fig_no else "", text, units)

    def colorbar(self, fig, mappable, ax, label, width_in=0.14):
        """A colour bar to the right of ax, exactly as tall as ax's drawn box
        (an inset axes: it follows the box that set_aspect leaves, which
        fig.colorbar(ax=...) does not), width_in inches wide."""
        w_in = ax.get_position().width * fig.get_figwidth()
        frac = width_in / max(w_in, 1e-3)
        cax = ax.inset_axes([1.0 + 0.12 / max(w_in, 1e-3), 0.0, frac, 1.0])
        return fig.colorbar(mappable, cax=cax, label=label)

    def magnification(self, points, u):
        """(s, max |u|): the deformed configurations are drawn at x + s u, s such that the largest
        displacement is DEFORMATION_FRACTION of the body's size; bodies in contact at true scale
        (s = 1), as s would carry their rigid motions into each other (a pressed roller deep in
        its block)."""
        import numpy as np

        if self.run.several_bodies():
            return 1.0, float(np.max(np.linalg.norm(u, axis=1))) if len(u) else 0.0
        return deformation_scale(points, u)

    def scale_words(self, s):
        """How the displacements are drawn, for the titles."""
        return "true scale" if self.run.several_bodies() else "displacements magnified × %s" % scale_text(s)

    # ---- d = 1 -----------------------------------------------------------

    def rod_fields(self, vtu):
        """x of the nodes (sorted), u there, beta there; cell edges and sigma per cell (sorted by x)."""
        import numpy as np

        x = vtu.points[:, 0]
        order = np.argsort(x)
        u = vtu.point("displacement")[order, 0] if vtu.has("displacement") else None
        beta = vtu.beta()[order] if vtu.has("beta") else None
        cells = vtu.cells
        xl = np.minimum(x[cells[:, 0]], x[cells[:, 1]])
        xr = np.maximum(x[cells[:, 0]], x[cells[:, 1]])
        corder = np.argsort(xl)
        sig = vtu.cell("stress")[corder, 0] if vtu.has("stress") else None
        return x[order], u, beta, xl[corder], xr[corder], sig

    def empty_panel(self, ax, why, key):
        ax.text(0.5, 0.5, "not drawn:\n" + why, ha="center", va="center", transform=ax.transAxes, color="0.4")
        print("note: %s: a panel left empty (%s)" % (self.name(key), why.replace("\n", " ")))

    def snapshot_colors(self, n):
        cmap = self.plt.get_cmap(FIELD_CMAP)
        return [cmap(0.9 * i / max(n - 1, 1)) for i in range(n)]

    def displacement_stress(self):
        key = "displacement_stress"
        if not self.run.solutions:
            return self.skip(key, self.no_vtu_reason())
        import numpy as np

        snaps, exact = self.run.snapshots()
        fig = self.figure(key)
        ax_u, ax_s = fig.subplots(1, 2)
        for (t, path, targets), c in zip(snaps, self.snapshot_colors(len(snaps))):
            x, u, _, xl, xr, sig = self.rod_fields(self.run.vtu(path))
            label = snapshot_label(t, targets, exact)
            if u is not None:
                ax_u.plot(x, u, color=c, label=label)
            if sig is not None:
                ax_s.plot(np.column_stack([xl, xr]).ravel(), np.repeat(sig, 2), color=c, label=label)
        for ax, ylabel, title in ((ax_u, r"displacement $u$" + UNITS.br("length"), "(a) displacement field"),
                                  (ax_s, r"stress $\sigma$" + UNITS.br("line"), r"(b) stress field ($P_0$, per element)")):
            ax.set_xlabel(r"$x$" + UNITS.br("length"))
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.grid(True, alpha=0.4)
        ax_s.axhline(0.0, color="k", lw=0.6)
        legend_title = None if exact else "only %d VTU outputs: nearest times" % len(self.run.solutions)
        for ax, field in ((ax_u, "displacement"), (ax_s, "stress")):
            if [l for l in ax.lines if not l.get_label().startswith("_")]:
                ax.legend(fontsize="small", title=legend_title, title_fontsize="small")
            else:
                self.empty_panel(ax, "no '%s' field in the VTU files" % field, key)
        fig.suptitle(self.title(key, "displacement and stress along the rod"))
        self.save(fig, key)

    def time_histories(self):
        key = "time_histories"
        pr = self.run.probes
        fig = self.figure(key)
        ax_u, ax_s = fig.subplots(1, 2)
        t = pr["t"]
        for i, p in enumerate(self.run.probe_points):
            c = "C%d" % (i % 10)
            if "p%d_ux" % i in pr:
                ax_u.plot(t, pr["p%d_ux" % i], color=c, label=probe_label(p, 1))
            if "p%d_sigma11" % i in pr:
                ax_s.plot(t, pr["p%d_sigma11" % i], color=c, label=probe_label(p, 1) + " (its element)")
        for ax, ylabel, title in ((ax_u, r"displacement $u$" + UNITS.br("length"), "(a) evolution of the displacement"),
                                  (ax_s, r"stress $\sigma$" + UNITS.br("line"), "(b) evolution of the stress")):
            ax.set_xlabel(r"time $t$" + UNITS.br("time"))
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.grid(True, alpha=0.4)
            if self.run.probe_points:
                ax.legend(fontsize="small")
        ax_s.axhline(0.0, color="k", lw=0.6)
        fig.suptitle(self.title(key, "time histories at the probe points"))
        self.save(fig, key)

    def beta_1d(self):
        key = "beta_1d"
        pr = self.run.probes
        fig = self.figure(key)
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
                self.empty_panel(ax_x, "no 'beta' (or 'damage') field in the VTU files", key)
        else:
            self.empty_panel(ax_x, "no VTU files in the output directory\n(was the run made with --no-vtu?)", key)
        for i, p in enumerate(self.run.probe_points):
            if "p%d_beta" % i in pr:
                ax_t.plot(pr["t"], pr["p%d_beta" % i], color="C%d" % (i % 10), label=probe_label(p, 1))
        ax_x.set_xlabel(r"$x$" + UNITS.br("length"))
        ax_x.set_title("(a) damage function at several times")
        ax_t.set_xlabel(r"time $t$" + UNITS.br("time"))
        ax_t.set_title("(b) evolution of the damage function")
        if self.run.probe_points:
            ax_t.legend(fontsize="small")
        for ax in (ax_x, ax_t):
            ax.set_ylabel(BETA_LABEL)
            ax.grid(True, alpha=0.4)
        fig.suptitle(self.title(key, r"damage ($\beta = 1$ undamaged, $\beta = 0$ fully damaged)"))
        self.save(fig, key)

    # ---- d = 2 -----------------------------------------------------------

    def deformed_2d(self, vtu):
        import matplotlib.tri as mtri

        xy = vtu.points[:, :2]
        u = vtu.displacement()[:, :2]
        s, umax = self.magnification(xy, u)
        y = xy + s * u
        return mtri.Triangulation(y[:, 0], y[:, 1], vtu.cells), s, umax, xy

    def deformed_mesh(self):
        key = "deformed_mesh"
        if not self.run.solutions:
            return self.skip(key, self.no_vtu_reason())
        import numpy as np

        t, vtu = self.run.final_vtu()
        why = self.missing(vtu, "displacement")
        if why:
            return self.skip(key, why)
        tri, s, umax, xy = self.deformed_2d(vtu)
        true_scale = self.run.several_bodies()
        fig = self.figure(key, size=deformed_mesh_size(plot_aspect(tri, xy), colorbar=true_scale))
        ax = fig.subplots()
        if true_scale:  # the displacements too small to see: their size in colour
            u = np.linalg.norm(vtu.displacement()[:, :2], axis=1)
            pc = ax.tripcolor(tri, u, shading="gouraud", cmap=FIELD_CMAP)
            self.colorbar(fig, pc, ax, r"displacement $|u|$" + UNITS.br("length"))
        ax.triplot(tri, color="0.2" if true_scale else "C0", lw=0.35 if true_scale else 0.5,
                   alpha=0.5 if true_scale else 1.0, label="deformed mesh")
        for k, loop in enumerate(edge_loops(boundary_edges(vtu.cells))):
            ax.plot(xy[loop, 0], xy[loop, 1], "k--", lw=1.2, label="initial boundary" if k == 0 else None)
        active, what = self.contact_nodes(vtu)
        if np.any(active):
            ax.plot(tri.x[active], tri.y[active], "o", color="C3", ms=4,
                    label="%s: %d" % (what, np.count_nonzero(active)))
        self.draw_obstacles(ax, t, s)
        ax.set_aspect("equal")
        ax.set_xlabel(r"$x$" + UNITS.br("length"))
        ax.set_ylabel(r"$y$" + UNITS.br("length"))
        ax.grid(True, alpha=0.3)
        # Above the axes, under the title: never over the mesh or the x label.
        ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, fontsize="small", frameon=False,
                  borderaxespad=0.3)
        how = "true scale, colour: $|u|$" if true_scale else self.scale_words(s)
        fig.suptitle(self.title(key, "deformed mesh at $t$ = %s%s and initial boundary\n"
                                "%s (max $|u|$ = %.3g%s)"
                                % (fmt_t(t), UNITS.after("time"), how, umax, UNITS.after("length"))),
                     fontsize="medium")
        self.save(fig, key)

    def contact_nodes(self, vtu):
        """(mask, what) of the nodes in contact: with contact pairs those of the slave sides (a
        master node reads the slave's reaction: the same contact seen from the other body)."""
        import numpy as np

        active = in_contact(vtu)
        if not self.run.pair_slaves or len(self.run.bodies) < 2 or not vtu.has("body"):
            return active, "nodes in contact"
        slaves = [self.run.slave_body(sl) for sl in self.run.pair_slaves]
        on_slave = np.zeros(len(vtu.points), dtype=bool)
        on_slave[np.unique(vtu.cells[np.isin(vtu.cell("body"), slaves)])] = True
        return active & on_slave, "slave nodes in contact"

    def draw_obstacles(self, ax, t, s):
        """The rigid obstacles at time t (summary.json "obstacles": their positions at the
        output times): a plane as a line, a cylinder or sphere as a circle. Their motion
        since the first output is magnified × s as the displacements are, so that a body
        the obstacle pushes stays on it. The view stays the body's."""
        import numpy as np
        import matplotlib.patches as mpatches

        if not self.run.obstacles:
            return
        xlim, ylim = ax.get_xlim(), ax.get_ylim()
        for k, ob in enumerate(self.run.obstacles):
            pos = [e for e in ob.get("positions", []) if len(e) == 4]
            if not pos:
                continue
            first = np.array(pos[0][1:3], dtype=float)
            at = np.array(min(pos, key=lambda e: abs(e[0] - t))[1:3], dtype=float)
            c = first + s * (at - first)
            if not np.all(np.isfinite(c)):
                continue
            label = "obstacle %s" % ob.get("name", k)
            style = {"color": "C%d" % (5 + k % 5), "lw": 1.8}
            if ob.get("shape") == "plane":
                n = np.array(ob.get("normal", [0, 1, 0])[:2], dtype=float)
                ax.axline(tuple(c), tuple(c + np.array([-n[1], n[0]])), label=label, **style)
            else:
                ax.add_patch(mpatches.Circle(tuple(c), float(ob.get("radius", 0)), fill=False, label=label, **style))
        ax.set_xlim(xlim)
        ax.set_ylim(ylim)

    def von_mises_beta(self):
        key = "von_mises_beta"
        if not self.run.solutions:
            return self.skip(key, self.no_vtu_reason())
        t, vtu = self.run.final_vtu()
        if not vtu.has("von_mises") and not vtu.has("beta"):
            return self.skip(key, self.missing(vtu, "von_mises", "beta"))
        tri, s, _, xy = self.deformed_2d(vtu)
        size, rows = field_pair_layout(plot_aspect(tri, xy))
        fig = self.figure(key, size=size)
        ax_v, ax_b = fig.subplots(rows, 2 // rows)
        ax_v.set_title(r"(a) von Mises norm of $\sigma$ (per element)")
        ax_b.set_title(r"(b) damage field $\beta$")
        for ax in (ax_v, ax_b):
            ax.set_aspect("equal")
            ax.set_xlabel(r"$x$" + UNITS.br("length"))
            ax.set_ylabel(r"$y$" + UNITS.br("length"))
        if vtu.has("von_mises"):
            pc = ax_v.tripcolor(tri, facecolors=vtu.von_mises(), cmap=FIELD_CMAP)
            self.colorbar(fig, pc, ax_v, vm_label())
        else:
            ax_v.triplot(tri, color="0.85", lw=0.3)
            self.empty_panel(ax_v, self.missing(vtu, "von_mises"), key)
        if vtu.has("beta"):
            pc = ax_b.tripcolor(tri, vtu.beta(), shading="gouraud", cmap=FIELD_CMAP)
            self.colorbar(fig, pc, ax_b, BETA_LABEL)
        else:
            ax_b.triplot(tri, color="0.85", lw=0.3)
            self.empty_panel(ax_b, self.missing(vtu, "beta"), key)
        where = ("on the deformed configuration (%s)" % self.scale_words(s) if vtu.has("displacement")
                 else "on the undeformed configuration (no displacement field in the VTU files)")
        fig.suptitle(self.title(key, "at $t$ = %s%s %s" % (fmt_t(t), UNITS.after("time"), where)))
        self.save(fig, key)

    # ---- d = 3 -----------------------------------------------------------

    def surface_3d(self, key, field, title, label):
        if not self.run.solutions:
            return self.skip(key, self.no_vtu_reason())
        import numpy as np
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection
        import matplotlib.colors as mcolors

        t, vtu = self.run.final_vtu()
        if vtu.cells.shape[1] != 4:
            raise PlotError("%s: expected tetrahedra in a 3D output, found cells with %d nodes"
                            % (self.run.solutions[-1][1], vtu.cells.shape[1]))
        why = self.missing(vtu, field)
        if why:
            return self.skip(key, why)
        s, umax = self.magnification(vtu.points, vtu.displacement())
        y = vtu.points + s * vtu.displacement()
        faces, owner = boundary_faces(vtu.cells, y)
        normals = np.cross(y[faces[:, 1]] - y[faces[:, 0]], y[faces[:, 2]] - y[faces[:, 0]])
        if field == "von_mises":
            values = vtu.von_mises()[owner]
        else:
            values = vtu.beta()[faces].mean(axis=1)
        norm = mcolors.Normalize(vmin=float(values.min()), vmax=float(values.max()))
        cmap = self.plt.get_cmap(FIELD_CMAP)
        fig = self.figure(key, constrained=False)
        lo, hi = y.min(axis=0), y.max(axis=0)
        views = ((25, -60, "(a) from above"), (-25, -60, "(b) from below"))
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
            ax.set_xlabel(r"$x$" + UNITS.br("length"))
            ax.set_ylabel(r"$y$" + UNITS.br("length"))
            # mplot3d turns the z label with the axis; seen from below that
            # reads upside down. Keep it upright.
            ax.zaxis.set_rotate_label(False)
            ax.set_zlabel(r"$z$" + UNITS.br("length"), rotation=90)
            fig.text(0.215 + 0.43 * k, 0.015, what, ha="center", va="bottom", fontsize="large")
        sm = self.plt.cm.ScalarMappable(norm=norm, cmap=cmap)
        sm.set_array([])
        fig.subplots_adjust(left=0.0, right=0.86, bottom=0.1, top=0.85, wspace=0.05)
        cax = fig.add_axes([0.89, 0.2, 0.018, 0.56])
        fig.colorbar(sm, cax=cax, label=label)
        where = ("on the deformed boundary (%s, max $|u|$ = %.3g%s)" % (self.scale_words(s), umax, UNITS.after("length"))
                 if vtu.has("displacement") else "on the undeformed boundary (no displacement field in the VTU files)")
        fig.suptitle(self.title(key, "%s at $t$ = %s%s\n%s" % (title, fmt_t(t), UNITS.after("time"), where)))
        self.save(fig, key)

    def pressure_surface(self, t, vtu, pres):
        """(faces, what they are, (force name, value) or None): the surface the pressure figure
        draws at time t. With contact pairs, the slave side of the pair carrying the largest normal
        force (its nodes hold the pair's λ_j; the master side reads the slave's reaction, another
        body), found on the slave's body as contact_boundary finds Γ3 on the one body, with the
        pair's force (history.csv force_pair_<slave>); else Γ3 and the total contact force."""
        import numpy as np

        if not self.run.pair_slaves:
            faces, where = contact_boundary(vtu.points, vtu.cells, pres)
            total = self.run.history_at("total_contact_force", t)
            return faces, where, None if total is None else ("total force", total)
        forces = {sl: self.run.history_at("force_pair_" + sl, t) for sl in self.run.pair_slaves}
        slave = max(self.run.pair_slaves, key=lambda sl: abs(forces[sl] or 0.0))
        body = self.run.slave_body(slave)
        cells = vtu.cells
        if len(self.run.bodies) > 1:
            if not vtu.has("body"):
                raise PlotError("%s: no cell field 'body' for the %d bodies of summary.json"
                                % (self.run.solutions[-1][1], len(self.run.bodies)))
            cells = cells[vtu.cell("body") == body]
        faces, where = contact_boundary(vtu.points, cells, pres)
        which = " (of %d pairs, the one of largest force)" % len(forces) if len(forces) > 1 else ""
        return (faces, "the slave part \"%s\"%s: %s of its body" % (slave, which, where),
                ("force between the bodies", forces[slave]))

    def contact_pressure(self):
        key = "contact_pressure"
        if not self.run.solutions:
            return self.skip(key, self.no_vtu_reason())
        import numpy as np
        import matplotlib.tri as mtri

        t, vtu = self.run.final_vtu()
        if vtu.cells.shape[1] != 4:
            raise PlotError("%s: expected tetrahedra in a 3D output" % self.run.solutions[-1][1])
        if not vtu.has("contact_pressure"):
            return self.skip(key, "the VTU files have no 'contact_pressure' field (outputs of vpcontact before "
                                  "it was added, or a selection of fields): re-run the case to draw it")
        pres = vtu.scalar("contact_pressure")
        p = vtu.points
        lower, where, force = self.pressure_surface(t, vtu, pres)
        if len(lower) == 0:
            return self.skip(key, "no boundary faces look down (-z)")
        nodes = np.unique(lower)
        active = nodes[pres[nodes] > 0]
        tri = mtri.Triangulation(p[:, 0], p[:, 1], lower)
        fig = self.figure(key)
        ax_m, ax_r = fig.subplots(1, 2)
        # (a) the nodal pressure on the lower boundary, as the P1 field it defines.
        pmax = float(pres[nodes].max()) if len(nodes) else 0.0
        pc = ax_m.tripcolor(tri, pres, shading="gouraud", cmap=FIELD_CMAP, vmin=0.0, vmax=max(pmax, 1e-300))
        ax_m.triplot(tri, color="w", lw=0.3, alpha=0.5)
        if len(active):
            ax_m.plot(p[active, 0], p[active, 1], "o", mfc="w", mec="k", mew=0.5, ms=3,
                      label="nodes in contact ($p > 0$)")
            a = p[active]
            c0, c1 = a[:, :2].min(axis=0), a[:, :2].max(axis=0)
            pad = 0.25 * max(float((c1 - c0).max()), 0.02 * float(np.ptp(p[:, :2], axis=0).max()))
            ax_m.set_xlim(c0[0] - pad, c1[0] + pad)
            ax_m.set_ylim(c0[1] - pad, c1[1] + pad)
            ax_m.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), fontsize="small", frameon=False)
        ax_m.set_aspect("equal")
        ax_m.set_xlabel(r"$x$" + UNITS.br("length"))
        ax_m.set_ylabel(r"$y$" + UNITS.br("length"))
        ax_m.set_title("(a) pressure on %s" % where, fontsize="medium", pad=22 if len(active) else 6)
        self.colorbar(fig, pc, ax_m, pressure_label())
        # (b) the same nodal values against the distance from the centre of
        # pressure: the profile of the contact zone (e.g. Hertz's ellipse).
        if len(active):
            tol = 1e-9 * max(float(np.ptp(p[:, :2], axis=0).max()), 1.0)
            centre = centre_of_pressure(p[active, :2], pres[active], self.run.symmetry_planes, tol)
            r = np.linalg.norm(p[nodes, :2] - centre, axis=1)
            r_act = np.linalg.norm(p[active, :2] - centre, axis=1)
            near = r <= 1.5 * max(float(r_act.max()), 1e-12)
            ax_r.plot(r[near], pres[nodes][near], "o", ms=3.5, color="C0", mec="none")
            ax_r.set_title("(b) nodal pressure against the distance from the centre of pressure\n"
                           "$(x_c, y_c)$ = (%.4g, %.4g)%s" % (centre[0], centre[1], UNITS.after("length")),
                           fontsize="medium")
        else:
            self.empty_panel(ax_r, "no node in contact at t = %s%s" % (fmt_t(t), UNITS.after("time")), key)
        ax_r.set_xlabel(r"distance $r$ from $(x_c, y_c)$" + UNITS.br("length"))
        ax_r.set_ylabel(pressure_label())
        ax_r.set_xlim(left=0.0)
        ax_r.set_ylim(bottom=0.0)
        ax_r.grid(True, alpha=0.4)
        extra = ": %d nodes in contact, max $p$ = %.4g%s" % (len(active), pmax, UNITS.after("stress"))
        if force is not None:
            extra += ", %s %.4g%s" % (force[0], force[1], UNITS.after("force"))
        fig.suptitle(self.title(key, "contact pressure at $t$ = %s%s (undeformed coordinates)%s"
                                % (fmt_t(t), UNITS.after("time"), extra)))
        self.save(fig, key)

    # ---- CSV figures for d = 2, 3 and all ------------------------------------

    def probes_figure(self):
        key = "probes"
        pr = self.run.probes
        d = self.run.dim
        fig = self.figure(key)
        ax_u, ax_v, ax_b = fig.subplots(1, 3)
        styles = ["-", "--", ":"]
        t = pr["t"]
        for i, p in enumerate(self.run.probe_points):
            c = "C%d" % (i % 10)
            for k, comp in enumerate("xyz"[:d]):
                col = "p%d_u%s" % (i, comp)
                if col in pr:
                    ax_u.plot(t, pr[col], color=c, ls=styles[k],
                              label="%s  $u_%s$" % (probe_label(p, d), comp))
            if "p%d_von_mises" % i in pr:
                ax_v.plot(t, pr["p%d_von_mises" % i], color=c, label=probe_label(p, d) + " (its element)")
            if "p%d_beta" % i in pr:
                ax_b.plot(t, pr["p%d_beta" % i], color=c, label=probe_label(p, d))
        for ax, ylabel, title in ((ax_u, "displacement" + UNITS.br("length"), "displacement components"),
                                  (ax_v, vm_label(), r"von Mises norm of $\sigma$"),
                                  (ax_b, BETA_LABEL, r"damage $\beta$")):
            ax.set_xlabel(r"time $t$" + UNITS.br("time"))
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.grid(True, alpha=0.4)
            if self.run.probe_points:
                ax.legend(fontsize="x-small")
        fig.suptitle(self.title(key, "time histories at the probe points"))
        self.save(fig, key)

    def history_figure(self):
        key = "history"
        h = self.run.history
        fig = self.figure(key)
        ax_f, ax_b = fig.subplots(1, 2)
        t = h["t"]
        lines = []
        if "total_contact_force" in h:
            lines += ax_f.plot(t, h["total_contact_force"], "C0", label="total contact force")
        # With [[obstacle]] sections: the force on each obstacle (history.csv force_<name>).
        for k, col in enumerate(c for c in h if c.startswith("force_")):
            lines += ax_f.plot(t, h[col], "C%d:" % (5 + k % 5), label="on %s" % col[len("force_"):])
        # The reactions of the clamped, symmetry and displacement parts (reaction_<part>_<x|y|z>):
        # a force-displacement curve. Columns that stay at round-off level are left out.
        forces = [c for c in h if c == "total_contact_force" or c.startswith("force_") or c.startswith("reaction_")]
        scale = max([float(abs(h[c]).max()) for c in forces if len(h[c])] + [0.0])
        for k, col in enumerate(c for c in forces if c.startswith("reaction_")):
            if len(t) and float(abs(h[col]).max()) > 1e-9 * scale:
                part, comp = col[len("reaction_"):].rsplit("_", 1)
                lines += ax_f.plot(t, h[col], "C%d-." % (2 + k % 8), label="reaction of %s, %s" % (part, comp))
        ax_f.set_ylabel("force" + UNITS.br(force_quantity(self.run.dim)))
        if "n_active" in h:
            ax_n = ax_f.twinx()
            lines += ax_n.step(t, h["n_active"], "C1--", where="post", label="active contact nodes")
            ax_n.set_ylabel("active contact nodes")
            ax_n.yaxis.set_major_locator(self.plt.MaxNLocator(integer=True))
            ax_n.set_ylim(bottom=0, top=max(1.0, float(h["n_active"].max()) * 1.15) if len(t) else 1.0)
        if lines:
            ax_f.legend(lines, [l.get_label() for l in lines], fontsize="small", loc="upper left")
        ax_f.set_title("contact and reaction forces" if any(c.startswith("reaction_") for c in h) else "contact")
        for col, style, label in (("beta_min", "C2", r"min $\beta$"), ("beta_max", "C4--", r"max $\beta$")):
            if col in h:
                ax_b.plot(t, h[col], style, label=label)
        ax_b.set_ylabel(BETA_LABEL)
        ax_b.set_title("damage extremes over the mesh")
        ax_b.legend(fontsize="small")
        for ax in (ax_f, ax_b):
            ax.set_xlabel(r"time $t$" + UNITS.br("time"))
            ax.grid(True, alpha=0.4)
        ok = h.get("ok")
        note = ""
        if ok is not None and len(ok) and not (ok == 1).all():
            note = " — %d step(s) NOT ok" % int((ok != 1).sum())
        fig.suptitle(self.title(key, "per-step history" + note))
        self.save(fig, key)

    def friction_figure(self):
        """A frictional run's (history.csv has tangential_force_<x|y|z>): the tangential
        force, the force on the obstacles and the pairs' master sides (each drawn where there
        are several; the body, or the slave side, gets its opposite), against t, with the
        normal force; the stick and slip nodes and the frictional dissipation per step.
        Against t, not a displacement: the motion is imposed as a function of t (of a part or
        an obstacle), and a point of the body moves a little and back as it sticks and slips
        (a curve against it folds over) or not at all when its obstacle slides under it."""
        key = "friction"
        h = self.run.history
        comps = [c for c in "xyz"[: self.run.dim] if "tangential_force_" + c in h]
        if not comps or not len(h["t"]):
            return
        # The push: the component of the largest tangential force.
        size = {c: float(abs(h["tangential_force_" + c]).max()) for c in comps}
        push = max(comps, key=lambda c: size[c])
        x = h["t"]
        fig = self.figure(key)
        ax_f, ax_s = fig.subplots(1, 2)
        for k, c in enumerate(comps):
            if c != push and size[c] <= 1e-9 * size[push]:
                continue  # a component at round-off level (the push along one axis)
            ax_f.plot(x, h["tangential_force_" + c], "C%d" % k, marker="." if len(x) < 40 else None,
                      label="tangential force, %s" % c)
        obstacles = [o for o in (self.run.obstacles or []) if isinstance(o, dict) and "name" in o]
        # Each contact pair's force on its master side (tangential_force_pair_<slave>_<c>).
        pairs = sorted(c for c in h if c.startswith("tangential_force_pair_") and c.endswith("_" + push))
        several = len(obstacles) + len(pairs) > 1
        for k, o in enumerate(obstacles):
            col = "tangential_force_%s_%s" % (o["name"], push)
            if col in h and several:
                ax_f.plot(x, h[col], "C%d:" % (5 + k % 5), label="on %s, %s" % (o["name"], push))
        for k, col in enumerate(pairs if several else []):
            slave = col[len("tangential_force_pair_"):-len("_" + push)]
            ax_f.plot(x, h[col], "C%d-." % (5 + (len(obstacles) + k) % 5), label="pair %s, %s" % (slave, push))
        if "total_contact_force" in h:
            ax_f.plot(x, h["total_contact_force"], color="0.45", ls="--", label="normal force")
        ax_f.axhline(0.0, color="0.7", lw=0.8)
        ax_f.set_xlabel(r"time $t$" + UNITS.br("time"))
        on = " and ".join(w + ("s" if n > 1 else "") for w, n in (("the obstacle", len(obstacles) or not pairs),
                                                                   ("the master side", len(pairs))) if n)
        ax_f.set_ylabel("force on %s" % on + UNITS.br(force_quantity(self.run.dim)))
        ax_f.set_title("tangential and normal force")
        ax_f.legend(fontsize="small")
        t = h["t"]
        lines = []
        for col, style, label in (("n_stick", "C2", "stick nodes"), ("n_slip", "C3--", "slip nodes")):
            if col in h:
                lines += ax_s.step(t, h[col], style, where="post", label=label)
        ax_s.set_ylabel("contact nodes")
        ax_s.yaxis.set_major_locator(self.plt.MaxNLocator(integer=True))
        if "dissipation" in h:
            ax_d = ax_s.twinx()
            lines += ax_d.plot(t, h["dissipation"].cumsum(), "C4-.", label="dissipation so far")
            ax_d.set_ylabel("frictional dissipation" + UNITS.br(work_quantity(self.run.dim)))
        if lines:
            ax_s.legend(lines, [l.get_label() for l in lines], fontsize="small", loc="upper left")
        ax_s.set_xlabel(r"time $t$" + UNITS.br("time"))
        ax_s.set_title("stick, slip and dissipation")
        for ax in (ax_f, ax_s):
            ax.grid(True, alpha=0.4)
        fig.suptitle(self.title(key, "friction"))
        self.save(fig, key)

    def surface_state_figures(self):
        """Each contact law's per-node variable of one number (summary.json surface_state: the worn
        depth `wear`, ...): on the left its values at the contact nodes against their coordinate along
        the contact surface's longest extent (3D: the nodes on the line through its final largest
        value), at the output times (colour: t); on the right its integral over Gamma_3 against t
        where history.csv has it."""
        import numpy as np

        for v in self.run.surface_state:
            key = "surface_" + v["name"]
            if v["width"] != 1:
                continue
            if not self.run.solutions:
                self.skip(key, self.no_vtu_reason())
                continue
            series = []
            for t, path in self.run.solutions:
                vtu = self.run.vtu(path)
                if not vtu.has(v["name"]):
                    break
                series.append((t, vtu.scalar(v["name"]), vtu.points))
            if not series:
                self.skip(key, self.missing(self.run.vtu(self.run.solutions[0][1]), v["name"]))
                continue
            # Gamma_3's nodes: where the field is not 0 at some output time (0 off Gamma_3).
            on = np.zeros(len(series[-1][1]), dtype=bool)
            for _, values, _ in series:
                if len(values) == len(on):
                    on |= values != 0
            if not on.any():
                on[:] = True
            points = series[-1][2][on]
            extent = points.max(axis=0) - points.min(axis=0)
            axis = int(np.argmax(extent))
            where = ""
            if self.run.dim == 3:  # the line of nodes along `axis` through the final largest value
                across = int(np.argsort(extent)[-2])
                c = points[int(np.argmax(np.abs(series[-1][1][on]))), across]
                band = np.abs(series[-1][2][:, across] - c) <= 0.02 * extent[across]
                on &= band
                where = ", at %s = %.4g" % ("xyz"[across], c)
            h = self.run.history
            integrated = bool(v["history"]) and v["history"] in h
            fig = self.figure("surface_state")
            if integrated:
                ax_v, ax_h = fig.subplots(1, 2)
            else:  # no column to draw on the right: the values alone, the figure's whole width
                ax_v, ax_h = fig.subplots(1, 1), None
            cmap = self.plt.get_cmap(FIELD_CMAP)
            t_end = max(series[-1][0], 1e-300)
            picked = series if len(series) <= 8 else [series[int(round(i))] for i in np.linspace(0, len(series) - 1, 8)]
            for t, values, pts in picked:
                if len(values) != len(on):
                    continue
                x = pts[on][:, axis]
                order = np.argsort(x, kind="stable")
                ax_v.plot(x[order], values[on][order], ".-", ms=3, lw=0.8,
                          color=cmap(t / t_end), label="t = %s" % fmt_t(t))
            ax_v.set_xlabel("%s along the contact surface%s" % ("xyz"[axis], where) + UNITS.br("length"))
            ax_v.set_ylabel(v["name"])
            ax_v.set_title(v["meaning"] or v["name"], fontsize="medium")
            ax_v.legend(fontsize="small")
            if integrated:
                ax_h.plot(h["t"], h[v["history"]], "C0")
                ax_h.set_ylabel(v["history"].replace("_", " "))
                ax_h.set_title("mean over the contact surface" if v.get("history_mean") else "over the contact surface")
                ax_h.set_xlabel(r"time $t$" + UNITS.br("time"))
            for ax in (ax_v, ax_h):
                if ax is not None:
                    ax.grid(True, alpha=0.4)
            fig.suptitle(self.title(key, v["name"] + " on the contact surface"))
            self.save(fig, key)

    def time_steps_figure(self):
        """k(t) and the error estimate of each step, with the rejected steps marked: drawn
        when the steps are not all of one size (a list, a formula, error control)."""
        key = "time_steps"
        h = self.run.history
        if "dt" not in h or not len(h["dt"]):
            return
        k = h["dt"]
        rejected = h.get("rejected")
        uniform = float(k.max() - k.min()) <= 1e-9 * float(k.max())
        if uniform and (rejected is None or not rejected.any()):
            return
        t = h["t"]
        fig = self.figure(key)
        ax_k, ax_e = fig.subplots(1, 2)
        ax_k.step(t, k, "C0", where="pre", label="step size $k_n$")
        if rejected is not None and rejected.any():
            at = rejected > 0
            ax_k.plot(t[at], k[at], "C3v", markersize=5, label="redone after %d rejection(s)" % int(rejected.sum()))
        ax_k.set_yscale("log")
        ax_k.set_ylabel(r"step size $k_n = t_n - t_{n-1}$" + UNITS.br("time"))
        ax_k.set_title("%d steps, k in [%.3g, %.3g]" % (len(k), float(k.min()), float(k.max())))
        ax_k.legend(fontsize="small")
        if "error_estimate" in h:
            e = h["error_estimate"]
            positive = e > 0
            ax_e.semilogy(t[positive], e[positive], "C1.", markersize=4, label=r"estimate $e_n$")
            ax_e.semilogy(t[positive], (e / k)[positive], "C2.", markersize=4, label=r"$e_n / k_n$ (per unit time)")
            if self.run.tolerance is not None:  # a step is accepted when e_n <= tolerance k_n
                ax_e.axhline(self.run.tolerance, color="C3", ls="--", lw=1.2,
                             label=r"tolerance %g: accepted where $e_n / k_n \leq$ it" % self.run.tolerance)
            ax_e.legend(fontsize="small")
        ax_e.set_ylabel("relative error estimate [-]")
        ax_e.set_title("error estimate of each step")
        for ax in (ax_k, ax_e):
            ax.set_xlabel(r"time $t$" + UNITS.br("time"))
            ax.grid(True, alpha=0.4, which="both")
        fig.suptitle(self.title(key, "time steps"))
        self.save(fig, key)

    def all(self):
        d = self.run.dim
        if d == 1:
            self.displacement_stress()
            self.time_histories()
            self.beta_1d()
        elif d == 2:
            self.deformed_mesh()
            self.von_mises_beta()
            self.probes_figure()
        else:
            self.surface_3d("surface_von_mises", "von_mises",
                            r"von Mises norm of $\sigma$ (value of the owning tetrahedron)", vm_label())
            self.surface_3d("surface_beta", "beta", r"damage $\beta$ (mean of the face's nodes)", BETA_LABEL)
            self.contact_pressure()
            self.probes_figure()
        self.history_figure()
        self.friction_figure()
        if d > 1:
            self.surface_state_figures()
        self.time_steps_figure()


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="vpcontact_plot.py",
        description="Draw the figures of a vpcontact output directory into OUTDIR/figures/ (the paper's "
                    "Figs 4.2-4.4 and 4.6-4.7 for its cases paper-1d and paper-2d).")
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
