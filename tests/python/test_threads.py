"""Issue 48 item 4: one caller of a Simulation at a time. A call made while another is in
progress in another thread raises BusyError naming that call and its thread (it used to
segfault, or duplicate steps: 33 history rows for a 20-step run); a progress callback may
read the simulation but not step it. The second call is made from inside the first, made
to wait there for it (run()'s progress callback, or a hook in step()), so every test is
deterministic: no sleeps."""

import threading

import numpy as np
import pytest

import vpcontact

# The reported case (py-threads-race): two bodies, a Coulomb pair, 20 steps.
PAIR = """
[case]
name = "pr2"
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 0.5]
cells = [10, 3]
[[body]]
name = "upper"
[body.mesh]
generator = "rectangle"
lower = [0.5, 0.5]
upper = [1.5, 1.0]
cells = [7, 4]
[body.elasticity]
E = 3000.0
[boundary]
clamped = ["bottom"]
[[boundary.displacement]]
parts = ["upper.top"]
ux = "0.02*max(t - 1, 0)"
uy = "-0.005*min(t, 1)"
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[[contact.pair]]
slave = "upper.bottom"
master = "top"
friction = "coulomb"
mu = 0.3
[time]
T = 2.0
steps = 20
"""


def in_thread(name, *calls):
    """Runs each call in a new thread named `name` and waits for it; what each returned or raised."""
    out = []

    def go():
        for call in calls:
            try:
                out.append(call())
            except Exception as e:  # noqa: BLE001 (what the call raised is the result)
                out.append(e)

    t = threading.Thread(target=go, name=name)
    t.start()
    t.join()
    return out


def other_thread_calls(sim):
    """A writer, readers of the state, of the mesh, of the tables and of the matrices."""
    return (lambda: sim.step(), lambda: sim.u, lambda: sim.t, lambda: sim.done, lambda: sim.report,
            lambda: sim.history(), lambda: sim.points, lambda: sim.von_mises, lambda: sim.finish(),
            lambda: sim.checkpoint(), lambda: repr(sim))


def assert_refused(results, call, thread, caller):
    for r in results:
        assert isinstance(r, vpcontact.BusyError), r
        assert isinstance(r, RuntimeError)
        assert (r.call, r.thread) == (call, thread)
        assert "in thread '%s': refused: %s is in progress in thread '%s'" % (caller, call, thread) in str(r), str(r)


def test_another_thread_is_refused_while_run_is_in_progress():
    case = vpcontact.Case("paper-2d", n=10, steps=4)
    sim = vpcontact.Simulation(case)
    seen = {}

    def progress(report):
        if report["step"] == 2:  # inside run(): the second caller starts now, and run() waits for it
            seen["results"] = in_thread("intruder", *other_thread_calls(sim))

    sim.run(progress=progress)
    assert len(seen["results"]) == 11
    assert_refused(seen["results"], "Simulation.run()", threading.current_thread().name, "intruder")
    # the intruder changed nothing: the run is the uninterrupted one
    whole = vpcontact.run(case)
    assert sim.n == 4 and len(sim.history(frame=False)) == 4
    assert np.array_equal(sim.u, whole.u) and np.array_equal(sim.beta, whole.beta)
    # and the lock is free again
    assert in_thread("after", lambda: sim.n) == [4]


def test_another_thread_is_refused_while_a_step_is_in_progress():
    sim = vpcontact.Simulation(vpcontact.Case("paper-1d", steps=3))
    step = sim._step
    me = threading.current_thread()
    seen = []

    def hooked_step():  # runs inside step(), as the library's step does
        if threading.current_thread() is me:  # (without the lock the other thread's step would come here too)
            seen.extend(in_thread("worker-2", lambda: sim.beta, lambda: sim.step(2), lambda: sim.n))
        step()

    sim._step = hooked_step
    sim.step(2)
    assert len(seen) == 6  # two steps, three calls each
    assert_refused(seen, "Simulation.step()", threading.current_thread().name, "worker-2")
    del sim._step
    assert sim.n == 2 and len(sim.history(frame=False)) == 2


def test_a_progress_callback_may_read_but_not_step():
    sim = vpcontact.Simulation(vpcontact.Case("paper-1d", steps=3))
    seen = []

    def progress(report):
        assert sim.report == report and sim.n == report["step"] and sim.t == report["t"]  # reads nest
        assert len(sim.history(frame=False)) == sim.n and sim.beta.shape == sim.u.shape[:1]
        for call in (sim.step, sim.run, sim.finish):
            with pytest.raises(vpcontact.BusyError) as e:
                call()
            seen.append(e.value)

    sim.run(progress=progress)
    assert len(seen) == 9 and sim.n == 3 and sim.finished
    for e in seen:
        assert e.call == "Simulation.run()"
        assert " from the progress callback of Simulation.run() (thread '%s'): refused: a callback may read" % (
            threading.current_thread().name) in str(e)
    assert str(seen[0]).startswith("Simulation.step() from the progress callback")
    assert str(seen[2]).startswith("Simulation.finish() from the progress callback")


def test_an_error_in_the_callback_leaves_the_lock_free(tmp_path):
    sim = vpcontact.Simulation(vpcontact.Case("paper-1d", steps=4), output=tmp_path)

    def progress(report):
        sim.checkpoint()  # refused: a write from the callback

    with pytest.raises(vpcontact.BusyError, match=r"^Simulation.checkpoint\(\) from the progress callback"):
        sim.run(progress=progress)
    assert sim.n == 1 and not sim.finished
    sim.checkpoint()  # the same thread, no call in progress: fine
    assert in_thread("later", lambda: sim.step(), lambda: sim.n)[1] == 2
    sim.run()
    assert sim.n == 4 and len(sim.history(frame=False)) == 4


def test_two_threads_stepping_one_simulation():
    """The report: two threads stepping one Simulation until done. Whatever the timing, every
    step is taken once: the history has one row per step, and the result is the one-thread run's;
    the loser of a race gets BusyError (or RunError: the other thread took the last step)."""
    case = vpcontact.Case("pr2.toml", text=PAIR)
    ref = vpcontact.Simulation(case).run()
    for _ in range(10):
        sim = vpcontact.Simulation(case)
        errors = []

        def go():
            try:
                while not sim.done:
                    sim.step()
            except Exception as e:  # noqa: BLE001 (checked below, in the test's thread)
                errors.append(e)

        threads = [threading.Thread(target=go) for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for e in errors:  # BusyError, or RunError: the other thread took the last step meanwhile
            assert isinstance(e, vpcontact.BusyError) or "there is no step after the last" in str(e), repr(e)
        if not sim.done:  # both lost a race: this thread finishes the run
            assert errors
            sim.run()
        rows = sim.history(frame=False)
        assert sim.n == 20 and len(rows) == 20 and list(rows["step"]) == list(range(1, 21))
        assert np.array_equal(rows["t"], ref.history(frame=False)["t"])
        assert np.array_equal(sim.u, ref.u)
