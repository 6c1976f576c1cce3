#!/usr/bin/env bash
# `pip install .` of the Python module, into a fresh virtual environment that sees Debian's
# packages (numpy, scipy), installing the module already built in BUILD (setup.py:
# VPCONTACT_CMAKE_BUILD; nothing is compiled), then a run from outside the source tree. Exit 77 (CTest: skipped)
# where /usr/bin/python3 has no pip or venv (Debian: python3-pip, python3-venv).
#   tests/python/pip_install.sh PYTHON SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
python=$1 source=$2 build=$3 work=$4
if ! "$python" -m pip --version > /dev/null 2>&1 || ! "$python" -c "import venv, ensurepip" > /dev/null 2>&1; then
  echo "pip_install: no pip or venv for $python: skipped (pip install . is optional; docs/python.md)"
  exit 77
fi
rm -rf "$work" && mkdir -p "$work"
"$python" -m venv --system-site-packages "$work/venv"
mkdir -p "$build/setuptools"
VPCONTACT_CMAKE_BUILD="$build" "$work/venv/bin/python" -m pip install --no-build-isolation --no-index --no-deps \
  --no-cache-dir -q "$source"
cd "$work"
"$work/venv/bin/python" - <<'PY'
import os
import vpcontact
assert vpcontact.__file__.startswith(os.path.realpath("venv")) or "site-packages" in vpcontact.__file__, vpcontact.__file__
sim = vpcontact.run(vpcontact.Case("paper-1d"), output="out")
assert sim.done and 0.55 < sim.beta.min() < 0.56
print("pip_install: vpcontact", vpcontact.__version__, "from", os.path.dirname(vpcontact.__file__), "ran paper-1d")
PY
