"""The built-in cases through Python give the numbers of the command line, bit for
bit: the same history.csv, probes.csv and VTU files, and summary.json's numbers."""

import json
import os

import numpy as np
import pytest

import vpcontact
from conftest import read

# summary.json entries that say when, how fast and by which command a run was made.
NOT_NUMBERS = {"timing_seconds", "setup_seconds", "memory_bytes", "vpcontact"}


def same_files(a, b):
    files = sorted(f for f in os.listdir(a) if f.endswith((".csv", ".vtu", ".pvd")))
    assert files == sorted(f for f in os.listdir(b) if f.endswith((".csv", ".vtu", ".pvd")))
    assert "history.csv" in files
    for f in files:
        assert read(os.path.join(a, f)) == read(os.path.join(b, f)), f
    sa, sb = (json.load(open(os.path.join(d, "summary.json"))) for d in (a, b))
    for k in NOT_NUMBERS:
        sa.pop(k), sb.pop(k)
    assert sa == sb


@pytest.mark.parametrize(
    "name, cli_args, changes",
    [
        ("paper-1d", [], {}),
        ("paper-2d", ["--n", 10, "--steps", 8, "--every", 4], {"n": 10, "steps": 8, "set": {"output.every": 4}}),
        ("paper-2d", ["--n", 10, "--steps", 5, "--set", "damage.kappa=0.1"], {"n": 10, "steps": 5, "kappa": 0.1}),
        ("block-3d", ["--n", 5, "--steps", 3], {"n": 5, "steps": 3}),
    ],
)
def test_run_equals_command_line(tmp_path, cli, name, cli_args, changes):
    cli("run", name, "-q", "--engine", "serial", "-o", tmp_path / "cli", *cli_args)
    sim = vpcontact.run(vpcontact.Case(name, **changes), output=tmp_path / "py")
    assert sim.done and sim.finished
    same_files(tmp_path / "cli", tmp_path / "py")


def history_text(row, columns):
    """A report's numbers as history.csv writes them (the formats of the library's column table)."""
    formats = {c["name"]: c["format"] for c in vpcontact.history_column_table()}
    text = {"integer": lambda v: "%d" % v, "exact": lambda v: "%.17g" % v, "residual": lambda v: "%.3e" % v}
    return ",".join(text[formats.get(c, "exact")](v) for c, v in zip(columns, row))


def test_steps_without_output_equal_history(tmp_path, cli, monkeypatch):
    """Simulation without files, stepped one by one: its reports are history.csv's numbers
    (numbers, not text: the residuals unrounded, each written as the file writes it)."""
    cli("run", "paper-2d", "-q", "--engine", "serial", "--n", 10, "--steps", 6, "--no-vtu", "-o", tmp_path / "cli")
    lines = open(tmp_path / "cli" / "history.csv").read().splitlines()
    (tmp_path / "cwd").mkdir()
    monkeypatch.chdir(tmp_path / "cwd")
    sim = vpcontact.Simulation(vpcontact.Case("paper-2d", n=10, steps=6))
    assert sim.output is None and sim.history_columns == lines[0].split(",")
    while not sim.done:
        report = sim.step()
        assert report["step"] == sim.n and report["t"] == sim.t
        assert all(isinstance(v, (int, float)) for v in report.values())
        assert history_text([report[c] for c in sim.history_columns], sim.history_columns) == lines[sim.n]
        # The file's numbers exactly, but for the residuals it rounds
        residual = {c["name"] for c in vpcontact.history_column_table() if c["format"] == "residual"}
        parsed = vpcontact.tables.record(sim.history_columns, lines[sim.n])
        assert {c: v for c, v in report.items() if c not in residual} == {
            c: v for c, v in parsed.items() if c not in residual}
    assert [history_text(r, sim.history_columns) for r in sim._rows] == lines[1:]
    h = sim.history(frame=False)
    assert h.dtype.names == tuple(sim.history_columns) and len(h) == 6
    assert h["beta_min"][-1] == float(lines[-1].split(",")[sim.history_columns.index("beta_min")])
    sim.finish()
    assert os.listdir(".") == []  # no output directory: nothing written


def test_kappa_property_and_set_agree(tmp_path):
    a = vpcontact.Case("paper-2d", n=10, steps=4)
    b = a.copy()
    a.kappa = 0.25
    b.set("damage.kappa", 0.25)
    assert a.kappa == b.kappa == 0.25 and a.sets == b.sets == ["time.steps=4", "damage.kappa=0.25"]
    ra = vpcontact.Simulation(a)
    rb = vpcontact.Simulation(b)
    ra.step(4), rb.step(4)
    assert ra._rows == rb._rows
    assert np.array_equal(ra.beta, rb.beta)
