"""Bad input raises a Python exception with the command line's message and its location."""

import numpy as np
import pytest

import vpcontact

BAD_CASE = """[mesh]
generator = "interval"
lower = [0]
upper = [1]
cells = 10

[boundary]
clamped = "left"
contact = "right"

[elasticity]
E = 1

[damage]
kappa = -1
"""


def test_bad_case_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BAD_CASE)
    with pytest.raises(vpcontact.CaseError) as e:
        vpcontact.Case(path)
    err = e.value
    assert isinstance(err, ValueError)
    assert str(err) == "%s:15:9: damage.kappa: kappa must be >= 0 (got -1)" % path
    assert (err.file, err.line, err.column, err.key) == (str(path), 15, 9, "damage.kappa")


def test_unknown_key_in_a_file(tmp_path):
    path = tmp_path / "typo.toml"
    path.write_text(BAD_CASE.replace("kappa = -1", "kapa = 1"))
    with pytest.raises(vpcontact.CaseError, match="did you mean 'kappa'") as e:
        vpcontact.Case(path)
    assert (e.value.line, e.value.key) == (15, "damage.kapa")


def test_bad_override_leaves_the_case_unchanged():
    case = vpcontact.Case("paper-2d", n=10)
    with pytest.raises(vpcontact.CaseError) as e:
        case.set("damage.kapa", 1)
    assert str(e.value).startswith("--set damage.kapa=1: unknown key or parameter")
    assert e.value.key == "damage.kapa" and e.value.file is None and e.value.line is None
    with pytest.raises(vpcontact.CaseError, match=r"^--set damage.kappa=-1: kappa must be >= 0") as e:
        case.kappa = -1
    assert e.value.key == "damage.kappa"
    with pytest.raises(vpcontact.CaseError, match="expected an integer, got a string") as e:
        case.set({"time.steps": "many"})
    assert e.value.key == "time.steps"
    with pytest.raises(vpcontact.CaseError, match=r"^--n 12: the number of cells per edge n must be a multiple of 5"):
        case.n = 12
    assert case.sets == [] and case.n == 10 and case.kappa == 1


def test_unknown_case_and_bad_values():
    with pytest.raises(vpcontact.CaseError, match="unknown case 'paper-9d'; built-in cases are: .*paper-1d"):
        vpcontact.Case("paper-9d")
    with pytest.raises(TypeError, match="no TOML value"):
        vpcontact.Case("paper-1d").set("damage.kappa", object())


def test_a_formula_that_gives_nan_in_a_run_raises_run_error(tmp_path):
    # Issue 26 item 3: the run stops at the first non-finite value, naming the key, the time and the point
    text = BAD_CASE.replace("kappa = -1", 'phi = "t > 0.2 ? sqrt(-1) : -0.1"') + "[time]\nsteps = 10\n"
    sim = vpcontact.Simulation(vpcontact.Case("nan.toml", text=text), output=tmp_path)
    with pytest.raises(vpcontact.RunError, match=r"damage.phi: the formula .* gives NaN at t = 0.3 at the centroid") as e:
        sim.run()
    assert isinstance(e.value, RuntimeError) and sim.finished
    assert "Results up to step 2 are in" in str(e.value)
    assert len((tmp_path / "history.csv").read_text().splitlines()) == 1 + 2  # header, steps 1 and 2
    with pytest.raises(vpcontact.Error, match="the simulation is finished"):
        sim.step()


def test_resume_without_checkpoint(tmp_path):
    with pytest.raises(vpcontact.CaseError, match="needs the output directory"):
        vpcontact.Simulation("paper-1d", resume=True)
    with pytest.raises(vpcontact.Error, match="--resume: no good checkpoint for this case"):
        vpcontact.Simulation("paper-1d", output=tmp_path / "none", resume=True)


def test_misuse_of_a_simulation():
    sim = vpcontact.Simulation(vpcontact.Case("paper-1d", steps=2))
    with pytest.raises(vpcontact.CaseError, match="checkpoint.. needs an output directory"):
        sim.checkpoint()
    sim.step(5)  # not beyond the last step
    assert sim.n == 2 and sim.done
    with pytest.raises(vpcontact.CaseError, match="at its final time .step 2, t = T = 1."):
        sim._step()
    with pytest.raises(vpcontact.RunError, match="writes no files"):
        sim.results()


def test_reading_a_directory_that_is_no_run(tmp_path):
    with pytest.raises(vpcontact.RunError, match="summary.json") as e:
        vpcontact.read(tmp_path)
    assert e.value.file.endswith("summary.json")


def test_counts_and_times_that_are_zero_negative_or_nan_raise(tmp_path):
    # Issue 48 item 15: sim.step(0) and sim.step(-1) returned silently
    sim = vpcontact.Simulation(vpcontact.Case("paper-1d", steps=3))
    for count in (0, -1):
        with pytest.raises(ValueError, match=r"^Simulation.step\(count\): count must be an integer >= 1 \(got %d\)$"
                           % count):
            sim.step(count)
    for count in (1.5, float("nan"), True, "2"):
        with pytest.raises(TypeError, match=r"^Simulation.step\(count\): count must be an integer >= 1 \(got "):
            sim.step(count)
    assert sim.n == 0 and sim.report is None  # nothing stepped
    assert sim.step(np.int64(2))["step"] == 2  # a numpy integer is an integer
    with pytest.raises(TypeError, match=r"progress must be None, False, True or a callable .* \(got 5\)"):
        sim.run(progress=5)
    # the options of a Simulation: before anything is set up
    case = vpcontact.Case("paper-1d", steps=2)
    for options, message in (({"checkpoint_every": -2}, r"^checkpoint_every must be a number of steps >= 0 .*\(got -2\)"),
                             ({"checkpoint_seconds": 0}, r"^checkpoint_seconds must be a finite number .* > 0 \(got 0\)"),
                             ({"checkpoint_seconds": -1.0}, r"^checkpoint_seconds must .* \(got -1\)"),
                             ({"checkpoint_seconds": float("nan")}, r"^checkpoint_seconds must .* \(got nan\)"),
                             ({"halvings": -1}, r"^halvings must be in \[0, 20\] \(got -1\)")):
        with pytest.raises(vpcontact.CaseError, match=message):
            vpcontact.Simulation(case, output=tmp_path / "none", **options)
    assert not (tmp_path / "none").exists()
    for options in ({"checkpoint_every": 1.5}, {"halvings": 0.5}, {"checkpoint_seconds": "60"}):
        with pytest.raises(TypeError, match=r"^Simulation: %s must be" % next(iter(options))):
            vpcontact.Simulation(case, **options)
    with pytest.raises(TypeError, match=r"^Case.n: n must be an integer or None \(got 2.5\)"):
        vpcontact.Case("paper-2d", n=2.5)
    # a run read back: fields(t=nan) gave the first output, silently
    run = vpcontact.run(vpcontact.Case("paper-1d", steps=4, set={"output.every": 2}), output=tmp_path / "run")
    results = vpcontact.read(tmp_path / "run")
    assert list(results.steps) == [0, 2, 4]
    assert results.fields(t=0.6).n == 2 and results.fields(index=-3).n == 0
    with pytest.raises(ValueError, match=r"^Results.fields\(t\): t must be a finite time \(got nan\)"):
        results.fields(t=float("nan"))
    with pytest.raises(IndexError, match=r"^Results.fields\(index\): index must be in \[-3, 3\): 3 outputs \(got 3\)"):
        results.fields(index=3)
    assert run.done
