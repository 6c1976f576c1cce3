#!/usr/bin/env bash
# Issue 26 items 8 and 20: what the figures take from summary.json.
#  - item 8: the centre of pressure moves onto a side of the contact zone only where that
#    side is one of the case's symmetry planes (summary.json "symmetry_planes"); the
#    reporter's L bracket (whole-face contact, symmetry plane y = 0) was reported at the
#    corner (2, 0.5);
#  - item 20: the rigid obstacles are drawn in the 2D deformed mesh (summary.json
#    "obstacles": their positions at the output times); the labels' units follow
#    [case] units (SI by default, "mm-N-MPa", or free text: no units in the labels, the
#    text in the titles); time_steps.png of error-controlled steps has the tolerance.
#
# Usage: tests/plot/test_figure_data.sh PATH/TO/vpcontact TMPDIR SOURCE_DIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
src=$3
python=${PYTHON:-/usr/bin/python3}
fail() { echo "test_figure_data: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1
texts() { "$python" "$src/tests/plot/check_plot.py" texts "$1" > "$1.txt" 2> "$1.err" || fail "texts $1: $(tail -1 "$1.err")"; }

# --- item 8: the L bracket, from the reporter's files
cp "$src/tests/data/reported/lpart.toml" "$src/tests/data/reported/lpart.geo" .
"$vpcontact" run lpart.toml --steps 25 --every 25 -q -o lp || fail "run lpart.toml"
"$python" - lp/summary.json <<'PY' || fail "lpart: symmetry_planes in summary.json"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["symmetry_planes"] == [{"part": "sym", "axis": "y", "coordinate": 0.0}], s.get("symmetry_planes")
PY
texts lp
# The expected centre: the pressure-weighted mean of the nodes in contact, y on the plane y = 0.
want=$(PYTHONPATH="$src/scripts" "$python" - lp <<'PY'
import sys
import numpy as np
import vpcontact_plot as vp
run = vp.Run(sys.argv[1])
_, v = run.final_vtu()
p = v.scalar("contact_pressure")
a = p > 0
x = (v.points[a, 0] * p[a]).sum() / p[a].sum()
assert a.sum() > 50 and np.all(v.points[a, 2] == 0), "not a whole-face contact"
print("(%.4g, %.4g)" % (x, 0.0))
PY
) || fail "lpart: the expected centre"
grep -qF "\$(x_c, y_c)\$ = $want" lp.txt || fail "lpart: centre of pressure $(grep -o '(x_c, y_c)\$ = ([^)]*)' lp.txt), expected $want"
echo "item 8: ok ($want)"

# --- item 20: obstacles, units, tolerance
# A 2D plane-strain block on a rigid cylinder (the reporter's block_cyl, coarser and shorter).
cat > cyl.toml <<'TOML'
[case]
name = "block-cyl"
[mesh]
generator = "rectangle"
lower = [-1.0, 0.0]
upper = [1.0, 1.0]
cells = [10, 5]
[boundary]
contact = ["bottom"]
[[boundary.displacement]]
parts = ["top"]
ux = 0
uy = "-0.02*t"
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[damage]
kappa = 1.0
[[obstacle]]
name = "cylinder"
shape = "cylinder"
center = [0.0, "-1.0 + 0.01*t"]
radius = 1.0
[[obstacle]]
name = "floor"
shape = "plane"
point = [0, -0.5]
normal = [0, 1]
[time]
T = 1.0
steps = 4
[output]
every = 2
TOML
"$vpcontact" run cyl.toml -q -o cyl || fail "run cyl.toml"
"$python" - cyl/summary.json <<'PY' || fail "cyl: obstacles in summary.json"
import json, sys
s = json.load(open(sys.argv[1]))
ob = {o["name"]: o for o in s["obstacles"]}
c, f = ob["cylinder"], ob["floor"]
assert c["shape"] == "cylinder" and c["radius"] == 1.0, c
assert [e[0] for e in c["positions"]] == [0.0, 0.5, 1.0], c["positions"]
assert abs(c["positions"][-1][2] - (-0.99)) < 1e-15, c["positions"]
assert f["shape"] == "plane" and f["normal"][:2] == [0.0, 1.0] and f["positions"][0][1:3] == [0.0, -0.5], f
assert s["units"] == "SI"
PY
texts cyl
for o in cylinder floor; do
  grep -qP "^deformed_mesh\tlegend\tobstacle $o$" cyl.txt || fail "the deformed mesh does not draw the obstacle $o: $(grep deformed_mesh cyl.txt)"
done
grep -qP "^deformed_mesh\txlabel\t\\\$x\\\$ \[m\]$" cyl.txt || fail "SI: $(grep -P 'deformed_mesh\txlabel' cyl.txt)"
echo "item 20 obstacles: ok"

"$vpcontact" run cyl.toml -q -o mm --set case.units=mm-N-MPa || fail "run with units mm-N-MPa"
texts mm
grep -qP '\[m\]|N/m(?!m)' mm.txt && fail "mm-N-MPa: SI units in a label: $(grep -P '\[m\]|N/m(?!m)' mm.txt | head -3)"
grep -qP "^deformed_mesh\txlabel\t\\\$x\\\$ \[mm\]$" mm.txt || fail "mm-N-MPa: $(grep -P 'deformed_mesh\txlabel' mm.txt)"
grep -qP "^von_mises_beta\tcolorbar\t.*\[MPa\]$" mm.txt || fail "mm-N-MPa: $(grep -P 'von_mises_beta\tcolorbar' mm.txt)"
grep -qP "^history\tylabel\tforce \[N/mm\]$" mm.txt || fail "mm-N-MPa: $(grep -P 'history\tylabel' mm.txt)"
"$vpcontact" run cyl.toml -q -o free --set 'case.units="inch, lbf, psi"' || fail "run with free-text units"
texts free
grep -qP '\[m\]|\[s\]|N/m' free.txt && fail "free-text units: SI units in a label: $(grep -P '\[m\]|\[s\]|N/m' free.txt | head -3)"
grep -qP "^deformed_mesh\tsuptitle\t.*\(units: inch, lbf, psi\)$" free.txt || fail "free-text units not in the title"
echo "item 20 units: ok"

"$vpcontact" run paper-1d -q --no-vtu --set time.tolerance=1e-2 -o tol || fail "run paper-1d with tolerance"
texts tol
grep -qP "^time_steps\tlegend\ttolerance 0.01: accepted where" tol.txt || fail "time_steps: no tolerance line: $(grep time_steps tol.txt)"
echo "item 20 tolerance: ok"
echo "test_figure_data: all passed"
