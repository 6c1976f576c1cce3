#!/usr/bin/env python3
"""The backend-equivalence test (issue 12): one case, the whole path from the case
file to the files a run writes, on the serial engine and on the PETSc engine at
several rank counts.

  equivalence.py --vpcontact BIN --mpiexec MPIEXEC --work DIR [--ranks 1,2,3]
                 -- CASE [run options...]

Runs `BIN run CASE OPTIONS --engine serial` once and `MPIEXEC -n P BIN run CASE
OPTIONS --engine petsc` for each P, then compares what they wrote:
- every VTU file (the serial solution_NNNNN.vtu against the PETSc engine's pieces
  solution_NNNNN_pXXXX.vtu listed by solution_NNNNN.pvtu, or on one rank its one
  solution_NNNNN.vtu, as a serial run's, matched by node coordinates and, for cells,
  by their nodes): every point and cell array, raw or zlib-compressed; the PETSc
  engine's `rank` array (several ranks only) is the only one allowed in one engine only;
- solution.pvd (the same output times);
- history.csv and probes.csv: the same header, rows and every column;
- summary.json: every number and string, except the run's timings and memory, its command
  line and date, and the PETSc engine's `ranks` and `linear_solver`.
Numbers agree when |a - b| <= 1e-10 * scale + floor, where scale is the largest
magnitude of that array or column in the serial run (a field's own unit), and
floor is 1e-13 * (1 + scale) (the VTU `gap`, g - N u, takes the displacement's scale where larger:
its error is u's), except for the solvers' residuals (history.csv,
summary.json "checks") and history.csv's error_estimate: relative residuals at round-off level, written with 3
digits in history.csv, and the estimate's round-off, which is the solution's, agree when |a - b| <= 1e-10. Integers
(steps, iterations, counts, flags) must be equal, except a frictional run's contact_iterations
(history.csv has n_stick), which may differ by one, and so summary.json's max_contact_iterations:
the frictional dual's semismooth Newton stops at round-off (1e-13 of its scale), and the primal's
Newton at its tolerance, where another engine's factor of K can take one more step.

With --command converge the runs are `BIN converge CASE OPTIONS --no-plot` and what is
compared is every convergence_*.csv (the norms of the study, computed on rank 0 from the
states gathered there): the same comment line, header and rows; numbers to 1e-6 of their
column's largest magnitude plus 1e-11 (an error norm is a difference of two runs: the
engines' round-off, about 1e-13 of the solution, is relative to the solution, not to
the error); a rate of a norm below 1e-11 (round-off, e.g. a contact force that every level
gets exactly) is not compared; NaN only against NaN; the `seconds` column and the
solvers' iteration means and maxima (which round-off may change by one) are not compared;
counts of active sets and bounds are.

Prints "equivalence: PASSED" or the differences and "equivalence: FAILED".
Python standard library only.
"""
import argparse
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import time
import zlib

REL = 1e-10
RESIDUAL_ABS = 1e-10
ITERATIVE = False  # --iterative: a CG PETSc run against CHOLMOD (see main)
# Keys of summary.json that say how a run went, not what it computed.
# `factorizations` counts how the solvers went about it (the serial damage solver
# picks capacitance or a reduced factor by measured time), not a result.
# An adaptive run's time split and memory ([adapt]: adaptation_seconds, each adaptation's seconds_*, resident_bytes) are measurements too.
SUMMARY_SKIP = {"timing_seconds", "setup_seconds", "memory_bytes", "vpcontact", "engine", "ranks", "linear_solver", "factorizations",
                "adaptation_seconds", "seconds_adapt", "seconds_rebuild", "resident_bytes"}


class Report:
    def __init__(self):
        self.failures = []
        self.worst = {}  # what -> largest |a - b| / tolerance seen

    def fail(self, msg):
        self.failures.append(msg)

    def note(self, what, ratio):
        self.worst[what] = max(self.worst.get(what, 0.0), ratio)


# ---------------------------------------------------------------- VTU reading

def read_vtu(path):
    """{'points': [(x, y, z)], 'cells': [[node, ...]], 'point': {name: (ncomp, values)}, 'cell': {...}}"""
    with open(path, "rb") as f:
        data = f.read()
    head, sep, rest = data.partition(b"<AppendedData")
    if not sep:
        raise ValueError(f"{path}: no AppendedData")
    xml = head.decode()
    binary = rest[rest.index(b"_") + 1:]
    compressed = "vtkZLibDataCompressor" in xml
    if 'header_type="UInt64"' not in xml:
        raise ValueError(f"{path}: expected header_type UInt64")

    def block(offset):
        if not compressed:
            (n,) = struct.unpack_from("<Q", binary, offset)
            return binary[offset + 8: offset + 8 + n]
        nb, _, _ = struct.unpack_from("<QQQ", binary, offset)
        sizes = struct.unpack_from(f"<{nb}Q", binary, offset + 24)
        pos = offset + 24 + 8 * nb
        out = bytearray()
        for s in sizes:
            out += zlib.decompress(binary[pos: pos + s])
            pos += s
        return bytes(out)

    fmt_of = {"Float64": "d", "Int64": "q", "Int32": "i", "UInt8": "B"}  # Int32: the material and rank fields
    out = {"point": {}, "cell": {}}
    section = None
    for m in re.finditer(r"<(/?)(Points|Cells|PointData|CellData)\b[^>]*>|<DataArray ([^>]*)/>", xml):
        if m.group(2):
            section = None if m.group(1) else m.group(2)
            continue
        attrs = dict(re.findall(r'(\w+)="([^"]*)"', m.group(3)))
        raw = block(int(attrs["offset"]))
        code = fmt_of[attrs["type"]]
        values = struct.unpack(f"<{len(raw) // struct.calcsize(code)}{code}", raw)
        ncomp = int(attrs.get("NumberOfComponents", "1"))
        if section == "Points":
            out["points"] = [tuple(values[i:i + 3]) for i in range(0, len(values), 3)]
        elif section == "Cells":
            out[attrs["Name"]] = values
        elif section == "PointData":
            out["point"][attrs["Name"]] = (ncomp, values)
        elif section == "CellData":
            out["cell"][attrs["Name"]] = (ncomp, values)
    conn, offs = out.pop("connectivity"), out.pop("offsets")
    start, cells = 0, []
    for o in offs:
        cells.append(conn[start:o])
        start = o
    out["cells"] = cells
    return out


def compare_values(rep, what, serial, other, scale, floor, label):
    tol = REL * scale + floor
    for i, (a, b) in enumerate(zip(serial, other)):
        d = abs(a - b)
        if not d <= tol:  # also catches NaN
            rep.fail(f"{what}: {label(i)}: serial {a!r}, PETSc {b!r} (|diff| {d:.3e} > {tol:.3e})")
            return
        if tol > 0:
            rep.note(what, d / tol)


def scale_of(values):
    return max((abs(v) for v in values if math.isfinite(v)), default=0.0)


def point_bodies(v):
    """Per point, the body of a cell that has it (the cell array "body" of several bodies), or None:
    two bodies in contact may have a node each at one place (issue 29), told apart by their body."""
    out = [None] * len(v["points"])
    if "body" in v["cell"]:
        body = v["cell"]["body"][1]
        for ci, c in enumerate(v["cells"]):
            for j in c:
                out[j] = body[ci]
    return out


def compare_vtu(rep, what, serial_path, pieces):
    s = read_vtu(serial_path)
    index = {p: i for i, p in enumerate(zip(s["points"], point_bodies(s)))}
    if len(index) != len(s["points"]):
        rep.fail(f"{what}: the serial mesh has coincident nodes in one body; cannot match pieces by coordinates")
        return
    at = {}  # coordinates -> the serial points there (several where bodies touch)
    for (x, _), i in index.items():
        at.setdefault(x, []).append(i)
    cell_index = {tuple(sorted(c)): i for i, c in enumerate(s["cells"])}
    point_seen, cell_seen = set(), set()
    names = {"point": set(s["point"]), "cell": set(s["cell"])}
    for piece in pieces:
        p = read_vtu(piece)
        for kind in ("point", "cell"):
            extra = set(p[kind]) - names[kind] - ({"rank"} if kind == "cell" else set())
            missing = names[kind] - set(p[kind])
            if extra or missing:
                rep.fail(f"{what}: {os.path.basename(piece)}: {kind} arrays differ: only in PETSc {sorted(extra)}, "
                         f"only in serial {sorted(missing)}")
                return
        # A point in none of the piece's cells (a contact pair's node the rank owns, others' cells
        # touch it) has no body here: matched by its coordinates alone where one serial node is
        # there, else left to the pieces whose cells have it (-1: not compared here).
        pmap = []
        for x, b in zip(p["points"], point_bodies(p)):
            if (x, b) in index:
                pmap.append(index[(x, b)])
            elif b is None and len(at.get(x, [])) > 1:
                pmap.append(-1)
            elif b is None and x in at:
                pmap.append(at[x][0])
            else:
                rep.fail(f"{what}: {os.path.basename(piece)}: node {x} is not a node of the serial mesh")
                return
        cmap = []
        for c in p["cells"]:
            key = tuple(sorted(pmap[j] for j in c))
            if key not in cell_index:
                rep.fail(f"{what}: {os.path.basename(piece)}: a cell with serial nodes {key} is not a serial cell")
                return
            cmap.append(cell_index[key])
        point_seen.update(i for i in pmap if i >= 0)
        cell_seen.update(cmap)
        for kind, m in (("point", pmap), ("cell", cmap)):
            for name in sorted(names[kind]):
                nc, sv = s[kind][name]
                nc2, pv = p[kind][name]
                if nc != nc2 or len(pv) != len(m) * nc:
                    rep.fail(f"{what}: {name}: {nc2} components x {len(pv) // max(nc2, 1)} in a piece, "
                             f"serial {nc} components")
                    return
                keep = [i for i in range(len(pv)) if m[i // nc] >= 0]
                pv = [pv[i] for i in keep]
                ref = [sv[m[i // nc] * nc + i % nc] for i in keep]
                scale = scale_of(sv)
                if name == "gap" and "displacement" in s["point"]:  # g - N u: its error is u's
                    scale = max(scale, scale_of(s["point"]["displacement"][1]))
                compare_values(rep, f"vtu {name}", ref, pv, scale, 1e-13 * (1 + scale),
                               lambda i, kind=kind, m=m, nc=nc, keep=keep: f"{os.path.basename(piece)} {kind} "
                                                                 f"{m[keep[i] // nc]} component {keep[i] % nc}")
    if len(point_seen) != len(s["points"]) or len(cell_seen) != len(s["cells"]):
        rep.fail(f"{what}: the pieces cover {len(point_seen)} of {len(s['points'])} nodes and {len(cell_seen)} of "
                 f"{len(s['cells'])} cells")


# ---------------------------------------------------------------- CSV, PVD, JSON

def read_csv(path):
    with open(path) as f:
        lines = [l.rstrip("\n") for l in f if l.strip()]
    return lines[0].split(","), [l.split(",") for l in lines[1:]]


def is_int(text):
    return re.fullmatch(r"-?\d+", text) is not None


def compare_csv(rep, name, serial_path, other_path):
    sh, srows = read_csv(serial_path)
    ph, prows = read_csv(other_path)
    if sh != ph:
        rep.fail(f"{name}: headers differ: serial {sh}, PETSc {ph}")
        return
    if len(srows) != len(prows):
        rep.fail(f"{name}: {len(srows)} rows in serial, {len(prows)} in PETSc")
        return
    for j, col in enumerate(sh):
        if ITERATIVE and "iterations" in col:
            continue  # an inexact solve finds the same set in its own number of iterations
        sv, pv = [r[j] for r in srows], [r[j] for r in prows]
        # Counts are integers on both sides and must match exactly; a float column whose
        # serial values happen to be whole numbers (contact_area = 1) is compared as floats.
        if all(is_int(v) for v in sv + pv):
            slack = 1 if col == "contact_iterations" and "n_stick" in sh else 0
            for i, (a, b) in enumerate(zip(sv, pv)):
                if abs(int(a) - int(b)) > slack:
                    rep.fail(f"{name} {col}: row {i + 1} (step {srows[i][0]}): serial {a}, PETSc {b}")
                    break
            continue
        sf, pf = [float(v) for v in sv], [float(v) for v in pv]
        # The error estimate too: a difference of two solutions relative to the solution (it is
        # dimensionless), its round-off is the solution's, not its own (materials-2d at 3 ranks:
        # 3.0e-13 apart at 1.9e-3, above 1e-10 of itself).
        residual = ("residual" in col or col in FRICTION_RESIDUALS or col == "error_estimate"
                    or col.startswith("contact_") and col not in ("contact_iterations", "contact_area"))
        scale = scale_of(sf)
        if col.startswith("reaction_"):
            # A reaction that vanishes (a roller's in a symmetric case) is round-off of the
            # size of the case's forces: compare every reaction against the largest force.
            forces = [k for k, c in enumerate(sh) if c.startswith("reaction_") or c == "total_contact_force"]
            scale = max(scale_of([float(r[k]) for r in srows]) for k in forces)
        floor = RESIDUAL_ABS if residual else 1e-13 * (1 + scale)
        compare_values(rep, f"{name} {col}", sf, pf, 0 if residual else scale, floor,
                       lambda i: f"row {i + 1} (step {srows[i][0]})")


# Friction's residuals (history.csv columns and summary.json's friction block): round-off-sized
# numbers, compared as residuals (to RESIDUAL_ABS), not as values.
FRICTION_RESIDUALS = ("friction_bound", "friction_stick_slip", "friction_slip_direction", "max_friction_bound",
                      "max_stick_slip", "max_slip_direction")


NOISE = 1e-11  # below this a norm of a difference of runs is round-off of the solution itself


def compare_convergence(rep, serial_dir, petsc_dir):
    """The convergence_*.csv of a `converge` study; returns how many files."""
    names = sorted(f for f in os.listdir(serial_dir) if f.startswith("convergence_") and f.endswith(".csv"))
    if not names:
        rep.fail("the serial study wrote no convergence_*.csv")
    for name in names:
        other = os.path.join(petsc_dir, name)
        if not os.path.exists(other):
            rep.fail(f"{name}: missing in the PETSc study")
            continue
        with open(os.path.join(serial_dir, name)) as f:
            a = [l.rstrip("\n") for l in f if l.strip()]
        with open(other) as f:
            b = [l.rstrip("\n") for l in f if l.strip()]
        if len(a) != len(b) or a[0] != b[0] or a[1] != b[1]:
            rep.fail(f"{name}: comment, header or row count differ: {a[:2]} / {b[:2]}")
            continue
        header = a[1].split(",")
        rows_a = [r.split(",") for r in a[2:]]
        rows_b = [r.split(",") for r in b[2:]]
        column = {c: j for j, c in enumerate(header)}
        for j, col in enumerate(header):
            if col == "seconds" or "_iter_" in col:
                continue
            va, vb = [r[j] for r in rows_a], [r[j] for r in rows_b]
            try:
                fa, fb = [float(v) for v in va], [float(v) for v in vb]
            except ValueError:
                if va != vb:
                    rep.fail(f"{name} {col}: serial {va}, PETSc {vb}")
                continue
            finite = [abs(x) for x in fa if math.isfinite(x)]
            scale = max(finite, default=0.0)
            # The rate of a norm that is round-off (a contact force exact on every level) is noise.
            base = col.replace("rate_", "") if col.startswith("diff_rate_") else col.replace("rate_", "err_")
            noise = [i for i in range(len(fa)) if base != col and base in column and
                     any(abs(float(r[column[base]])) < NOISE for r in rows_a[max(i - 1, 0):i + 1])]
            for i, (x, y) in enumerate(zip(fa, fb)):
                if i in noise:
                    continue
                if math.isnan(x) or math.isnan(y):
                    if not (math.isnan(x) and math.isnan(y)):
                        rep.fail(f"{name} {col}: row {i + 1}: serial {va[i]}, PETSc {vb[i]}")
                    continue
                tol = 1e-6 * scale + NOISE
                rep.note(f"{name} {col}", abs(x - y) / tol)
                if abs(x - y) > tol:
                    rep.fail(f"{name} {col}: row {i + 1}: serial {va[i]}, PETSc {vb[i]}")
    return len(names)


def pvd_times(path):
    with open(path) as f:
        return [float(t) for t in re.findall(r'timestep="([^"]*)"', f.read())]


def compare_json(rep, path, a, b, beta=None, frictional=False):
    """beta: the serial final VTU's {point: β}, to accept another node where min β is
    attained to round-off (a uniform β, as in patch-3d, has its minimum anywhere); frictional:
    max_contact_iterations may differ by one (as history.csv's contact_iterations)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in SUMMARY_SKIP or ITERATIVE and "iterations" in k:
                continue
            if k not in a or k not in b:
                rep.fail(f"summary.json {path}{k}: only in {'serial' if k in a else 'PETSc'}")
                continue
            if k == "beta_min_location" and beta and a[k] != b[k] and "beta_min" in a:
                at = beta.get(tuple(float(x) for x in b[k]) + (0.0,) * (3 - len(b[k])))
                if at is not None and abs(at - a["beta_min"]) <= 1e-13 * (1 + abs(a["beta_min"])):
                    continue
            compare_json(rep, f"{path}{k}.", a[k], b[k], beta, frictional)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            rep.fail(f"summary.json {path}: {len(a)} entries in serial, {len(b)} in PETSc")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            compare_json(rep, f"{path}{i}.", x, y, beta, frictional)
    elif isinstance(a, bool) or isinstance(a, str) or a is None or isinstance(a, int) and isinstance(b, int):
        if frictional and path == "checks.max_contact_iterations." and abs(a - b) <= 1:
            return
        if a != b:
            rep.fail(f"summary.json {path.rstrip('.')}: serial {a!r}, PETSc {b!r}")
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if "residual" in path or path.rstrip(".").split(".")[-1] in FRICTION_RESIDUALS:
            compare_values(rep, "summary.json residuals", [a], [b], 0, RESIDUAL_ABS, lambda i: path.rstrip("."))
        else:
            scale = abs(a)
            compare_values(rep, "summary.json", [a], [b], scale, 1e-13 * (1 + scale), lambda i: path.rstrip("."))
    else:
        rep.fail(f"summary.json {path.rstrip('.')}: serial {a!r}, PETSc {b!r}")


def compare_runs(rep, serial_dir, petsc_dir, ranks):
    files = sorted(os.listdir(serial_dir))
    stems = [f[:-4] for f in files if re.fullmatch(r"solution_\d{5}\.vtu", f)]
    # One rank writes what a serial run writes; several, pieces and a .pvtu per step.
    one = ranks == 1
    pstems = sorted(f[:f.index(".")] for f in os.listdir(petsc_dir)
                    if re.fullmatch(r"solution_\d{5}\.vtu" if one else r"solution_\d{5}\.pvtu", f))
    if one and any(re.fullmatch(r"solution_\d{5}(_p\d{4}\.vtu|\.pvtu)", f) for f in os.listdir(petsc_dir)):
        rep.fail("PETSc on one rank wrote pieces or a .pvtu")
    if stems != pstems:
        rep.fail(f"output steps differ: serial {stems}, PETSc {pstems}")
    if os.path.exists(os.path.join(serial_dir, "solution.pvd")):
        st, pt = pvd_times(os.path.join(serial_dir, "solution.pvd")), pvd_times(os.path.join(petsc_dir, "solution.pvd"))
        if st != pt:
            rep.fail(f"solution.pvd: output times differ: serial {st}, PETSc {pt}")
    for stem in stems:
        pieces = [os.path.join(petsc_dir, f"{stem}.vtu" if one else f"{stem}_p{r:04d}.vtu") for r in range(ranks)]
        if not all(os.path.exists(p) for p in pieces):
            rep.fail(f"{stem}: missing PETSc pieces")
            continue
        compare_vtu(rep, stem, os.path.join(serial_dir, stem + ".vtu"), pieces)
    for name in ("history.csv", "probes.csv"):
        compare_csv(rep, name, os.path.join(serial_dir, name), os.path.join(petsc_dir, name))
    with open(os.path.join(serial_dir, "summary.json")) as f:
        sj = json.load(f)
    with open(os.path.join(petsc_dir, "summary.json")) as f:
        pj = json.load(f)
    beta = None
    if stems:
        v = read_vtu(os.path.join(serial_dir, stems[-1] + ".vtu"))
        field = v["point"].get("beta") or v["point"].get("damage")
        if field:
            beta = {tuple(p): x for p, x in zip(v["points"], field[1])}
    with open(os.path.join(serial_dir, "history.csv")) as f:
        frictional = "n_stick" in f.readline().strip().split(",")
    compare_json(rep, "", sj, pj, beta, frictional)
    return len(stems)


# ---------------------------------------------------------------- running

def run(cmd, env):
    t0 = time.monotonic()
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return p, time.monotonic() - t0


def main():
    global REL, RESIDUAL_ABS, ITERATIVE
    ap = argparse.ArgumentParser()
    ap.add_argument("--vpcontact", required=True)
    ap.add_argument("--mpiexec", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--ranks", default="1,2,3")
    ap.add_argument("--command", default="run", choices=["run", "converge"])
    ap.add_argument("--petsc-arg", action="append", default=[],
                    help="an argument for the PETSc runs only (e.g. --petsc-arg=--linear-solver --petsc-arg=cg-gamg)")
    ap.add_argument("--iterative", type=float, default=0,
                    help="the PETSc runs use an iterative solver stopped at a relative residual r: numbers agree "
                         "to the given relative tolerance (about cond(K) r), residuals to 1e-8 (the runs' "
                         "tolerance), iteration counts are not compared")
    ap.add_argument("--tolerance", type=float, default=0,
                    help="numbers agree to this relative tolerance instead of 1e-10 (everything else as without it)")
    ap.add_argument("case", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    if a.iterative > 0:
        REL, RESIDUAL_ABS, ITERATIVE = a.iterative, 1e-8, True
    if a.tolerance > 0:
        REL = a.tolerance
    case = [x for x in a.case if x != "--"]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    ok = True

    serial_dir = os.path.join(a.work, "serial")
    extra = ["--no-plot"] if a.command == "converge" else []
    p, secs = run([a.vpcontact, a.command, *case, *extra, "--engine", "serial", "-q", "-o", serial_dir], env)
    print(f"serial: exit {p.returncode}, {secs:.2f} s")
    if p.returncode != 0:
        print(p.stdout + p.stderr)
        print("equivalence: FAILED (the serial run failed)")
        return 1
    for ranks in [int(r) for r in a.ranks.split(",")]:
        out = os.path.join(a.work, f"np{ranks}")
        p, secs = run([a.mpiexec, "-n", str(ranks), "--oversubscribe", a.vpcontact, a.command, *case, *extra, *a.petsc_arg,
                       "--engine", "petsc", "-q", "-o", out], env)
        text = p.stdout + p.stderr
        if p.returncode != 0:
            print(f"PETSc on {ranks} ranks: exit {p.returncode}\n{text}")
            ok = False
            continue
        rep = Report()
        if a.command == "converge":
            what = f"{compare_convergence(rep, serial_dir, out)} convergence tables"
        else:
            what = f"{compare_runs(rep, serial_dir, out, ranks)} VTU steps, history, probes, summary"
        worst = max(rep.worst.values(), default=0.0)
        print(f"PETSc on {ranks} rank{'s' if ranks > 1 else ''}: {secs:.2f} s; {what}: "
              f"{'match' if not rep.failures else 'DIFFER'} (largest |diff| / tolerance {worst:.2e})")
        for f in rep.failures[:20]:
            print("  differs: " + f)
        if len(rep.failures) > 20:
            print(f"  ... and {len(rep.failures) - 20} more")
        ok &= not rep.failures
    print(f"equivalence: {'PASSED' if ok else 'FAILED'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
