"""Issue 51: views held across a mesh adaptation. A view taken before an adaptation keeps the arrays
of the mesh it was taken of (never dangling, even once the simulation is gone), says so (its base's
`stale`, `mesh_version`), and a view taken after has the new mesh's shape."""

import gc

import numpy as np

import vpcontact


def test_views_held_across_an_adaptation():
    sim = vpcontact.Simulation(vpcontact.Case("ironing-2d", steps=6, set={"adapt.max_level": 4}))
    sim.step(1)
    u, sigma, points, cells = sim.u, sim.sigma, sim.points, sim.cells
    shapes = {"u": u.shape, "sigma": sigma.shape, "points": points.shape, "cells": cells.shape}
    assert u.base.mesh_version == sim.mesh_version and not u.base.stale
    version = sim.mesh_version
    sim.step(1)
    assert sim.mesh_version > version  # adapted (the step redone on meshes adapted from its solution)
    # The old views keep the old mesh's arrays as they were when it was replaced, marked stale, and no
    # longer follow the steps.
    kept = {"u": u.copy(), "sigma": sigma.copy(), "points": points.copy(), "cells": cells.copy()}
    sim.step(1)
    for name, v in (("u", u), ("sigma", sigma), ("points", points), ("cells", cells)):
        assert v.shape == shapes[name] and np.array_equal(v, kept[name]), name
        assert v.base.stale and v.base.mesh_version == version
    # New views: the new mesh's shapes, consistent with each other.
    assert sim.points.shape[0] == sim.u.shape[0] != points.shape[0]
    assert sim.cells.shape[0] == sim.sigma.shape[0] != cells.shape[0]
    assert not sim.u.base.stale
    assert sim.report["cells"] == sim.cells.shape[0] and sim.report["adaptations"] > 0
    # Held beyond the simulation: still the arrays they were.
    new_u = sim.u
    new_u_copy = new_u.copy()
    del sim
    gc.collect()
    assert np.array_equal(u, kept["u"]) and np.array_equal(points, kept["points"])
    assert np.array_equal(new_u, new_u_copy)
