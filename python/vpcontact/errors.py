"""The exceptions of vpcontact: the library's errors (vpc::Error) with their location.

The library's messages say where the error is: ``file:line:column: key: what``
for a value in a case file, ``--set key=value: what`` or ``--set key: what`` for
an override, ``file: missing key 'x.y': ...`` for a key that is missing. The
exceptions carry that location as attributes (None where the message has none);
``str(error)`` is the whole message.
"""

import re

__all__ = ["Error", "CaseError", "RunError", "BusyError", "from_message"]


class Error(Exception):
    """An error of vpcontact's library.

    Attributes: ``message`` (the whole message, also ``str(error)``), ``file``,
    ``line``, ``column`` (ints) and ``key`` (a dotted key path such as
    ``damage.kappa``), each None where the message does not say.
    """

    def __init__(self, message, file=None, line=None, column=None, key=None):
        super().__init__(message)
        self.message = message
        self.file = file
        self.line = line
        self.column = column
        self.key = key


class CaseError(Error, ValueError):
    """A bad case file, override or option: what ``vpcontact run`` reports as
    ``vpcontact: error: ...`` before it starts."""


class RunError(Error, RuntimeError):
    """A run that cannot go on: a step that failed (the solvers did not converge,
    NaN in the data) or no checkpoint to resume from."""


class BusyError(Error, RuntimeError):
    """A call of a Simulation refused because another call of it is in progress: a
    Simulation is driven from one thread at a time (docs/python.md, "Threads"). Raised in
    the second caller's thread; the first call goes on unharmed. Also a step, checkpoint or
    finish() asked for from run()'s progress callback. Attributes: ``call``, the call in
    progress (e.g. ``"Simulation.run()"``), and ``thread``, its thread's name."""

    def __init__(self, message, call=None, thread=None):
        super().__init__(message)
        self.call = call
        self.thread = thread


# file:line:column: rest
_AT_LINE = re.compile(r"^(?P<file>[^\n]+?):(?P<line>\d+):(?P<column>\d+): (?P<rest>.*)$", re.S)
# file: rest (a case file, or a built-in case "NAME.toml (built-in)")
_AT_FILE = re.compile(r"^(?P<file>[^\n:]+?\.toml(?: \(built-in\))?): (?P<rest>.*)$", re.S)
# --set key=value or --set key, and the options that stand for one key
_SET = re.compile(r"^--set (?P<key>[^=:\s]+)")
_OPTIONS = {"--kappa": "damage.kappa", "--steps": "time.steps", "--dt": "time.dt", "--n": "mesh.cells"}
# a key path at the start of the rest: damage.kappa, mesh.part[0].where
_KEY = re.compile(r"^(?P<key>[A-Za-z_][\w-]*(?:\[\d+\])?(?:\.[A-Za-z_][\w-]*(?:\[\d+\])?)*)(?::|$)")
_UNKNOWN = re.compile(r"unknown key '(?P<key>[^']+)'(?: in \[(?P<section>[^\]]+)\])?")
_MISSING = re.compile(r"missing key '(?P<key>[^']+)'")


def location(message):
    """(file, line, column, key) of a library message; None for what it does not say."""
    file = line = column = key = None
    rest = message
    m = _AT_LINE.match(message)
    if m:
        file, line, column, rest = m["file"], int(m["line"]), int(m["column"]), m["rest"]
    else:
        m = _AT_FILE.match(message)
        if m:
            file, rest = m["file"], m["rest"]
    m = _SET.match(message)
    if m:
        key = m["key"]
    for option, k in _OPTIONS.items():
        if message.startswith(option + " ") or message.startswith(option + ":"):
            key = k
    if key is None:
        m = _UNKNOWN.search(rest)
        if m:
            key = m["key"] if not m["section"] else m["section"] + "." + m["key"]
    if key is None:
        m = _MISSING.search(rest)
        if m:
            key = m["key"]
    if key is None and file is not None:
        m = _KEY.match(rest)
        if m and " " not in m["key"]:
            key = m["key"]
    return file, line, column, key


def from_message(message, kind="case"):
    """The exception for a library message: CaseError, or RunError for kind "run"."""
    cls = RunError if kind == "run" else CaseError
    return cls(message, *location(message))
