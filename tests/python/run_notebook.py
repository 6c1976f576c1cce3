#!/usr/bin/python3
"""Runs a Jupyter notebook's code cells in order, in one namespace, with plain Python
(no Jupyter needed): a cell that raises fails the run, naming the cell. Lines that are
IPython magics or shell escapes (%..., !...) are not Python and are refused.

    /usr/bin/python3 tests/python/run_notebook.py NOTEBOOK.ipynb
"""
import json
import os
import sys


def run(path):
    os.environ.setdefault("MPLBACKEND", "Agg")
    with open(path) as f:
        notebook = json.load(f)
    namespace = {"__name__": "__main__", "__file__": path}
    n = 0
    for i, cell in enumerate(notebook["cells"]):
        if cell["cell_type"] != "code":
            continue
        source = "".join(cell["source"])
        for line in source.splitlines():
            if line.lstrip().startswith(("%", "!")):
                raise SystemExit("%s: cell %d: IPython syntax '%s' is not Python" % (path, i, line.strip()))
        exec(compile(source, "%s [cell %d]" % (path, i), "exec"), namespace)
        n += 1
    print("%s: %d code cells ran" % (path, n))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    run(sys.argv[1])
