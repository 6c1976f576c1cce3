#!/usr/bin/env bash
# Runs vpcontact on small cases and checks that scripts/vpcontact_plot.py draws
# every expected figure, under the paper's names for paper-1d/paper-2d and
# neutral names for other cases (a renamed 1D rod, a 4 x 1 strip), as a PNG
# of the expected pixel size (figure size in inches x dpi, see FIGSIZES in the
# script; the 2D field figures follow the domain's shape), as PDF and SVG too;
# that it reads zlib-compressed VTU files exactly as raw ones and the damage
# field under both names ('beta', formerly 'damage'); that the contact
# pressure figure is drawn from the 'contact_pressure' field; that colour bars
# stay within their plot's height and legends off the plots (check_plot.py);
# skips the VTU-based figures of a --no-vtu run, and fails with a one-line
# message on a non-output directory.
#
# Usage: tests/plot/test_plot.sh PATH/TO/vpcontact TMPDIR
# Needs /usr/bin/python3 with Debian's python3-numpy and python3-matplotlib
# (override the interpreter with PYTHON=...).
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: $0 VPCONTACT_BINARY TMPDIR" >&2
  exit 2
fi
vpcontact=$1
tmp=$2
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
script="$here/../../scripts/vpcontact_plot.py"
python=${PYTHON:-/usr/bin/python3}
dpi=150

fail() { echo "test_plot: FAIL: $*" >&2; exit 1; }

[ -x "$vpcontact" ] || fail "vpcontact binary '$vpcontact' not found or not executable"
[ -f "$script" ] || fail "plot script '$script' not found"
mkdir -p "$tmp"
out="$tmp/plot-test"
rm -rf "$out"

"$vpcontact" run paper-1d -q -o "$out/p1" || fail "vpcontact run paper-1d failed"
"$vpcontact" run paper-2d -q --n 10 --steps 10 -o "$out/p2" || fail "vpcontact run paper-2d failed"
"$vpcontact" run block-3d -q --n 5 --steps 5 -o "$out/p3" || fail "vpcontact run block-3d failed"
"$vpcontact" run paper-1d -q --every 0 -o "$out/e0" || fail "vpcontact run paper-1d --every 0 failed"
"$vpcontact" run paper-2d -q --n 10 --steps 10 --no-vtu -o "$out/nv" || fail "vpcontact run paper-2d --no-vtu failed"
# The user's own cases: the paper's files with another name (and a 4 x 1 domain).
sed -e 's/^name = "paper-1d"/name = "my-rod"/' "$here/../../cases/paper-1d.toml" > "$out/rod.toml"
sed -e 's/^name = "paper-2d"/name = "strip-4x1"/' -e 's/^upper = .*/upper = [4.0, 1.0]/' \
    -e 's/^cells = .*/cells = [20, 5]/' -e 's/x > 0.8 \&\& x < 1.2/x > 1.8 \&\& x < 2.2/' \
    -e 's/^probes = .*/probes = [[2.0, 0.0], [2.0, 0.5]]/' "$here/../../cases/paper-2d.toml" > "$out/strip.toml"
grep -q 'upper = \[4.0, 1.0\]' "$out/strip.toml" && grep -q 'x > 1.8' "$out/strip.toml" ||
  fail "could not derive the 4 x 1 strip case from cases/paper-2d.toml"
"$vpcontact" run "$out/rod.toml" -q -o "$out/u1" || fail "vpcontact run rod.toml failed"
"$vpcontact" run "$out/strip.toml" -q --steps 10 -o "$out/u2" || fail "vpcontact run strip.toml failed"

# block-3d again, its VTU files rewritten with a contact_pressure field (if the
# writer did not add one), 'damage' renamed 'beta' and zlib-compressed.
cp -r "$out/p3" "$out/p3z"
for f in "$out"/p3z/solution_*.vtu; do
  if ! grep -aq 'Name="contact_pressure"' "$f"; then
    "$python" "$here/vtu_tools.py" add-pressure "$f" "$f.tmp" && mv "$f.tmp" "$f" || fail "vtu_tools add-pressure $f"
  fi
  if grep -aq 'Name="damage"' "$f"; then
    "$python" "$here/vtu_tools.py" damage-to-beta "$f" "$f.tmp" && mv "$f.tmp" "$f" || fail "vtu_tools damage-to-beta $f"
  fi
  "$python" "$here/vtu_tools.py" compress "$f" "$f.tmp" 2048 && mv "$f.tmp" "$f" || fail "vtu_tools compress $f"
done
# paper-1d with the damage field under the other name ('beta' <-> 'damage').
cp -r "$out/p1" "$out/p1r"
for f in "$out"/p1r/solution_*.vtu; do
  if grep -aq 'Name="damage"' "$f"; then how=damage-to-beta; else how=beta-to-damage; fi
  "$python" "$here/vtu_tools.py" $how "$f" "$f.tmp" && mv "$f.tmp" "$f" || fail "vtu_tools $how $f"
done
rm -rf "$out/p1r/figures"

for d in p1 p1r p2 p3 p3z e0 nv u1 u2; do
  "$python" "$script" "$out/$d" --dpi "$dpi" > "$out/$d.log" 2>&1 ||
    fail "vpcontact_plot.py $out/$d exited non-zero: $(tail -n 1 "$out/$d.log")"
done

# A directory that is not a vpcontact output: non-zero exit, one line naming summary.json.
mkdir -p "$out/empty"
if "$python" "$script" "$out/empty" > "$out/empty.log" 2>&1; then
  fail "vpcontact_plot.py accepted a directory without summary.json"
fi
grep -q "summary.json not found" "$out/empty.log" || fail "unclear message for a non-output directory: $(cat "$out/empty.log")"

# The --no-vtu run: the VTU figures are reported as skipped and not written.
for f in fig_4_6_deformed_mesh fig_4_7_von_mises_damage; do
  grep -q "skipped: $f.png" "$out/nv.log" || fail "--no-vtu run: '$f' not reported as skipped"
  [ ! -e "$out/nv/figures/$f.png" ] || fail "--no-vtu run: '$f.png' written without VTU files"
done

# The compressed block-3d: its contact pressure figure is drawn.
grep -q "skipped" "$out/p3z.log" && fail "compressed block-3d: a figure was skipped: $(grep skipped "$out/p3z.log")"
# The damage field read under either name: the same figure, byte for byte.
cmp -s "$out/p1/figures/fig_4_4_damage.png" "$out/p1r/figures/fig_4_4_damage.png" ||
  fail "fig_4_4_damage.png differs when the VTU field is named 'beta' instead of 'damage' (or back)"
# No paper name and no "Fig. 4." for the user's cases.
for d in u1 u2 p3; do
  if ls "$out/$d/figures" | grep -q '^fig_'; then fail "$d: paper figure names for a user case: $(ls "$out/$d/figures")"; fi
done

# Every expected PNG: exists, is a PNG, has the expected size (width x height at $dpi).
"$python" - "$out" "$dpi" <<'PY'
import struct
import sys

out, dpi = sys.argv[1], float(sys.argv[2])
inches = {  # the figures whose size does not depend on the domain (FIGSIZES in the script)
    "fig_4_2_displacement_stress": (12.0, 4.8), "displacement_stress": (12.0, 4.8),
    "fig_4_3_time_histories": (12.0, 4.8), "time_histories": (12.0, 4.8),
    "fig_4_4_damage": (12.0, 4.8), "beta": (12.0, 4.8),
    "surface_von_mises": (13.0, 6.0),
    "surface_beta": (13.0, 6.0),
    "contact_pressure": (13.0, 5.6),
    "probes": (15.0, 4.8),
    "history": (12.0, 4.8),
}
# The 2D field figures follow the domain: (min, max) of width / height.
ratios = {
    ("p2", "fig_4_6_deformed_mesh"): (0.8, 1.1),      # the square block, displacements magnified
    ("p2", "fig_4_7_von_mises_damage"): (1.8, 2.4),   # two square plots side by side
    ("u2", "deformed_mesh"): (1.8, 3.0),              # a 4 x 1 strip
    ("u2", "von_mises_beta"): (1.0, 1.6),             # two strips, one above the other
}
expected = {
    "p1": ["fig_4_2_displacement_stress", "fig_4_3_time_histories", "fig_4_4_damage", "history"],
    "p1r": ["fig_4_2_displacement_stress", "fig_4_3_time_histories", "fig_4_4_damage", "history"],
    "e0": ["fig_4_2_displacement_stress", "fig_4_3_time_histories", "fig_4_4_damage", "history"],
    "u1": ["displacement_stress", "time_histories", "beta", "history"],
    "p2": ["fig_4_6_deformed_mesh", "fig_4_7_von_mises_damage", "probes", "history"],
    "u2": ["deformed_mesh", "von_mises_beta", "probes", "history"],
    "p3": ["surface_von_mises", "surface_beta", "probes", "history"],
    "p3z": ["surface_von_mises", "surface_beta", "contact_pressure", "probes", "history"],
    "nv": ["probes", "history"],
}
errors = []
for run, names in expected.items():
    for name in names:
        path = "%s/%s/figures/%s.png" % (out, run, name)
        try:
            with open(path, "rb") as f:
                head = f.read(33)
        except OSError:
            errors.append("%s: missing" % path)
            continue
        if len(head) < 33 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
            errors.append("%s: not a PNG file" % path)
            continue
        w, h = struct.unpack(">II", head[16:24])
        if (run, name) in ratios:
            lo, hi = ratios[(run, name)]
            if not (lo <= w / h <= hi and 600 <= w <= 2400 and 400 <= h <= 2000):
                errors.append("%s: %dx%d pixels, expected width/height in [%g, %g]" % (path, w, h, lo, hi))
            continue
        want = tuple(int(round(x * dpi)) for x in inches[name])
        if (w, h) != want:
            errors.append("%s: %dx%d pixels, expected %dx%d" % (path, w, h, want[0], want[1]))
for e in errors:
    print("test_plot: FAIL: " + e, file=sys.stderr)
sys.exit(1 if errors else 0)
PY

# PDF and SVG: every figure of a 2D and a 3D run.
for fmt in pdf svg; do
  for d in p2 p3z; do
    "$python" "$script" "$out/$d" --format $fmt --dpi 100 > "$out/$d.$fmt.log" 2>&1 ||
      fail "vpcontact_plot.py $out/$d --format $fmt: $(tail -n 1 "$out/$d.$fmt.log")"
    n_png=$(ls "$out/$d/figures"/*.png | wc -l)
    n_fmt=$(ls "$out/$d/figures"/*.$fmt 2>/dev/null | wc -l)
    [ "$n_fmt" -eq "$n_png" ] || fail "$d: $n_fmt .$fmt figures for $n_png .png"
    for f in "$out/$d/figures"/*.$fmt; do
      case $fmt in
        pdf) head -c 5 "$f" | grep -q '%PDF-' || fail "$f is not a PDF file" ;;
        svg) grep -q '<svg' "$f" || fail "$f is not an SVG file" ;;
      esac
    done
  done
done

# The compressed-VTU reader against the raw one; colour bars and legends of a
# non-square case and of the contact pressure figure.
"$python" "$here/check_plot.py" reader "$out/p2" "$out/p3" > "$out/reader.log" 2>&1 ||
  fail "$(tail -n 1 "$out/reader.log")"
for d in u2 p3z; do
  "$python" "$here/check_plot.py" layout "$out/$d" > "$out/layout-$d.log" 2>&1 || fail "$(tail -n 1 "$out/layout-$d.log")"
done
echo "test_plot: OK (figures in $out)"
