"""Tables of numbers by their column names: history.csv and probes.csv (of a run
on disk, or of a Simulation's steps) as numpy structured arrays, or as pandas
DataFrames where pandas is installed.

Columns are found by the header's names, never by position, so columns that a
newer vpcontact adds to history.csv appear here without a change.
"""

import numpy as np

__all__ = ["value", "record", "table", "read_csv", "have_pandas"]


def value(token):
    """A CSV field as a number: an int where it is written as one, else a float."""
    try:
        return int(token)
    except ValueError:
        return float(token)


def record(columns, row):
    """One CSV row (a string without its newline) as a dict column -> number."""
    fields = row.split(",")
    if len(fields) != len(columns):
        raise ValueError("a row of %d fields for %d columns" % (len(fields), len(columns)))
    return {c: value(f) for c, f in zip(columns, fields)}


def have_pandas():
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def table(columns, rows, frame=None):
    """Rows of CSV fields (lists of strings) or of numbers (a Simulation's reports) as a
    structured array with one field per column (int64 where every entry is an integer,
    else float64), or a pandas DataFrame: frame=True (pandas needed), False (never), None
    (when pandas is installed)."""
    if frame is None:
        frame = have_pandas()
    data = {}
    for j, c in enumerate(columns):
        entries = [value(r[j]) if isinstance(r[j], str) else r[j] for r in rows]
        if all(isinstance(v, int) for v in entries):
            data[c] = np.array(entries, dtype=np.int64)
        else:
            data[c] = np.array(entries, dtype=np.float64)
    if frame:
        import pandas

        return pandas.DataFrame(data, columns=list(columns))
    out = np.empty(len(rows), dtype=[(c, data[c].dtype) for c in columns])
    for c in columns:
        out[c] = data[c]
    return out


def read_csv(path, frame=None):
    """A CSV file with a header line (history.csv, probes.csv) as table()."""
    with open(path) as f:
        lines = [line.rstrip("\n") for line in f]
    if not lines or not lines[0]:
        raise ValueError("%s: no header line" % path)
    columns = lines[0].split(",")
    rows = []
    for i, line in enumerate(lines[1:], start=2):
        if not line:
            continue
        fields = line.split(",")
        if len(fields) != len(columns):
            raise ValueError("%s:%d: %d fields, the header has %d" % (path, i, len(fields), len(columns)))
        rows.append(fields)
    return table(columns, rows, frame)
