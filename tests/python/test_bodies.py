"""Several bodies (issue 29, [[body]]): a run's fields restricted to one body (Fields.body),
and a contact pair's force in the history, read back from the output directory."""

import numpy as np
import pytest

import vpcontact



@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("bodies")
    # The shipped contact patch test (cases/contact-patch-2d.toml): two blocks, the upper one "upper".
    vpcontact.Simulation(vpcontact.Case("contact-patch-2d", steps=2), output=out).run()
    return vpcontact.read(out)


def test_each_body_is_its_own_mesh_and_fields(results):
    assert results.bodies == ["body", "upper"]
    f = results.fields()
    lower, upper = f.body("body"), f.body("upper")
    assert (len(lower.points), len(upper.points)) == (6 * 4, 8 * 5)
    assert (len(lower.cells), len(upper.cells)) == (2 * 5 * 3, 2 * 7 * 4)
    assert len(lower.points) + len(upper.points) == len(f.points)
    for b in (lower, upper):
        assert b.cells.min() == 0 and b.cells.max() == len(b.points) - 1  # renumbered
        assert np.array_equal(b.points, f.points[b.nodes])
        assert np.array_equal(b.u, f.u[b.nodes]) and np.array_equal(b.sigma, f.sigma[b.cell_ids])
    assert upper.points[:, 1].min() == 0.5 and lower.points[:, 1].max() == 0.5
    assert np.array_equal(f.body(1).nodes, upper.nodes)  # by index too
    # The patch test: both bodies carry the same uniform stress across the pair.
    sigma_yy = -0.01 / (0.5 * 0.91 / 1000 + 0.5 * 0.91 / 3000)
    for b in (lower, upper):
        assert np.allclose(b.sigma[:, 1], sigma_yy, rtol=1e-11, atol=0)


def test_both_sides_of_the_pair_show_the_pressure_and_the_gap(results):
    f = results.fields()
    sigma_yy = -0.01 / (0.5 * 0.91 / 1000 + 0.5 * 0.91 / 3000)
    for name in ("body", "upper"):  # the master's top and the slave's bottom, at y = 0.5
        b = f.body(name)
        on = np.isclose(b.points[:, 1], 0.5)
        assert on.sum() in (6, 8)
        assert np.allclose(b.contact_pressure[on], -sigma_yy, rtol=1e-11, atol=0)
        assert np.all(b.contact_pressure[~on] == 0)
        assert np.allclose(b.gap, 0, atol=1e-14)


def test_the_pair_force_is_in_the_history(results):
    h = results.history()
    assert np.allclose(h["force_pair_upper.bottom"], h["total_contact_force"], rtol=1e-12)
    sigma_yy = -0.01 / (0.5 * 0.91 / 1000 + 0.5 * 0.91 / 3000)
    assert h["force_pair_upper.bottom"][-1] == pytest.approx(-sigma_yy * 1.0, rel=1e-11)  # σ times the unit interface


def test_an_unknown_body_is_named(results):
    with pytest.raises(ValueError, match="no body 'lower': the run's bodies are body, upper"):
        results.fields().body("lower")
    with pytest.raises(ValueError, match="no body 5"):
        results.fields().body(5)
