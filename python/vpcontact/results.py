"""A finished run's output directory read back into numpy: summary.json, history.csv
and probes.csv by their column names, and the fields of any output time from the
VTU files, as the arrays a Simulation has. The VTU files are read by the figures
script's reader (scripts/vpcontact_plot.py, shipped as vpcontact._plot): one reader
for the figures and for Python.
"""

import json
import math
import numbers
import os

import numpy as np

from . import _plot
from .errors import RunError
from .tables import read_csv

__all__ = ["Results", "Fields", "read", "VTK_TO_SYM"]

# The VTU tensors are in VTK's order XX, YY, ZZ, XY, YZ, XZ (io/vtu_writer.cpp: tensor_field);
# State's SymTensor is 11, 22, 33, 23, 13, 12.
VTK_TO_SYM = [0, 1, 2, 4, 5, 3]


class Fields:
    """The state at one output time, as a Simulation shows it: t, n, points (n_nodes, 3),
    cells (n_cells, d + 1), and each field of the library's table (vpcontact.state_fields())
    that the VTU files hold, by its Python name: u (n_nodes, d), beta (n_nodes,), sigma, eps,
    z (n_cells, 6 in the order 11, 22, 33, 23, 13, 12), von_mises (n_cells,),
    contact_force_vector (the point field -lambda nu, (n_nodes, 3)), contact_pressure
    (n_nodes,), contact_force (lambda's block at each node, written where it has more than
    one number); with friction tangential_force, tangential_traction, slip_increment
    (n_nodes, 3) and slip, contact_status (n_nodes,; zero off the contact boundary); with
    contact pairs gap (n_nodes,: g - N u on both sides of each pair; contact_pressure is then on
    both sides too); active
    (the nodes with a contact pressure > 0). Fields the run did not write ([output] fields,
    friction's without friction) are None; `arrays` holds every VTU array by its VTU name."""

    def __init__(self, t, n, vtu, dim, bodies=("body",)):
        from . import state_fields

        self.t = t
        self.n = n
        self.bodies = list(bodies)
        self.points = vtu.points
        self.cells = vtu.cells
        self.arrays = dict(vtu.point_data)
        self.arrays.update(vtu.cell_data)
        for f in state_fields():
            if not f["vtu"] or not f["python"]:
                continue
            v = self.arrays.get(f["vtu"])
            if v is None and f["vtu"] == "beta":
                v = self.arrays.get("damage")  # beta's name in earlier versions
            if v is not None and f["name"] == "u":
                v = np.ascontiguousarray(v[:, :dim])  # VTU vectors have 3 components
            elif v is not None and f["location"] == "cell" and v.ndim == 2 and v.shape[1] == 6:
                v = np.ascontiguousarray(v[:, VTK_TO_SYM])
            setattr(self, f["python"], v)
        self.active = None if self.contact_pressure is None else self.contact_pressure > 0

    def body(self, which):
        """The fields of one body (SPEC §8, [[body]]): `which` its name ("body" for the case's
        [mesh]) or its index. Its points and cells (renumbered from 0), and every node and cell
        field restricted to them; `nodes` and `cell_ids` are their numbers in the whole."""
        import copy

        k = which if isinstance(which, (int, np.integer)) else None
        if k is None:
            if which not in self.bodies:
                raise ValueError("no body %r: the run's bodies are %s" % (which, ", ".join(self.bodies)))
            k = self.bodies.index(which)
        if not 0 <= k < len(self.bodies):
            raise ValueError("no body %d: the run has %d" % (k, len(self.bodies)))
        of_cell = self.arrays.get("body")
        in_body = np.ones(len(self.cells), bool) if of_cell is None else np.asarray(of_cell).reshape(-1) == k
        nodes = np.unique(self.cells[in_body])
        renumber = np.full(len(self.points), -1, dtype=np.int64)
        renumber[nodes] = np.arange(len(nodes))
        view = copy.copy(self)
        n_nodes, n_cells = len(self.points), len(self.cells)
        for name, value in vars(self).items():
            if isinstance(value, np.ndarray) and value.ndim >= 1 and name not in ("points", "cells"):
                if value.shape[0] == n_nodes:
                    setattr(view, name, value[nodes])
                elif value.shape[0] == n_cells:
                    setattr(view, name, value[in_body])
        view.arrays = {}
        for name, value in self.arrays.items():
            value = np.asarray(value)
            view.arrays[name] = value[nodes] if value.shape[0] == n_nodes else value[in_body] if value.shape[0] == n_cells else value
        view.points = self.points[nodes]
        view.cells = renumber[self.cells[in_body]]
        view.nodes = nodes
        view.cell_ids = np.flatnonzero(in_body)
        view.bodies = [self.bodies[k]]
        return view

    def __repr__(self):
        return "<vpcontact.Fields t=%g n=%s: %d nodes, %d cells>" % (self.t, self.n, len(self.points), len(self.cells))


class Results:
    """A run's output directory (vpcontact run, vpcontact.run or a Simulation with output=).

    summary: summary.json as a dict; bodies: the bodies' names ("body", then each [[body]]'s;
    Fields.body(name) restricts an output time's fields to one); history(), probes(): the CSV files as tables
    (structured arrays, or DataFrames: see tables.table); times, steps: the output
    times and their steps; fields(t=None, index=None): the state at the output time
    nearest t, or the index-th output (default: the last)."""

    def __init__(self, outdir):
        self.directory = os.fspath(outdir)
        summary = os.path.join(self.directory, "summary.json")
        try:
            with open(summary) as f:
                self.summary = json.load(f)
        except OSError as e:
            raise RunError("%s: %s (is this a vpcontact output directory?)" % (summary, e.strerror), file=summary)
        except ValueError as e:
            raise RunError("%s: not valid JSON: %s" % (summary, e), file=summary)
        self.dim = int(self.summary.get("dimension", 0))
        # The bodies (SPEC §8): "body" (the case's [mesh]), then each [[body]]'s name.
        self.bodies = [b["name"] for b in self.summary.get("bodies", [])] or ["body"]
        try:
            probes = _plot.read_csv(os.path.join(self.directory, "probes.csv"))
            self._solutions = _plot.list_solutions(self.directory, probes)
        except _plot.PlotError as e:
            raise RunError(str(e))
        self.times = np.array([t for t, _ in self._solutions])
        self.steps = [_step_of(p) for _, p in self._solutions]

    def history(self, frame=None):
        return read_csv(os.path.join(self.directory, "history.csv"), frame)

    def probes(self, frame=None):
        return read_csv(os.path.join(self.directory, "probes.csv"), frame)

    def fields(self, t=None, index=None):
        if not self._solutions:
            raise RunError("%s: no VTU output (output.vtu = false?)" % self.directory)
        if t is not None and index is not None:
            raise ValueError("give t or index, not both")
        k = len(self._solutions)
        if index is not None:
            if isinstance(index, bool) or not hasattr(type(index), "__index__"):
                raise TypeError("Results.fields(index): index must be an integer (got %r)" % (index,))
            if not -k <= index < k:
                raise IndexError("Results.fields(index): index must be in [%d, %d): %d outputs (got %d)"
                                 % (-k, k, k, index))
        elif t is None:
            index = -1
        else:
            # a NaN would pick the first output silently (argmin of NaNs)
            if isinstance(t, bool) or not isinstance(t, numbers.Real) or not math.isfinite(t):
                raise ValueError("Results.fields(t): t must be a finite time (got %r)" % (t,))
            index = int(np.argmin(np.abs(self.times - t)))
        time, path = self._solutions[index]
        try:
            vtu = _plot.read_vtu(path)
        except _plot.PlotError as e:
            raise RunError(str(e), file=path)
        return Fields(time, self.steps[index], vtu, self.dim, self.bodies)

    def __repr__(self):
        return "<vpcontact.Results %s: %s, %d outputs>" % (self.directory, self.summary.get("case"), len(self.times))


def _step_of(path):
    stem = os.path.basename(path).split(".")[0]
    try:
        return int(stem.split("_")[1])
    except (IndexError, ValueError):
        return None


def read(outdir):
    """The output directory of a finished (or interrupted) run."""
    return Results(outdir)
