"""vpcontact from Python: quasistatic frictionless Signorini contact of an
elastic-viscoplastic body with damage (Fernandez & Sofonea 2003).

The module drives the C++ library: its case reader, its run loop (the one
`vpcontact run` uses) and its TimeStepper. docs/python.md documents it.

    import vpcontact
    case = vpcontact.Case("paper-2d", n=20)
    case.set("damage.kappa", 0.1)
    sim = vpcontact.run(case, output="out/k01")        # as `vpcontact run -o out/k01`
    sim.beta, sim.sigma, sim.history()                  # numpy views and tables

    sim = vpcontact.Simulation(case)                    # step by step (no output: no files)
    while not sim.done:
        report = sim.step()                             # history.csv's numbers of the step
"""

import numbers as _numbers
import operator as _operator
import os as _os

# The command line runs with passive OpenMP waiting (app/process_policy.cpp: spinning
# workers steal the core the next solve needs on a shared machine); libgomp reads the
# variable when it is loaded, which is when _core is imported just below.
_os.environ.setdefault("OMP_WAIT_POLICY", "passive")

from . import _core  # noqa: E402
from ._core import builtin_cases, case_text  # noqa: E402
from .errors import BusyError, CaseError, Error, RunError  # noqa: E402
from .results import Fields, Results, read  # noqa: E402
from .tables import table as _table  # noqa: E402

__version__ = _core.__version__
__all__ = ["Case", "Simulation", "run", "read", "plot", "builtin_cases", "case_text", "toml_value",
           "Results", "Fields", "Error", "CaseError", "RunError", "BusyError", "state_fields",
           "history_column_table"]


def state_fields():
    """The table of the state's fields the library declares once (src/io/state_fields.hpp): a list
    of dicts with name, python (the attribute of Simulation and Fields), vtu (the VTU array, as
    [output] fields names it), location (node, cell, contact node), stored (a view of the state)
    and meaning."""
    return _core._state_fields()


def history_column_table():
    """The table of history.csv's columns (src/io/history_columns.hpp): a list of dicts with
    name, format (integer, exact, residual: 4 digits in the file), meaning and friction. Every
    run has those with friction False, in order; a run adds force_<obstacle> and
    reaction_<part>_<x|y|z> after them, and a frictional run then those with friction True
    and tangential_force_<x|y|z>, tangential_force_<obstacle>_<x|y|z>
    (Simulation.history_columns)."""
    return _core._history_column_table()


def toml_value(value):
    """A Python value as TOML text for Case.set: bool, int, float, str, list/tuple, dict."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if value != value:
            return "nan"
        if value in (float("inf"), float("-inf")):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        import json

        return json.dumps(value)  # a TOML basic string (\uXXXX escapes are TOML's too)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join("%s = %s" % (k, toml_value(v)) for k, v in value.items()) + "}"
    try:  # numpy scalars
        return toml_value(value.item())
    except AttributeError:
        raise TypeError("no TOML value for %r (of type %s)" % (value, type(value).__name__)) from None


class Case(_core.Case):
    """A case: a built-in case by name (builtin_cases()), a case file (a path), or TOML
    text (text=..., with the name used in messages and base_dir for relative mesh files).

    Every change is checked at once by the library's case reader, with the command
    line's located errors (CaseError: file, line, key):
        case.set("damage.kappa", 0.1)            # --set damage.kappa=0.1
        case.set({"damage.kappa": 0.1, "time.steps": 20})
        case.n = 20                              # --n 20 (generated meshes): 20 cells along
                                                 # every edge, whatever the domain's aspect
        case.kappa = 0.1; case.steps = 20; case.dt = 0.05
    """

    def __init__(self, source, *, text=None, base_dir=".", n=None, set=None, kappa=None, steps=None, dt=None):
        if isinstance(source, _core.Case):
            super().__init__(source)
        else:
            super().__init__(_os.fspath(source), text, _os.fspath(base_dir))
        if n is not None:
            self.n = n
        changes = dict(set or {})
        for key, v in (("damage.kappa", kappa), ("time.steps", steps), ("time.dt", dt)):
            if v is not None:
                changes[key] = v
        if changes:
            self.set(changes)

    def set(self, key, value=None):
        """Overrides keys, as --set key=value: set("damage.kappa", 0.1) or set({key: value, ...}).
        A value is a Python value (toml_value), or TOML text given as set("key=value")."""
        if isinstance(key, dict):
            sets = ["%s=%s" % (k, toml_value(v)) for k, v in key.items()]
        elif value is None and "=" in key:
            sets = [key]
        else:
            sets = ["%s=%s" % (key, toml_value(value))]
        self._add_sets(sets)
        return self

    def copy(self):
        return Case(self)

    def _set_n(self, n):
        # the range is the case reader's (--n); the type is said here, not as pybind11's overloads
        _core.Case.n.fset(self, None if n is None else _integer("Case.n", "n", n, "an integer or None"))

    n = property(_core.Case.n.fget, _set_n, doc=_core.Case.n.__doc__)
    kappa = property(_core.Case.kappa.fget, lambda self, v: self.set("damage.kappa", v), doc="damage.kappa")
    steps = property(_core.Case.steps.fget, lambda self, v: self.set("time.steps", v), doc="time.steps")
    dt = property(_core.Case.dt.fget, lambda self, v: self.set("time.dt", v), doc="time.dt")

    def __repr__(self):
        extra = "".join(", --set " + s for s in self.sets)
        if self.n is not None:
            extra += ", n=%d" % self.n
        return "<vpcontact.Case %s (%s)%s>" % (self.name, self.source, extra)


class Simulation(_core.Simulation):
    """The run loop of `vpcontact run`, step by step.

        sim = Simulation(case, output=None)  # output: a directory for the run's files
                                             # (VTU, history.csv, probes.csv, checkpoints,
                                             # summary.json); True: the case's own directory
                                             # (case.output_directory); None: no files
        sim.step()                           # one step; its report (history.csv's numbers);
                                             # RunError once the run is at T (sim.done)
        sim.run(progress=True)               # the remaining steps, then finish()
        sim.checkpoint(); sim.finish()
        Simulation(case, output=dir, resume=True)  # continues from dir's newest checkpoint

    Views (read-only numpy arrays that follow the steps): the state's fields (fields():
    u, beta, sigma, eps, z, contact_force; with friction (frictional) slip_step, slip,
    contact_status per contact node); points, cells, facets. Copies: the output fields as
    the VTU files have them (contact_force_vector, contact_pressure, von_mises; with
    friction tangential_force, tangential_traction, slip_increment),
    active, contact_nodes, contact_directions, facet_parts, free_dofs, boundary_parts,
    matrices(). state_fields() and history_column_table() list the fields and columns.

    One caller at a time: a call made while another call of the same Simulation is in
    progress in another thread (a step releases the GIL) raises BusyError naming that call
    and its thread; so does a step, checkpoint or finish() from run()'s progress callback.
    """

    def __init__(self, case, output=None, *, resume=False, quiet=True, checkpoint_every=-1,
                 checkpoint_seconds=60.0, halvings=0):
        if not isinstance(case, _core.Case):
            case = Case(case)
        # the ranges are checked by _core (CaseError), the types here
        checkpoint_every = _integer("Simulation", "checkpoint_every", checkpoint_every, "an integer")
        halvings = _integer("Simulation", "halvings", halvings, "an integer")
        if isinstance(checkpoint_seconds, bool) or not isinstance(checkpoint_seconds, _numbers.Real):
            raise TypeError("Simulation: checkpoint_seconds must be a number (got %r)" % (checkpoint_seconds,))
        super().__init__(case, _output_directory(case, output), resume, quiet,
                         checkpoint_every, float(checkpoint_seconds), halvings)
        self.case = Case(case)

    def step(self, count=1):
        """Advances `count` steps (an integer >= 1; fewer where fewer are left before T);
        returns the last one's report. Raises RunError when no step is left (sim.done: the
        run is at T), ValueError for a count < 1."""
        count = _count("Simulation.step(count)", "count", count)
        with self._hold("Simulation.step()"):
            if self.done:
                raise RunError("the simulation is at its final time (step %d, t = T = %g): there is no step after "
                               "the last (sim.done is True)" % (self.n, self.final_time))
            for _ in range(count):
                if self.done:
                    break
                self._step()
            return self.report

    @property
    def report(self):
        """The last step's numbers, history.csv's columns (a dict column -> number: an int
        where the file writes an integer, else the float itself); None before a step."""
        row = self._last_row
        return None if row is None else dict(zip(self._history_columns, row))

    @property
    def history_columns(self):
        return list(self._history_columns)

    def history(self, frame=None):
        """The reports of the steps taken by this object, as history.csv's table
        (a structured array, or a DataFrame where pandas is installed: tables.table)."""
        return _table(self._history_columns, self._rows, frame)

    def run(self, progress=None):
        """Runs the remaining steps and finishes (summary.json). progress: None or False
        (nothing), True (a bar: tqdm where installed), or a callable given each report; it
        may read the simulation (sim.u, sim.t, ...), not step it (BusyError).
        On KeyboardInterrupt a run with output writes a checkpoint and summary.json
        first (resume with Simulation(case, output=dir, resume=True))."""
        if not (progress is None or isinstance(progress, bool) or callable(progress)):
            raise TypeError("Simulation.run(progress): progress must be None, False, True or a callable given each "
                            "step's report (got %r)" % (progress,))
        with self._hold("Simulation.run()") as held:
            if progress is True:
                from .progress import bar

                progress = bar(self.final_time, self.t)
            try:
                while not self.done:
                    self._step()
                    if progress:
                        report = self.report
                        with held.callback():  # the user's code: it may read, not step
                            progress(report)
            except KeyboardInterrupt:
                if self.output is not None and not self.finished:
                    self.checkpoint()
                self.finish()
                raise
            finally:
                if progress and hasattr(progress, "close"):
                    with held.callback():
                        progress.close()
            self.finish()
        return self

    @property
    def active(self):
        """Whether each contact node is in contact (its normal force, the first of contact_force's
        numbers per node, > 0), a copy."""
        f = self.contact_force
        return (f if f.ndim == 1 else f[:, 0]) > 0

    @property
    def boundary_parts(self):
        """The boundary parts: name -> the sorted nodes of its facets (copies)."""
        import numpy as np

        facets, parts = self.facets, self.facet_parts
        return {name: np.unique(facets[parts == i]) for i, name in enumerate(self.part_names)}

    def fields(self):
        """The state's views by name (the stored fields of state_fields(): u, beta, contact_force,
        sigma, eps, z; with friction also slip_step, slip, contact_status)."""
        return {f["python"]: getattr(self, f["python"]) for f in state_fields()
                if f["stored"] and f["python"] and (self.frictional or not f["friction"])}

    def matrices(self):
        """The constant matrices as scipy.sparse.csr_matrix (copies; scipy needed): K (the
        stiffness over the free dofs: free_dofs), M and A (the P1 mass and Laplacian over the
        nodes: the damage matrix is M + k kappa A), N (the contact rows, contact_nodes order,
        over the free dofs)."""
        try:
            import scipy.sparse as sp
        except ImportError:
            raise ImportError("Simulation.matrices() needs scipy (Debian: python3-scipy)") from None
        out = {}
        for name, (data, indices, indptr, shape) in self._matrices().items():
            out[name] = sp.csc_matrix((data, indices, indptr), shape=shape).tocsr()
        return out

    def results(self):
        """The output directory read back (Results); the run must have output."""
        if self.output is None:
            raise RunError("this simulation writes no files (output=None)")
        return read(self.output)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.finish()
        return False

    def __repr__(self):
        of = " of %d" % self.n_steps if self.n_steps else ""  # None: error-controlled step sizes
        return "<vpcontact.Simulation %s: step %d%s, t = %g of %g>" % (self.case.name, self.n, of, self.t, self.final_time)


def _integer(call, name, value, expected):
    """`value` as an int (a Python or numpy integer, not a bool, a float or a NaN), else a
    TypeError naming the argument and what is `expected` of it."""
    if isinstance(value, bool) or not hasattr(type(value), "__index__"):
        raise TypeError("%s: %s must be %s (got %r)" % (call, name, expected, value))
    return _operator.index(value)


def _count(call, name, value):
    """`value` as an int >= 1 (a number of steps), else TypeError or ValueError naming the
    argument: a count of 0, -1 or NaN is a mistake, not a request for nothing."""
    expected = "an integer >= 1"
    value = _integer(call, name, value, expected)
    if value < 1:
        raise ValueError("%s: %s must be %s (got %d)" % (call, name, expected, value))
    return value


def _output_directory(case, output):
    """The rule of run() and Simulation() alike: files only where output is given; True
    stands for the case's own directory (case.output_directory: what `vpcontact run`
    writes without -o)."""
    if output is None or output is False:
        return None
    if output is True:
        return case.output_directory
    return _os.fspath(output)


def run(case, output=None, *, progress=False, quiet=True, **options):
    """Runs a case as `vpcontact run` does and returns the finished Simulation.
    output: the directory for the run's files; True: the case's own ([output] directory,
    else output/NAME); None (default): no files, as Simulation(case);
    progress: see Simulation.run; quiet=False prints the command line's header and
    set-up stages; options: those of Simulation (checkpoint_every, halvings, ...)."""
    if not isinstance(case, _core.Case):
        case = Case(case)
    sim = Simulation(case, output, quiet=quiet, **options)
    return sim.run(progress)


def plot(outdir, format="png", dpi=150):
    """Draws the figures of a run's output directory into outdir/figures/ as `vpcontact
    plot` does (the same script); returns their paths. Needs matplotlib."""
    from . import _plot

    outdir = _os.path.normpath(_os.fspath(outdir))
    try:
        run_ = _plot.Run(outdir)
        _plot.Plotter(run_, format, float(dpi)).all()
    except _plot.PlotError as e:
        raise RunError(str(e)) from None
    figures = _os.path.join(outdir, "figures")
    return sorted(_os.path.join(figures, f) for f in _os.listdir(figures) if f.endswith("." + format))
