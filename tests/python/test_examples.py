"""The examples (examples/) and the notebook run, on small sizes, as CI runs them."""

import os
import subprocess
import sys

import pytest

SOURCE = os.environ.get("VPCONTACT_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
EXAMPLES = os.path.join(SOURCE, "examples")


def run(tmp_path, *args):
    env = dict(os.environ, MPLBACKEND="Agg", VPCONTACT_N="10")
    r = subprocess.run([sys.executable, *map(str, args)], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert r.returncode == 0, "%s: exit %d\n%s\n%s" % (" ".join(map(str, args)), r.returncode, r.stdout, r.stderr)
    return r.stdout


def test_paper_1d(tmp_path):
    pytest.importorskip("matplotlib")
    out = run(tmp_path, os.path.join(EXAMPLES, "paper_1d.py"), "out")
    for fig in ("fig_4_2_displacement_stress", "fig_4_3_time_histories", "fig_4_4_damage"):
        assert os.path.getsize(tmp_path / "out" / "figures" / (fig + ".png")) > 0
    assert "t = 1: min beta = 0.5533" in out


def test_kappa_sweep(tmp_path):
    pytest.importorskip("matplotlib")
    out = run(tmp_path, os.path.join(EXAMPLES, "kappa_sweep.py"), "sweep", "--n", 10, "--steps", 10, "--kappa", 0.1, 10)
    lines = [line for line in out.splitlines() if line.startswith("kappa")]
    beta = [float(line.split()[-1]) for line in lines]
    assert len(beta) == 2 and beta[0] < beta[1] < 1  # more diffusion, less concentrated damage
    assert os.path.getsize(tmp_path / "sweep" / "kappa_sweep.png") > 0


def test_read_run(tmp_path):
    out = run(tmp_path, os.path.join(EXAMPLES, "read_run.py"))
    assert "output times: [0.  0.1 0.2" in out and "nodes in contact at the end" in out


def test_notebook(tmp_path):
    pytest.importorskip("matplotlib")
    out = run(tmp_path, os.path.join(SOURCE, "tests", "python", "run_notebook.py"), os.path.join(EXAMPLES, "vpcontact.ipynb"))
    assert "5 code cells ran" in out
