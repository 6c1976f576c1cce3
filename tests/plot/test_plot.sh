#!/usr/bin/env bash
# Runs vpcontact on small cases and checks that scripts/vpcontact_plot.py draws
# every expected figure as a PNG of the expected pixel size (figure size in
# inches x dpi, see FIGSIZES in the script), skips the VTU-based figures of a
# --no-vtu run, and fails with a one-line message on a non-output directory.
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

for d in p1 p2 p3 e0 nv; do
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

# Every expected PNG: exists, is a PNG, has the expected size (width x height at $dpi).
"$python" - "$out" "$dpi" <<'PY'
import struct
import sys

out, dpi = sys.argv[1], float(sys.argv[2])
inches = {
    "fig_4_2_displacement_stress": (12.0, 4.8),
    "fig_4_3_time_histories": (12.0, 4.8),
    "fig_4_4_damage": (12.0, 4.8),
    "fig_4_6_deformed_mesh": (8.0, 7.2),
    "fig_4_7_von_mises_damage": (13.0, 5.6),
    "surface_von_mises": (13.0, 6.0),
    "surface_damage": (13.0, 6.0),
    "contact_pressure": (12.0, 5.6),
    "probes": (15.0, 4.8),
    "history": (12.0, 4.8),
}
expected = {
    "p1": ["fig_4_2_displacement_stress", "fig_4_3_time_histories", "fig_4_4_damage", "history"],
    "e0": ["fig_4_2_displacement_stress", "fig_4_3_time_histories", "fig_4_4_damage", "history"],
    "p2": ["fig_4_6_deformed_mesh", "fig_4_7_von_mises_damage", "probes", "history"],
    "p3": ["surface_von_mises", "surface_damage", "contact_pressure", "probes", "history"],
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
        want = tuple(int(round(x * dpi)) for x in inches[name])
        if (w, h) != want:
            errors.append("%s: %dx%d pixels, expected %dx%d" % (path, w, h, want[0], want[1]))
for e in errors:
    print("test_plot: FAIL: " + e, file=sys.stderr)
sys.exit(1 if errors else 0)
PY
echo "test_plot: OK (figures in $out)"
