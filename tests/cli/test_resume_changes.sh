#!/usr/bin/env bash
# --resume with a changed case, and the output's size (issue 48), on the reported case
# (tests/data/reported/resume_changed_law.toml: a frictional block, E = 1000, mu = 0.3):
#   - another E or mu is refused, naming the key and both values; the run's files stay as they were;
#   - a later T is continued, printed in the header and recorded in summary.json;
#   - `check` prints the output's estimated size; 10^8 steps with a VTU file at each is refused.
#   test_resume_changes.sh VPCONTACT WORKDIR CASE
set -euo pipefail
V=$1 W=$2 C=$3
rm -rf "$W" && mkdir -p "$W" && cd "$W"
cp "$C" c.toml
fail() { echo "test_resume_changes: $*"; exit 1; }
refused() {  # WHAT EXPECTED ARGS...: the resume exits 1 and its error has EXPECTED
  local what=$1 expected=$2; shift 2
  if "$V" run c.toml -o out -q --no-vtu "$@" --resume out 2> err.txt; then fail "$what: resumed"; fi
  grep -qF -- "$expected" err.txt || { cat err.txt; fail "$what: the error does not say '$expected'"; }
}
"$V" run c.toml -o out -q --no-vtu --set time.T=1.0 --steps 10
cp out/history.csv history_before.csv
refused "another E" "was written for another case: elasticity.E: 1000 → 2000" --set elasticity.E=2000
refused "another mu" "contact.mu: 0.3 → 0.6" --set contact.mu=0.6
refused "another kappa" "damage.kappa: (not given) → 0.5" --set damage.kappa=0.5
cmp out/history.csv history_before.csv || fail "a refused resume changed history.csv"
"$V" run c.toml -o out --no-vtu --resume out > log.txt  # the file's T = 2, steps = 20
grep -qF "changed on resume: time.T: 1 → 2" log.txt && grep -qF "changed on resume: time.steps: 10 → 20" log.txt ||
  { cat log.txt; fail "a later T: not printed"; }
/usr/bin/python3 - out/summary.json <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
changed = {c["key"]: (c["step"], c["checkpoint"], c["now"]) for c in s["changed_on_resume"]}
assert changed == {"time.T": (10, "1", "2"), "time.steps": (10, "10", "20")}, changed
assert s["steps"] == 20, s["steps"]
PY
echo "a changed E, mu or kappa refused by its key; a later T continued and recorded"
# 10^6 steps: about 0.5 GiB, which any test machine has free (10^8 steps, 44 GiB, did not always).
"$V" check c.toml --steps 1000000 > log.txt
grep -qE "output: about .* \(history.csv .*: 1000000 steps of [0-9]+ B; .*\); .* free where 'output/fr2' is" log.txt ||
  { cat log.txt; fail "check: no estimate of the output"; }
if "$V" check c.toml --steps 100000000 --set output.every=1 > /dev/null 2> err.txt; then fail "10^8 VTU files accepted"; fi
grep -qE "error: the output would take about [0-9.]+ [TPE]iB .*100000001 VTU files.*, more than the .* free where 'output/fr2' is: use fewer steps" err.txt ||
  { cat err.txt; fail "10^8 VTU files: not the expected error"; }
echo "check: the output's size estimated, 10^8 VTU files refused"
echo "test_resume_changes: all passed"
