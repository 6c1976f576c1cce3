#!/usr/bin/env bash
# Issue 28: `vpcontact plot` of a frictional run draws friction.png: the tangential force
# (the force on the obstacle) against t (issue 48: not a probe's displacement, which may move
# a little and back), with the normal force, and the stick/slip counts and dissipation per step; a frictionless
# run has no such figure (nothing skipped either). The frictional run: tests/data/friction-2d.toml
# (a block pressed onto a plane, then pushed sideways until it slides at μ times the normal force).
#
# Usage: tests/plot/test_friction_plot.sh PATH/TO/vpcontact TMPDIR SOURCE_DIR
set -uo pipefail
vpcontact=$1 tmp=$2 src=$3
friction_case="$src/tests/data/friction-2d.toml"
python=${PYTHON:-/usr/bin/python3}
script="$src/scripts/vpcontact_plot.py"
fail() { echo "test_friction_plot: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" || exit 1

"$vpcontact" run paper-2d -q --n 10 --steps 10 -o "$tmp/plain" || fail "run paper-2d"
"$python" "$script" "$tmp/plain" > "$tmp/plain.log" 2>&1 || fail "plot paper-2d: $(tail -1 "$tmp/plain.log")"
[ ! -e "$tmp/plain/figures/friction.png" ] || fail "a frictionless run got friction.png"
grep -q "friction\.png" "$tmp/plain.log" && fail "a frictionless run mentions friction.png: $(grep friction "$tmp/plain.log")"

"$vpcontact" run "$friction_case" -q -o "$tmp/fric" || fail "run $friction_case"
"$python" "$script" "$tmp/fric" > "$tmp/fric.log" 2>&1 || fail "plot the frictional run: $(tail -1 "$tmp/fric.log")"
grep -q "skipped" "$tmp/fric.log" && fail "a figure was skipped: $(grep skipped "$tmp/fric.log")"
"$python" - "$tmp/fric/figures/friction.png" <<'PY' || exit 1
import struct, sys
with open(sys.argv[1], "rb") as f:
    head = f.read(24)
assert head[:8] == b"\x89PNG\r\n\x1a\n", "%s: not a PNG" % sys.argv[1]
w, h = struct.unpack(">II", head[16:24])
assert (w, h) == (1800, 720), "%s: %dx%d pixels, expected 1800x720 (FIGSIZES 12 x 4.8 in at 150 dpi)" % (sys.argv[1], w, h)
PY
[ $? -eq 0 ] || fail "friction.png"
# Its texts: the tangential force against t, the counts, the dissipation (a work per unit thickness).
"$python" "$src/tests/plot/check_plot.py" texts "$tmp/fric" > "$tmp/fric.txt" 2> "$tmp/fric.err" ||
  fail "texts: $(tail -1 "$tmp/fric.err")"
for want in $'friction\txlabel\ttime $t$ [s]' $'friction\tylabel\tfrictional dissipation [J/m]' $'friction\tlegend\ttangential force, x' $'friction\tlegend\tnormal force' \
            $'friction\tlegend\tstick nodes' $'friction\tlegend\tslip nodes' $'friction\tlegend\tdissipation so far'; do
  grep -qF "$want" "$tmp/fric.txt" || fail "friction.png has no '$want': $(grep '^friction' "$tmp/fric.txt")"
done
echo "test_friction_plot: all passed"
