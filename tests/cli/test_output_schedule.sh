#!/usr/bin/env bash
# Issue 26 item 6: the VTU schedule follows the kind of time grid. With error-controlled
# steps (`--set time.tolerance=...` on a case with steps), `output.every` counts the
# steps of the fixed grid the tolerance replaced, so the run writes the files the fixed
# run would, at its times (it wrote one every `every` accepted steps: 8,379 files for
# block_cyl.toml); a case whose own steps are error-controlled cannot count them before
# the run and is refused with every > 0.
#
# Usage: tests/cli/test_output_schedule.sh PATH/TO/vpcontact TMPDIR SOURCE_DIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
src=$3
fail() { echo "test_output_schedule: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1

times() { grep -o 'timestep="[^"]*"' "$1/solution.pvd" | sed 's/timestep="\(.*\)"/\1/' | tr '\n' ' '; }

# paper-1d: steps = 100; every 2 steps of that grid: t = 0.02, 0.04, ..., 1, and the initial state.
"$vpcontact" run paper-1d --set output.every=2 --set time.tolerance=1e-2 -q -o every2 || fail "every = 2 under tolerance"
n=$(ls every2/solution_*.vtu | wc -l)
[ "$n" -eq 51 ] || fail "every = 2 of 100 steps under tolerance: $n VTU files, expected 51 (the fixed grid's 50 and t = 0)"
t=$(times every2)
case "$t" in "0 0.02 0.040000000000000001 0.059999999999999998 "*" 1 ") ;; *) fail "every = 2: VTU times $t" ;; esac
# --every is the same key; the times are the fixed grid's, which the steps end at.
"$vpcontact" run paper-1d --set time.tolerance=1e-2 --every 25 -q -o every25 || fail "--every 25 under tolerance"
[ "$(times every25)" = "0 0.25 0.5 0.75 1 " ] || fail "--every 25 under tolerance: VTU times $(times every25)"
# The grid is the file's with the case's T: 100 steps of T / 100 = 0.02.
"$vpcontact" run paper-1d --set time.tolerance=1e-2 --set time.T=2 --every 50 -q -o longer || fail "T = 2"
[ "$(times longer)" = "0 1 2 " ] || fail "--every 50, T = 2 under tolerance: VTU times $(times longer)"

# A case whose own steps are error-controlled: every > 0 is refused, on one located line.
sed -e 's/^steps = 100.*/tolerance = 1e-2/' -e 's/^\[output\].*/[output]\nevery = 5/' "$src/cases/paper-1d.toml" > tol.toml
grep -q '^every = 5' tol.toml || fail "could not make tol.toml"
"$vpcontact" run tol.toml -q -o refused > out.log 2> err.log && fail "every = 5 with the case's own tolerance was accepted"
[ "$(wc -l < err.log)" -eq 1 ] || fail "not one line: $(cat err.log)"
grep -Eq '^vpcontact: error: tol.toml:[0-9]+:[0-9]+: output.every: counts the steps of a fixed grid, but \[time\] tolerance chooses the steps during the run .*give times = \[...\]' err.log ||
  fail "message: $(cat err.log)"
"$vpcontact" run tol.toml --every 0 -q -o final || fail "every = 0 with tolerance"
[ "$(times final)" = "0 1 " ] || fail "every = 0 under tolerance: VTU times $(times final)"
echo "test_output_schedule: ok"
