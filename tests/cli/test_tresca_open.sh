#!/usr/bin/env bash
# Issue 48: Tresca's given bound acts on all of Γ3, in contact or not (the classical model, kept):
# a plane 0.1 below shear-2d's face that slides drags it. The run says so: one warning located at
# the friction key, history.csv's n_tresca_open counts those nodes (n_stick = n_slip = 0 there),
# and the state's contact_status is 3 there (tests/regression FrictionShear). Coulomb with a shear limit transmits nothing, has
# no such column and no warning.
#
# Usage: tests/cli/test_tresca_open.sh PATH/TO/vpcontact TMPDIR
set -uo pipefail
vpcontact=$1 tmp=$2
python=${PYTHON:-/usr/bin/python3}
fail() { echo "test_tresca_open: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1
cat > c.toml <<'TOML'
[case]
name = "fr2"
[mesh]
generator = "rectangle"
lower = [-1.0, 0.0]
upper = [1.0, 0.5]
cells = [20, 5]
[boundary]
clamped = ["top"]
contact = ["bottom"]
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[[obstacle]]
name = "plane"
shape = "plane"
point = ["0.02*max(t - 1, 0)", "-0.1"]
normal = [0.0, 1.0]
[contact]
friction = "tresca"
friction_bound = 1.0
[time]
T = 2.0
steps = 20
TOML
"$vpcontact" run c.toml -o A -q > A.log 2> A.err || fail "Tresca run: $(tail -3 A.err)"
[ "$(grep -c 'warning' A.err)" = 1 ] || fail "expected one warning, got: $(cat A.err)"
grep -q '^vpcontact: warning: c.toml:25:[0-9]*: contact.friction: Tresca friction acts through 21 contact node(s) not in contact at step 11' A.err ||
  fail "the warning is not located at the friction key: $(cat A.err)"
"$vpcontact" run c.toml -o B -q --no-vtu --set contact.friction='"coulomb"' --set contact.mu=0.3 --set contact.shear_limit=1 \
  > B.log 2> B.err || fail "Coulomb run: $(tail -3 B.err)"
[ -s B.err ] && fail "a warning for Coulomb with a shear limit: $(cat B.err)"
"$python" - <<'PY' || fail "the outputs disagree (above)"
import csv, glob, re, sys
import numpy as np

def history(d):
    rows = list(csv.reader(open(d + "/history.csv")))
    return rows[0], {c: np.array([float(r[i]) for r in rows[1:]]) for i, c in enumerate(rows[0])}

head, h = history("A")
assert "n_tresca_open" in head and head.index("n_tresca_open") == head.index("friction_slip_direction") + 1, head
dragged = h["t"] > 1.05
assert (h["n_tresca_open"][dragged] == 21).all(), h["n_tresca_open"]
assert (h["n_stick"] == 0).all() and (h["n_slip"] == 0).all() and (h["n_active"] == 0).all()
assert np.allclose(h["tangential_force_x"][dragged], -2.0, rtol=1e-9), h["tangential_force_x"]
head_b, hb = history("B")
assert "n_tresca_open" not in head_b, head_b
assert (hb["tangential_force_x"] == 0).all(), hb["tangential_force_x"]
print("history ok")
PY
echo "test_tresca_open: all passed"
