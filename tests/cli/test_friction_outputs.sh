#!/usr/bin/env bash
# Issue 28: a frictional run's outputs agree with each other and survive a resume bit for bit.
#   - history.csv has friction's columns after the reactions (n_stick, n_slip, dissipation, the
#     friction residuals, tangential_force_<x|y>, tangential_force_<obstacle>_<x|y>);
#   - the final VTU has tangential_force, tangential_traction, slip_increment, slip and
#     contact_status, and their sums and counts are the history's and summary.json's: Σ of the
#     nodal tangential force (on the body) = −the history's total (on the obstacle), the statuses = n_stick and n_slip, the
#     traction × the tributary measure (= force / pressure × λ_ν) = the force;
#   - summary.json's friction block: the final counts, the dissipation summed over the steps,
#     the residuals' maxima;
#   - [output] fields selects friction's fields like the others;
#   - interrupted after its checkpoint of step 6 and resumed: history.csv, probes.csv, the last
#     VTU and summary.json's results byte for byte those of the uninterrupted run.
#
# Usage: tests/cli/test_friction_outputs.sh PATH/TO/vpcontact TMPDIR SOURCE_DIR
set -uo pipefail
vpcontact=$1 tmp=$2 src=$3
python=${PYTHON:-/usr/bin/python3}
case_file="$src/tests/data/friction-2d.toml"
fail() { echo "test_friction_outputs: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" || exit 1

"$vpcontact" run "$case_file" -q --every 10 -o "$tmp/A" > "$tmp/A.log" 2>&1 || fail "run: $(tail -3 "$tmp/A.log")"
"$python" - "$tmp/A" "$src/scripts" <<'PY' || fail "the outputs disagree (above)"
import csv, json, os, sys
import numpy as np
out = sys.argv[1]
sys.path.insert(0, sys.argv[2])
import vpcontact_plot as vp

rows = list(csv.reader(open(os.path.join(out, "history.csv"))))
head = rows[0]
h = {c: np.array([float(r[i]) for r in rows[1:]]) for i, c in enumerate(head)}
friction = ["n_stick", "n_slip", "dissipation", "friction_bound", "friction_stick_slip", "friction_slip_direction",
            "tangential_force_x", "tangential_force_y", "tangential_force_plane_x", "tangential_force_plane_y"]
assert head[-len(friction):] == friction, head
assert head.index("n_stick") > max(i for i, c in enumerate(head) if c.startswith("reaction_")), head
last = {c: v[-1] for c, v in h.items()}
assert (h["dissipation"] >= 0).all(), h["dissipation"]
assert last["tangential_force_x"] > 0, "pushed towards +x: the force on the plane is along +x"
assert np.array_equal(h["tangential_force_x"], h["tangential_force_plane_x"])  # one obstacle: all of it

vtu = vp.read_vtu(os.path.join(out, "solution_00010.vtu"))
for name, comps in (("tangential_force", 3), ("tangential_traction", 3), ("slip_increment", 3), ("slip", 1),
                    ("contact_status", 1), ("contact_lambda", 2)):
    a = vtu.point_data.get(name)
    assert a is not None, "final VTU has no %s: %s" % (name, sorted(vtu.point_data))
    assert (a.shape[1] if a.ndim == 2 else 1) == comps, (name, a.shape)
f = vtu.point_data["tangential_force"]
scale = max(1.0, abs(last["tangential_force_x"]))
# the field is the force on the body, the history's the force on the obstacle: opposite sums
assert abs(f[:, 0].sum() + last["tangential_force_x"]) <= 1e-12 * scale, (f[:, 0].sum(), last["tangential_force_x"])
assert abs(f[:, 1].sum() + last["tangential_force_y"]) <= 1e-12 * scale
assert np.abs(f[:, 1]).max() <= 1e-12 * scale, "the tangent of the plane y = 0 is x"
status = vtu.point_data["contact_status"]
assert int((status == 1).sum()) == last["n_stick"] and int((status == 2).sum()) == last["n_slip"], \
    ((status == 1).sum(), (status == 2).sum(), last["n_stick"], last["n_slip"])
# traction × measure = force, with measure = λ_ν / pressure where the node presses
lam, p = vtu.point_data["contact_lambda"][:, 0], vtu.point_data["contact_pressure"]
on = p > 0
assert on.any()
assert np.allclose(vtu.point_data["tangential_traction"][on, 0] * lam[on] / p[on], f[on, 0], rtol=1e-12, atol=1e-15)
assert (vtu.point_data["slip"] >= 0).all()

s = json.load(open(os.path.join(out, "summary.json")))
fr = s["friction"]
assert fr["n_stick"] == last["n_stick"] and fr["n_slip"] == last["n_slip"], (fr, last)
assert abs(fr["dissipation"] - h["dissipation"].sum()) <= 1e-12 * max(1e-300, abs(fr["dissipation"])), fr
for key, col in (("max_friction_bound", "friction_bound"), ("max_stick_slip", "friction_stick_slip"),
                 ("max_slip_direction", "friction_slip_direction")):
    assert float("%.3e" % fr[key]) == h[col].max(), (key, fr[key], h[col].max())
print("outputs agree: tangential force %.6g, %d stick, %d slip, dissipation %.6g"
      % (last["tangential_force_x"], fr["n_stick"], fr["n_slip"], fr["dissipation"]))
PY

# [output] fields selects friction's fields like the others.
"$vpcontact" run "$case_file" -q --every 10 --set 'output.fields=["slip", "contact_status"]' -o "$tmp/S" \
  > "$tmp/S.log" 2>&1 || fail "run with output.fields: $(tail -3 "$tmp/S.log")"
grep -aq 'Name="slip"' "$tmp/S/solution_00010.vtu" && grep -aq 'Name="contact_status"' "$tmp/S/solution_00010.vtu" ||
  fail "output.fields: slip or contact_status missing"
grep -aq 'Name="tangential_force"' "$tmp/S/solution_00010.vtu" && fail "output.fields: tangential_force written unasked"

# Interrupted after the checkpoint of step 6, resumed: byte for byte the uninterrupted run.
"$vpcontact" run "$case_file" -q --every 10 --checkpoint-every 6 -o "$tmp/B" > /dev/null 2>&1 || fail "run B"
"$vpcontact" run "$case_file" -q --every 10 --checkpoint-every 6 -o "$tmp/C" > /dev/null 2>&1 || fail "run C"
rm -f "$tmp"/C/checkpoint_00010*.bin  # as if killed after step 6 (the newest two: 6 and 10)
ls "$tmp"/C/checkpoint_00006.bin > /dev/null 2>&1 || fail "no checkpoint of step 6 to resume"
"$vpcontact" run "$case_file" -q --every 10 --checkpoint-every 6 --resume "$tmp/C" > "$tmp/C.log" 2>&1 ||
  fail "resume: $(tail -3 "$tmp/C.log")"
for f in history.csv probes.csv solution_00010.vtu; do
  cmp -s "$tmp/B/$f" "$tmp/C/$f" || fail "resumed run: $f differs from the uninterrupted run"
done
"$python" - "$tmp/B/summary.json" "$tmp/C/summary.json" <<'PY' || fail "resumed run: summary.json differs"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
for k in ("final", "checks", "friction"):
    assert a[k] == b[k], (k, a[k], b[k])
PY
echo "test_friction_outputs: all passed"
