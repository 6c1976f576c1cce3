"""Shared set-up of the Python module's tests (run by CTest: python/CMakeLists.txt sets
PYTHONPATH to build/python and VPCONTACT_EXE to the command line program)."""

import os
import subprocess

import pytest


@pytest.fixture(scope="session")
def exe():
    """The command line program of the same build."""
    path = os.environ.get("VPCONTACT_EXE")
    if not path:
        pytest.fail("VPCONTACT_EXE is not set (run the tests with ctest -L python)")
    return path


@pytest.fixture
def cli(exe):
    """Runs `vpcontact ARGS...`; fails the test on a non-zero exit."""

    def run(*args):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        assert r.returncode == 0, "vpcontact %s: exit %d\n%s" % (" ".join(map(str, args)), r.returncode, r.stderr)
        return r

    return run


def read(path):
    with open(path, "rb") as f:
        return f.read()
