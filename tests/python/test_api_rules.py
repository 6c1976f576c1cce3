"""Issue 26 item 21: one rule for the files of run() and Simulation(), no step after the
last, N of an error-controlled run, what case.n does to a non-square domain, and the VTU
cell field `material` read back as integers."""

import os

import numpy as np
import pytest

import vpcontact


def files_under(path):
    return sorted(os.path.relpath(os.path.join(d, f), path) for d, _, fs in os.walk(path) for f in fs)


def test_run_and_simulation_write_files_only_where_output_is_given(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    case = vpcontact.Case("paper-1d", steps=4)
    sim = vpcontact.run(case)
    assert sim.done and sim.output is None
    vpcontact.Simulation(case).run()
    assert files_under(tmp_path) == []  # neither wrote anything
    sim = vpcontact.run(case, output=True)  # True: the case's own directory, as `vpcontact run` without -o
    assert sim.output == case.output_directory == os.path.join("output", "paper-1d")
    assert os.path.isfile(tmp_path / "output" / "paper-1d" / "summary.json")
    sim = vpcontact.Simulation(case, output=tmp_path / "here").run()
    assert os.path.isfile(tmp_path / "here" / "history.csv")


def test_a_step_after_the_last_raises():
    sim = vpcontact.Simulation(vpcontact.Case("paper-1d", steps=3))
    assert sim.step(10)["step"] == 3  # fewer than asked: those left
    assert sim.done
    with pytest.raises(vpcontact.RunError, match=r"at its final time \(step 3, t = T = 1\): there is no step after"):
        sim.step()


def test_n_steps_of_an_error_controlled_run_is_none():
    case = vpcontact.Case("paper-1d", set={"time.tolerance": 1e-2})
    assert case.steps is None
    sim = vpcontact.Simulation(case)
    assert sim.n_steps is None
    sim.step(2)
    assert sim.n == 2 and "step 2, t = " in repr(sim)  # no "step 2 of N"
    assert vpcontact.Simulation(vpcontact.Case("paper-1d", steps=7)).n_steps == 7


def test_n_sets_the_cells_along_every_edge_whatever_the_aspect():
    text = vpcontact.case_text("paper-2d")
    case = vpcontact.Case("wide.toml", text=text.replace("upper = [2.0, 2.0]", "upper = [2.0, 1.0]"))
    case.n = 10  # as --n 10: 10 x 10 cells (documented), not the file's aspect
    assert case.n_cells == 2 * 10 * 10
    assert "whatever the domain's aspect" in vpcontact.Case.n.__doc__


def test_material_is_an_integer_cell_field(tmp_path):
    text = vpcontact.case_text("paper-2d") + """
[[material]]
name = "left"
where = "x < 1"
[material.elasticity]
E = 2.0
nu = 0.3
"""
    case = vpcontact.Case("two.toml", text=text, n=10, steps=2)
    vpcontact.run(case, output=tmp_path)
    fields = vpcontact.read(tmp_path).fields(-1)
    m = fields.arrays["material"]
    assert m.dtype.kind == "i", m.dtype
    assert set(np.unique(m)) == {0, 1}
