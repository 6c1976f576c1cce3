"""Views, not copies: the arrays of a Simulation follow its steps, are read-only, keep
the simulation alive, and equal what its output files hold."""

import gc

import numpy as np
import pytest

import vpcontact


@pytest.fixture
def sim():
    return vpcontact.Simulation(vpcontact.Case("paper-2d", n=10, steps=6))


def test_shapes(sim):
    n_nodes, n_cells = 11 * 11, 2 * 10 * 10
    assert sim.dim == 2
    assert sim.points.shape == (n_nodes, 3) and sim.cells.shape == (n_cells, 3)
    assert sim.u.shape == (n_nodes, 2) and sim.beta.shape == (n_nodes,)
    for f in (sim.sigma, sim.eps, sim.z):
        assert f.shape == (n_cells, 6) and f.dtype == np.float64
    m = len(sim.contact_nodes)
    assert m > 0 and sim.contact_force.shape == (m,) and sim.active.shape == (m,)
    assert sim.contact_directions.shape == (m, 3)
    assert sim.facets.shape[1] == 2 and len(sim.facet_parts) == len(sim.facets)
    parts = sim.boundary_parts
    assert set(parts) == set(sim.part_names) and set(sim.contact_nodes) <= set(parts["contact"])
    # the contact part of paper-2d: the bottom side, y = 0, x in [0.8, 1.2]
    assert np.all(sim.points[sim.contact_nodes, 1] == 0)


def test_a_view_taken_before_a_step_shows_the_step(sim):
    views = sim.fields()
    before = {k: v.copy() for k, v in views.items()}
    assert np.all(before["u"] == 0) and np.all(before["sigma"] == 0)
    sim.step(3)
    for k, v in views.items():
        assert v.base is not None  # a view, not an owner of its data
        assert np.array_equal(v, getattr(sim, k)), k
    for k in ("u", "beta", "sigma", "eps", "z", "contact_force"):
        assert not np.array_equal(views[k], before[k]), k
    assert views["beta"].min() < 1 and views["contact_force"].max() > 0
    assert sim.active.sum() == sim.report["n_active"]


def test_views_are_read_only(sim):
    for v in list(sim.fields().values()) + [sim.points, sim.cells, sim.facets]:
        assert not v.flags.writeable
        with pytest.raises(ValueError):
            v[0] = 1


def test_a_view_keeps_the_simulation_alive():
    s = vpcontact.Simulation(vpcontact.Case("paper-2d", n=10, steps=2))
    s.step(2)
    beta, sigma, points = s.beta, s.sigma, s.points
    expected = beta.copy(), sigma.copy(), points.copy()
    del s
    gc.collect()
    for v, e in zip((beta, sigma, points), expected):
        assert np.array_equal(v, e)


def test_views_equal_the_files(tmp_path):
    s = vpcontact.run(vpcontact.Case("paper-2d", n=10, steps=6, set={"output.every": 3}), output=tmp_path)
    r = s.results()
    assert list(r.steps) == [0, 3, 6] and np.allclose(r.times, [0, 0.5, 1])
    f = r.fields()
    assert f.n == 6 and f.t == s.t
    for k in ("u", "beta", "sigma", "eps", "z"):
        assert np.array_equal(getattr(f, k), getattr(s, k)), k
    assert np.array_equal(f.points, s.points) and np.array_equal(f.cells, s.cells)
    assert np.array_equal(np.flatnonzero(f.active), np.sort(s.contact_nodes[s.active]))
    # contact_force_vector = -lambda nu at the contact nodes
    assert np.array_equal(f.contact_force_vector[s.contact_nodes], -s.contact_force[:, None] * s.contact_directions)
    # the output fields: the same table makes the files' arrays and the Simulation's copies
    for k in ("contact_force_vector", "contact_pressure", "von_mises"):
        assert np.array_equal(getattr(f, k), getattr(s, k)), k
    assert f.contact_force is None  # lambda's own array: only with more than one number per node
    first = r.fields(index=0)
    assert first.n == 0 and np.all(first.u == 0)
    assert r.fields(t=0.45).n == 3
    h = r.history(frame=False)
    assert np.array_equal(h["beta_min"], s.history(frame=False)["beta_min"])
    p = r.probes(frame=False)
    assert len(p) == 7 and "p0_beta" in p.dtype.names


def test_checkpoint_stop_and_resume_is_bit_identical(tmp_path):
    case = vpcontact.Case("paper-2d", n=10, steps=6, set={"output.every": 2})
    whole = vpcontact.run(case, output=tmp_path / "whole")
    first = vpcontact.Simulation(case, output=tmp_path / "parts", checkpoint_every=0)
    first.step(3)
    first.checkpoint()  # stop after step 3
    first.finish()
    with pytest.raises(vpcontact.Error, match="finished"):
        first.step()
    rest = vpcontact.Simulation(case, output=tmp_path / "parts", resume=True)
    assert rest.n == 3 and rest.t == first.t
    assert np.array_equal(rest.beta, first.beta) and np.array_equal(rest.sigma, first.sigma)
    beta = rest.beta
    rest.run()
    assert rest.n == 6 and np.array_equal(beta, whole.beta)
    for name in ("history.csv", "probes.csv", "solution_00006.vtu"):
        assert open(tmp_path / "whole" / name, "rb").read() == open(tmp_path / "parts" / name, "rb").read(), name


def test_matrices(sim):
    pytest.importorskip("scipy")
    m = sim.matrices()
    K, M, A, N = m["K"], m["M"], m["A"], m["N"]
    n_free, n_nodes = len(sim.free_dofs), len(sim.points)
    assert K.shape == (n_free, n_free) and abs(K - K.T).max() <= 1e-12 * abs(K).max()
    assert M.shape == A.shape == (n_nodes, n_nodes)
    assert M.sum() == pytest.approx(4.0)  # the square [0, 2]^2
    assert abs(A @ np.ones(n_nodes)).max() < 1e-12
    assert N.shape == (len(sim.contact_nodes), n_free)
    # N u: the normal displacement (u . nu) at the contact nodes
    sim.step(3)
    u = sim.u.ravel()[sim.free_dofs]
    normal = np.einsum("ij,ij->i", sim.u[sim.contact_nodes], sim.contact_directions[:, :2])
    assert np.allclose(N @ u, normal, atol=1e-15)
    # K u = F - B^T z - N^T lambda: with the loads of paper-2d, K u + N^T lambda is the load vector
    assert np.all(np.isfinite(K @ u))


def test_keyboard_interrupt_writes_a_checkpoint(tmp_path):
    """Ctrl-C in run() (here raised by the progress callback after step 3) leaves a
    checkpoint and summary.json, as SIGINT does to `vpcontact run`."""
    case = vpcontact.Case("paper-2d", n=10, steps=6)

    def stop_at_3(report):
        if report["step"] == 3:
            raise KeyboardInterrupt

    sim = vpcontact.Simulation(case, output=tmp_path / "run")
    with pytest.raises(KeyboardInterrupt):
        sim.run(progress=stop_at_3)
    assert sim.finished and sim.n == 3 and sim.last_checkpoint == 3
    assert vpcontact.read(tmp_path / "run").summary["final"]["t"] == sim.t
    rest = vpcontact.Simulation(case, output=tmp_path / "run", resume=True).run()
    whole = vpcontact.run(case, output=tmp_path / "whole")
    assert np.array_equal(rest.u, whole.u) and np.array_equal(rest.z, whole.z)
    assert open(tmp_path / "run" / "history.csv").read() == open(tmp_path / "whole" / "history.csv").read()


def test_fields_and_columns_come_from_the_library_tables(sim):
    table = vpcontact.state_fields()
    stored = [f["python"] for f in table if f["stored"] and not f["friction"]]
    assert list(sim.fields()) == stored == ["u", "beta", "contact_force", "sigma", "eps", "z"]
    assert not sim.frictional
    assert [f["python"] for f in table if f["stored"] and f["friction"]] == ["slip_step", "slip", "contact_status"]
    assert sim.slip.shape == (0,) and sim.slip_step.shape == (0,)  # friction's fields: empty without friction
    assert {f["location"] for f in table} == {"node", "cell", "contact node"}
    for f in table:
        assert getattr(vpcontact.Simulation, f["python"]).__doc__.startswith(f["meaning"])
    columns = [c["name"] for c in vpcontact.history_column_table() if not c["friction"]]
    assert sim.history_columns[: len(columns)] == columns
    friction = [c["name"] for c in vpcontact.history_column_table() if c["friction"]]
    assert "n_stick" in friction and not set(friction) & set(sim.history_columns)  # none without friction
    sim.step()
    assert isinstance(sim.report["n_active"], int) and isinstance(sim.report["contact_equilibrium"], float)


def test_surface_state_is_empty_where_no_law_keeps_any(sim):
    # The contact laws' per-node state (docs/scheme.md "A law may keep per-node state"): a dict of
    # views by declared name; the shipped laws declare none.
    assert sim.surface == {}
    sim.step(1)
    assert sim.surface == {}


def test_archard_wear_is_a_view_of_the_worn_depth_and_follows_the_recursion():
    # wear-2d (issue 50, docs/verification.md §8h): a block in uniaxial strain on a sliding plane;
    # the lagged worn depth is delta (1 - (1 - a)^n), a = k_w E' ds / H, at every contact node.
    sim = vpcontact.Simulation(vpcontact.Case("wear-2d"))
    wear = sim.surface["wear"]
    assert wear.shape == (len(sim.contact_nodes),) and not wear.flags.writeable
    assert np.all(wear == 0)
    E, nu, delta, k_w, ds = 1000.0, 0.3, 0.01, 5e-4, 0.05
    E_c = E * nu / ((1 + nu) * (1 - 2 * nu)) + E / (1 + nu)  # lambda + 2 mu
    a = k_w * E_c * ds
    for n in range(1, 6):
        sim.step()
        np.testing.assert_allclose(wear, delta * (1 - (1 - a) ** n), rtol=0, atol=1e-14)
    assert abs(sim.report["worn_volume"] - wear[0]) < 1e-15  # width 1: the depth times |Gamma_3| = 1


def test_fremond_adhesion_is_a_view_of_the_bonding_field_and_follows_its_recursion():
    # adhesion-bar-1d (issue 50, docs/verification.md §8i): a bar glued at its end and pulled through its
    # stiffness K; the lagged bonding is alpha_n = alpha_(n-1) exp(-gamma s_(n-1)^2 k / b) with
    # s = K delta / (K + gamma alpha^2), and the bond's pull is the node's tension and the history's force.
    sim = vpcontact.Simulation(vpcontact.Case("adhesion-bar-1d"))
    assert sorted(sim.surface) == ["adhesive_energy", "adhesive_traction", "bonding", "debonded",
                                   "debonding_energy", "separation"]
    bonding = sim.surface["bonding"]
    assert bonding.shape == (1,) and not bonding.flags.writeable
    K, gamma, delta, b, k = 100.0, 200.0, 0.01, 0.005, 0.05
    alpha, s = 1.0, 0.0
    for n in range(1, 6):
        sim.step()
        alpha *= np.exp(-gamma * s * s * k / b)
        s = K * delta / (K + gamma * alpha * alpha)
        assert abs(bonding[0] - alpha) < 1e-14
        assert abs(sim.report["adhesive_force"] - gamma * alpha * alpha * s) < 1e-13
        assert sim.report["debonded_fraction"] == 0


def test_the_tangential_bond_keeps_its_stretch_and_shear_as_views():
    # lap-shear-2d (issue 50, SPEC §9's gamma_tau): bond_slip is the tangential stretch v along each node's
    # tangents (2 numbers; the second 0 in 2D), adhesive_shear the bond's shear gamma_tau alpha^2 min(|v|, L).
    sim = vpcontact.Simulation(vpcontact.Case("lap-shear-2d"))
    m = len(sim.contact_nodes)
    slip, shear, bonding = sim.surface["bond_slip"], sim.surface["adhesive_shear"], sim.surface["bonding"]
    assert slip.shape == (m, 2) and shear.shape == (m,) and not slip.flags.writeable
    sim.step(10)
    assert np.all(slip[:, 1] == 0)
    gamma_tau, L = 2000.0, 0.02
    np.testing.assert_allclose(shear, gamma_tau * bonding**2 * np.minimum(np.abs(slip[:, 0]), L), rtol=1e-14, atol=0)
    assert shear.max() > 0 and bonding.min() < 1
