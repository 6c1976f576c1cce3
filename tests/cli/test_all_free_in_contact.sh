#!/usr/bin/env bash
# Issue 26 item 4: every free node a contact node (a layer one element thick clamped on
# top, pressed onto a zero gap: the exact u is 0). The default contact solver (the dual
# active set) refused it with "converged ... residual 1.00e+00": the residuals' displacement
# scale max(|u|, |g|) was the dual's round-off in u itself. It must solve the reporter's three
# cases and agree with primal-active-set (forces, reactions) to the solvers' tolerance.
#
# Usage: tests/cli/test_all_free_in_contact.sh PATH/TO/vpcontact TMPDIR DATA_DIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
data=$(cd "$3" && pwd)
fail() { echo "test_all_free_in_contact: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1
cp "$data"/thin.toml "$data"/thin3d.toml . || exit 1

compare() {  # name, then the case's arguments
  local name=$1
  shift
  "$vpcontact" run "$@" -q --no-vtu --engine serial -o "dual_$name" > "log_dual_$name" 2>&1 ||
    fail "$name with the default contact solver: $(cat "log_dual_$name")"
  "$vpcontact" run "$@" -q --no-vtu --engine serial --contact-solver primal-active-set -o "primal_$name" \
    > "log_primal_$name" 2>&1 || fail "$name with primal-active-set: $(cat "log_primal_$name")"
  /usr/bin/python3 - "dual_$name" "primal_$name" <<'PY' || fail "$name: the solvers disagree (see above)"
import csv, json, sys
dual, primal = sys.argv[1], sys.argv[2]
assert json.load(open(dual + "/summary.json"))["contact_solver"] == "active-set", "the default is not the dual solver"
a = list(csv.DictReader(open(dual + "/history.csv")))
b = list(csv.DictReader(open(primal + "/history.csv")))
assert len(a) == len(b) == 2, (len(a), len(b))
for ra, rb in zip(a, b):
    assert ra["ok"] == rb["ok"] == "1", (ra["ok"], rb["ok"])
    assert ra["n_active"] == rb["n_active"], (ra["n_active"], rb["n_active"])
    scale = abs(float(rb["total_contact_force"]))
    for key in ["total_contact_force"] + [k for k in ra if k.startswith("reaction_")]:
        x, y = float(ra[key]), float(rb[key])
        assert abs(x - y) <= 1e-10 * scale, (key, x, y)
    for key in ["contact_equilibrium", "contact_penetration", "contact_negative_force", "contact_complementarity"]:
        assert float(ra[key]) <= 1e-12, (key, ra[key])
PY
}
compare square thin.toml
compare layer thin.toml --set 'mesh.upper=[10.0,0.1]' --set 'mesh.cells=[100,1]'
compare layer3d thin3d.toml
echo "test_all_free_in_contact: all passed"
