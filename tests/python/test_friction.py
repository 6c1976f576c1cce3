"""Friction's outputs from Python (issue 28): a frictional Simulation's views of the slip
fields and copies of the tangential vectors are the VTU files' arrays, its reports have
friction's columns (those of history.csv), and Results reads them back."""

import os

import numpy as np
import pytest

import vpcontact

CASE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "friction-2d.toml")


@pytest.fixture
def sim(tmp_path):
    return vpcontact.Simulation(vpcontact.Case(CASE), output=tmp_path / "run")


def test_views_and_reports_of_a_frictional_run(sim, tmp_path):
    assert sim.frictional
    m = len(sim.contact_nodes)
    assert sim.contact_force.shape == (m, 2)  # λ_ν, λ_τ per node
    views = sim.fields()
    assert {"slip_step", "slip", "contact_status"} <= set(views)
    assert sim.slip_step.shape == (m,) and sim.slip.shape == (m,) and sim.contact_status.shape == (m,)
    slip = sim.slip  # a view: it follows the steps
    sim.run()
    assert np.array_equal(slip, sim.slip) and slip.max() > 0
    assert set(np.unique(sim.contact_status)) <= {0.0, 1.0, 2.0}
    report = sim.report
    friction = [c["name"] for c in vpcontact.history_column_table() if c["friction"]]
    assert all(c in report for c in friction), report
    assert isinstance(report["n_stick"], int) and isinstance(report["dissipation"], float)
    assert report["n_stick"] + report["n_slip"] == int((sim.contact_status > 0).sum())
    force = sim.tangential_force  # a copy, as the VTU file has it: the force on the body
    assert force.shape == (len(sim.points), 3)
    assert force[:, 0].sum() == pytest.approx(-report["tangential_force_x"], rel=1e-12)  # history: on the obstacle
    # The output directory read back: the same arrays and columns.
    run = sim.results()
    f = run.fields()
    assert np.array_equal(f.tangential_force, force)
    assert np.array_equal(f.slip[sim.contact_nodes], sim.slip)
    assert np.array_equal(f.contact_status[sim.contact_nodes], sim.contact_status)
    assert np.array_equal(f.slip_increment, sim.slip_increment)
    h = run.history(frame=False)
    assert h["n_slip"][-1] == report["n_slip"] and h["tangential_force_x"][-1] == report["tangential_force_x"]
    assert run.summary["friction"]["n_slip"] == report["n_slip"]
    assert run.summary["friction"]["dissipation"] == pytest.approx(h["dissipation"].sum(), rel=1e-12)


def test_a_frictionless_run_has_none_of_it(tmp_path):
    sim = vpcontact.Simulation(vpcontact.Case("paper-2d", n=10, steps=2), output=tmp_path / "plain")
    sim.run()
    assert not sim.frictional
    assert not {"slip_step", "slip", "contact_status"} & set(sim.fields())
    assert not any(c.startswith("tangential_") or c in ("n_stick", "n_slip") for c in sim.history_columns)
    f = sim.results().fields()
    assert f.tangential_force is None and f.slip is None and f.contact_status is None
    assert "friction" not in sim.results().summary
