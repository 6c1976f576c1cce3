#!/usr/bin/env bash
# Issue 48 item 10: the figures of cases with several bodies (contact pairs).
#  - contact_pressure.png of a 3D pair draws the pair's slave side (not the bounding box's
#    bottom face, where nothing touches) with its nodes in contact and the pair's force;
#  - bodies in contact are drawn at true scale (a magnification carried their rigid motions
#    into each other), and the titles say so;
#  - friction.png draws the forces against t (a point of the body moves a little and back);
#  - the labels carry the case's units: nafems-roller-2d is in mm, N, MPa; the frictional
#    dissipation is a work (J, J/m per unit thickness in 2D; mJ, mJ/mm in mm-N-MPa).
#
# Usage: tests/plot/test_pair_figures.sh PATH/TO/vpcontact TMPDIR SOURCE_DIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
src=$3
python=${PYTHON:-/usr/bin/python3}
check="$src/tests/plot/check_plot.py"
fail() { echo "test_pair_figures: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1
texts() { "$python" "$check" texts "$1" > "$1.txt" 2> "$1.err" || fail "texts $1: $(tail -1 "$1.err")"; }
drawn() { "$python" "$check" drawn "$1" > "$1.drawn" 2> "$1.derr" || fail "drawn $1: $(tail -1 "$1.derr")"; }
field() { grep -P "^$2\t$3\t" "$1" | cut -f3; }

# --- a 3D pair: the upper block of contact-patch-3d pressed on the lower one. Its slave side,
# upper.bottom, is the upper body's face z = 0.5 (5 x 4 cells: 30 nodes, all in contact).
"$vpcontact" run contact-patch-3d -q -o patch3 || fail "run contact-patch-3d"
texts patch3
drawn patch3
want=$(PYTHONPATH="$src/scripts" "$python" - patch3 <<'PY'
import sys
import numpy as np
import vpcontact_plot as vp
run = vp.Run(sys.argv[1])
t, v = run.final_vtu()
p, pres, body = v.points, v.scalar("contact_pressure"), v.cell("body")
upper = np.unique(v.cells[body == 1])
face = upper[np.abs(p[upper, 2] - 0.5) < 1e-12]        # upper.bottom
assert len(face) == 30, len(face)
n_active = int((pres[face] > 0).sum())
force = float(run.history["force_pair_upper.bottom"][-1])
assert n_active > 0 and force > 0
print("%s %d %.4g" % (",".join(str(int(i)) for i in sorted(face)), n_active, force))
PY
) || fail "contact-patch-3d: the expected slave side"
read -r nodes n_active force <<< "$want"
got=$(field patch3.drawn contact_pressure nodes)
[ "$got" = "$nodes" ] || fail "contact-patch-3d: the pressure map's nodes are $got, expected the slave side upper.bottom's $nodes"
grep -qP "^contact_pressure\tsuptitle\t.*: $n_active nodes in contact, .*force between the bodies $force N$" patch3.txt ||
  fail "contact-patch-3d: expected $n_active nodes in contact and the pair's force $force N: $(field patch3.txt contact_pressure suptitle)"
grep -qP "^contact_pressure\ttitle\t\(a\) pressure on the slave part \"upper.bottom\": the bottom face \\\$z\\\$ = 0.5 of its body$" patch3.txt ||
  fail "contact-patch-3d: $(field patch3.txt contact_pressure title | head -1)"
for f in surface_von_mises surface_beta; do
  grep -qP "^$f\tsuptitle\t.*on the deformed boundary \(true scale, max" patch3.txt ||
    fail "contact-patch-3d: $f is not at true scale: $(field patch3.txt $f suptitle)"
done
echo "3D pair: ok ($n_active nodes, $force N)"

# --- a 2D pair with friction: a block pressed on another and dragged along it.
cat > drag.toml <<'TOML'
[case]
name = "drag-2d"
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [1.0, 0.4]
cells = [10, 4]
[[body]]
name = "upper"
[body.mesh]
generator = "rectangle"
lower = [0.3, 0.4]
upper = [0.7, 0.6]
cells = [6, 3]
[boundary]
clamped = ["bottom"]
[[boundary.displacement]]
parts = ["upper.top"]
ux = "0.01*max(t - 1, 0)"
uy = "-0.004*min(t, 1)"
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
steps = 8
[output]
every = 4
probes = [[0.5, 0.4]]
TOML
"$vpcontact" run drag.toml -q -o drag || fail "run drag.toml"
texts drag
drawn drag
for f in deformed_mesh von_mises_beta; do
  s=$(field drag.drawn $f scale)
  "$python" -c "import sys; sys.exit(abs(float('$s') - 1) > 1e-12)" ||
    fail "drag-2d: $f draws the displacements x $s, expected the bodies at true scale"
done
grep -qP "^deformed_mesh\tsuptitle\t.*true scale, colour: \\\$\|u\|\\\$" drag.txt ||
  fail "drag-2d: the deformed mesh's title: $(field drag.txt deformed_mesh suptitle)"
grep -qP "^deformed_mesh\tcolorbar\tdisplacement \\\$\|u\|\\\$ \[m\]$" drag.txt || fail "drag-2d: no |u| colour bar"
grep -qP "^deformed_mesh\tlegend\tslave nodes in contact: [1-9]" drag.txt ||
  fail "drag-2d: $(grep -P '^deformed_mesh\tlegend' drag.txt | tr '\n' ' ')"
grep -qP "^von_mises_beta\tsuptitle\t.*on the deformed configuration \(true scale\)$" drag.txt ||
  fail "drag-2d: $(field drag.txt von_mises_beta suptitle)"
# friction.png against t: every curve's x data is history.csv's t.
"$python" - drag/history.csv "$(field drag.drawn friction x)" <<'PY' || fail "drag-2d: friction.png is not drawn against t"
import csv, sys
t = [float(r["t"]) for r in csv.DictReader(open(sys.argv[1]))]
curves = [[float(v) for v in c.split(",")] for c in sys.argv[2].split(";")]
assert len(curves) >= 2 and all(c == t for c in curves), (t, curves)
PY
[ "$(field drag.txt friction xlabel | head -1)" = 'time $t$ [s]' ] || fail "drag-2d: friction.png's forces against $(field drag.txt friction xlabel | head -1)"
grep -qP "^friction\tylabel\tforce on the master side \[N/m\]$" drag.txt || fail "drag-2d: $(field drag.txt friction ylabel | head -1)"
grep -qP "^friction\tylabel\tfrictional dissipation \[J/m\]$" drag.txt ||
  fail "drag-2d: the dissipation's unit: $(field drag.txt friction ylabel | tail -1)"
"$vpcontact" run drag.toml -q -o dragmm --set case.units=mm-N-MPa || fail "run drag.toml in mm-N-MPa"
texts dragmm
grep -qP "^friction\tylabel\tfrictional dissipation \[mJ/mm\]$" dragmm.txt ||
  fail "drag-2d in mm-N-MPa: the dissipation's unit: $(field dragmm.txt friction ylabel | tail -1)"
echo "2D pair with friction: ok"

# --- nafems-roller-2d: in mm, N, MPa.
"$vpcontact" run nafems-roller-2d -q -o roller || fail "run nafems-roller-2d"
"$python" -c "import json, sys; sys.exit(json.load(open('roller/summary.json'))['units'] != 'mm-N-MPa')" ||
  fail "nafems-roller-2d: summary.json units is not mm-N-MPa"
texts roller
grep -qP '\[m\]|N/m(?!m)' roller.txt && fail "nafems-roller-2d: SI units in a label: $(grep -P '\[m\]|N/m(?!m)' roller.txt | head -3)"
for want in $'deformed_mesh\txlabel\t$x$ [mm]' $'von_mises_beta\tcolorbar\t$|\\sigma|_{\\mathrm{VM}}$ [MPa]' \
            $'history\tylabel\tforce [N/mm]'; do
  grep -qF "$want" roller.txt || fail "nafems-roller-2d: no '$want': $(grep -F "$(echo "$want" | cut -f1-2)" roller.txt | head -2)"
done
drawn roller
s=$(field roller.drawn deformed_mesh scale)
"$python" -c "import sys; sys.exit(abs(float('$s') - 1) > 1e-12)" ||
  fail "nafems-roller-2d: the roller drawn with its displacement x $s (into the block)"
echo "nafems-roller-2d: ok"
echo "test_pair_figures: all passed"
