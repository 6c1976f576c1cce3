#!/usr/bin/env bash
# Issue 15 on the command line: a finished run continued to a later T is the longer
# run bit for bit (history.csv identical); a resume with other steps before the
# checkpoint is refused with the step that differs; error-controlled steps write
# their sizes, estimates and rejections and their k(t) figure; converge --adaptive
# runs error-controlled levels beside the fixed ones; an error-controlled run continued to a
# later T with its limits given is the longer run.
#
# Usage: tests/cli/test_time_steps.sh PATH/TO/vpcontact TMPDIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
fail() { echo "test_time_steps: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1

# Extend: T = 1 with 20 steps, continued to T = 2 with 40 steps = the run to T = 2.
"$vpcontact" run paper-1d -q --no-vtu --steps 20 -o extended > log1 2>&1 || fail "run to T = 1: $(cat log1)"
"$vpcontact" run paper-1d --no-vtu --set time.T=2 --steps 40 --resume extended > log2 2>&1 ||
  fail "continued to T = 2: $(cat log2)"
grep -q "resuming from the checkpoint of step 20 (t = 1)" log2 || fail "not resumed from step 20: $(cat log2)"
"$vpcontact" run paper-1d -q --no-vtu --set time.T=2 --steps 40 -o longer > log3 2>&1 || fail "run to T = 2: $(cat log3)"
[ "$(wc -l < extended/history.csv)" -eq 41 ] || fail "the continued history has $(wc -l < extended/history.csv) lines, not 41"
# Bit for bit, β = 0 at some nodes in the last step included (the damage solver's choice of
# method for its reduced systems does not depend on timings, so a resumed run makes it alike).
cmp -s extended/history.csv longer/history.csv || fail "the continued run differs from the longer run: $(diff extended/history.csv longer/history.csv | head -4)"

# Other steps before the checkpoint: refused, naming the step.
"$vpcontact" run paper-1d -q --no-vtu --set time.T=2 --steps 80 --resume extended > log4 2>&1 &&
  fail "a resume with other steps was accepted"
grep -q "the steps differ from step 1 on: t = 0.050000000000000003 in the checkpoint, 0.025000000000000001 in this case" log4 ||
  fail "the refusal does not say where the steps differ: $(cat log4)"

# Error-controlled steps: landing on the output times, rejections at the contact onset, k(t) drawn.
"$vpcontact" run paper-1d -q --set time.tolerance=2e-3 --plot -o adaptive > log5 2>&1 || fail "adaptive run: $(cat log5)"
head -1 adaptive/history.csv | grep -q ",dt,error_estimate,rejected" || fail "history.csv has no dt, error_estimate, rejected"
/usr/bin/python3 - adaptive <<'PY' || fail "adaptive history: see above"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/history.csv")))
s = json.load(open(sys.argv[1] + "/summary.json"))
assert float(rows[-1]["t"]) == 1.0, rows[-1]["t"]
assert sum(int(r["rejected"]) for r in rows) > 0, "no step was rejected"
assert all(float(r["error_estimate"]) <= 2e-3 * float(r["dt"]) * (1 + 1e-12) for r in rows), "a step above the tolerance"
assert s["rejected_steps"] == sum(int(r["rejected"]) for r in rows)
times = {round(float(r["t"]), 12) for r in rows}
assert all(round(0.1 * i, 12) in times for i in range(1, 11)), "an output time was not a step's end"
PY
[ -f adaptive/figures/time_steps.png ] || fail "no time_steps.png: $(cat log5)"
[ "$(ls adaptive/solution_*.vtu | wc -l)" -eq 11 ] || fail "not 11 VTU files (t = 0, 0.1, ..., 1): $(ls adaptive)"

# Error-controlled, continued to T = 2 (issue 26 item 7, docs/cases.md "Continuing a run"): the
# longer run bit for bit when the limits that default to T/100, T/10 are given and both runs end
# steps at the same output times up to t = 1.
limits="--set time.tolerance=2e-3 --set time.dt_initial=0.01 --set time.dt_max=0.1 --set time.dt_min=1e-6 --set time.event_dt=0.01"
"$vpcontact" run paper-1d -q --no-vtu $limits --set 'output.times=[0.5, 1.0]' -o adaptive_to1 > log7 2>&1 ||
  fail "adaptive run to T = 1: $(cat log7)"
"$vpcontact" run paper-1d -q --no-vtu $limits --set time.T=2 --set 'output.times=[0.5, 1.0, 2.0]' --resume adaptive_to1 \
  > log8 2>&1 || fail "adaptive run continued to T = 2: $(cat log8)"
"$vpcontact" run paper-1d -q --no-vtu $limits --set time.T=2 --set 'output.times=[0.5, 1.0, 2.0]' -o adaptive_to2 \
  > log9 2>&1 || fail "adaptive run to T = 2: $(cat log9)"
cmp -s adaptive_to1/history.csv adaptive_to2/history.csv ||
  fail "the continued error-controlled run differs from the longer run: $(diff adaptive_to1/history.csv adaptive_to2/history.csv | head -4)"

# converge --adaptive: fixed and error-controlled levels, compared at the base grid's times.
"$vpcontact" converge paper-1d --sequence k --levels 2 --steps 10 --adaptive 4e-3 --no-plot -q -o conv > log6 2>&1 ||
  fail "converge --adaptive: $(cat log6)"
grep -q "error-controlled levels (max over the base grid's times" log6 || fail "no error-controlled levels: $(cat log6)"
[ -f conv/convergence_k_adaptive.csv ] || fail "no convergence_k_adaptive.csv"
echo "test_time_steps: all passed"
