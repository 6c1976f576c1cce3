#!/usr/bin/env bash
# The command line of issue 11: --version, help, one-line errors with exit 1
# (item 10); the output directory checked before set-up and an earlier run's
# outputs removed (item 9); the header and set-up stages in order, ESC[K on the
# progress line (item 8); --set replacing the keys it excludes, --n on a Gmsh
# case (item 11).
#
# Usage: tests/cli/test_cli.sh PATH/TO/vpcontact TMPDIR SOURCE_DIR VERSION
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
src=$3
version=$4
fail() { echo "test_cli: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1

# expect_error NAME REGEX ARGS...: exit 1 and exactly one line on stderr matching REGEX.
expect_error() {
  local name=$1 regex=$2
  shift 2
  "$vpcontact" "$@" > out.log 2> err.log
  local rc=$?
  [ "$rc" -eq 1 ] || fail "$name: exit code $rc, expected 1: $(cat err.log)"
  [ "$(wc -l < err.log)" -eq 1 ] || fail "$name: not one line: $(cat err.log)"
  grep -Eq "^vpcontact: error: $regex" err.log || fail "$name: message '$(cat err.log)' does not match '$regex'"
}

# --- item 10
"$vpcontact" --version | grep -Eq "^vpcontact $version \(git ([0-9a-f]{7,40}(-dirty)?|unknown)\)$" || fail "--version: $("$vpcontact" --version 2>&1)"
"$vpcontact" > help.log 2>&1 || fail "vpcontact alone exits non-zero"
grep -q "Subcommands:" help.log || fail "vpcontact alone prints no help"
expect_error "unknown option" "The following argument was not expected: --frobnicate" run paper-1d --frobnicate
expect_error "not a number" "Could not convert: --steps = ten" run paper-1d --steps ten
expect_error "unknown subcommand" "The following argument was not expected: rnu" rnu
expect_error "missing plot directory" "outdir is required" plot
expect_error "bad format" "--format: Check png,pdf,svg|--format: .*not in" plot . --format bmp
expect_error "unknown case to show" "unknown case 'paper-9d'" cases --show paper-9d
"$vpcontact" run --help > run_help.log || fail "run --help exits non-zero"
for c in $(cd "$src/cases" && ls *.toml | sed 's/\.toml$//'); do
  desc=$(grep -m1 '^description' "$src/cases/$c.toml" | sed 's/^description = "\(.*\)"/\1/')
  grep -qF "$c" run_help.log && grep -qF "$desc" run_help.log || fail "run --help does not list $c with '$desc'"
  "$vpcontact" cases --show "$c" | cmp -s - "$src/cases/$c.toml" || fail "cases --show $c differs from cases/$c.toml"
done
# Issue 26 item 22: the descriptions of the built-in cases start in one column (names longer than 10 were not).
columns=$(for c in $(cd "$src/cases" && ls *.toml | sed 's/\.toml$//'); do
  grep -E "^  $c +[^ ]" run_help.log | sed -E 's/^(  [^ ]+ +).*/\1/' | awk '{ print length($0) }'
done | sort -u | wc -l)
[ "$columns" -eq 1 ] || fail "run --help: the built-in cases' descriptions are not aligned: $(grep -A12 'Built-in cases' run_help.log)"
"$vpcontact" run -q --no-vtu > /dev/null || fail "vpcontact run without a case failed"
[ -f output/paper-2d/summary.json ] || fail "vpcontact run without a case did not run paper-2d"
echo "item 10: ok"

# --- item 9: the output directory first, with the OS's reason
expect_error "/proc output" "cannot create the output directory '/proc/vpc': .+" run block-3d --n 40 -o /proc/vpc
grep -q "assembly" out.log && fail "/proc output: set-up ran before the directory was checked: $(cat out.log)"
touch afile
expect_error "file as output" "cannot create the output directory 'afile/x': .+" run paper-1d -o afile/x
"$vpcontact" run paper-1d -q --every 1 -o rerun || fail "first run failed"
touch rerun/notes.txt rerun/my_mesh.vtu
"$vpcontact" run paper-1d --every 0 -o rerun > rerun.log || fail "second run failed"
grep -q "removed [0-9]* files of an earlier run" rerun.log || fail "no message about removed files: $(cat rerun.log)"
[ -f rerun/solution_00001.vtu ] && fail "stale solution_00001.vtu of the earlier run is left"
[ -f rerun/solution_00100.vtu ] && [ -f rerun/notes.txt ] && [ -f rerun/my_mesh.vtu ] ||
  fail "the second run's or the user's files are missing: $(ls rerun)"
[ "$(grep -c '<DataSet' rerun/solution.pvd)" -eq "$(ls rerun/solution_*.vtu | wc -l)" ] ||
  fail "solution.pvd and the VTU files disagree: $(ls rerun)"
echo "item 9: ok"

# --- item 8: header first, then each stage as it starts, with its time
for cmd in run check; do
  extra=(); [ "$cmd" = run ] && extra=(--no-vtu -o stages)
  "$vpcontact" "$cmd" paper-2d "${extra[@]}" > stages.log || fail "$cmd paper-2d failed"
  order=$(grep -noE "^vpcontact: paper-2d —|building the mesh \.\.\. [0-9.]+ s|choosing the linear solver \([a-z ]+\) \.\.\. [0-9.]+ s|^  linear solver CHOLMOD on one process[ ;(]|^  assembly \.\.\. [0-9.]+ s|factorization of K \([0-9]+ x [0-9]+, [0-9]+ nonzeros; [A-Za-z -]+\) \.\.\. [0-9.]+ s|factorization of H \([0-9]+ x [0-9]+, [0-9]+ nonzeros\) \.\.\. [0-9.]+ s|contact set-up \.\.\. [0-9.]+ s|^  mesh: " stages.log | cut -d: -f1 | tr '\n' ' ')
  [ "$order" = "1 2 3 4 5 6 7 8 9 " ] || fail "$cmd: header and stages out of order or missing ($order): $(cat stages.log)"
done
# On a terminal the progress line is redrawn; each drawing clears the rest of the line.
script -qc "'$vpcontact' run paper-1d --no-vtu -o tty" /dev/null > tty.log 2>&1 || fail "run on a terminal failed"
n_draw=$(grep -o $'\r  \[' tty.log | wc -l)
n_clear=$(grep -o $'\x1b\[K' tty.log | wc -l)
[ "$n_draw" -gt 0 ] && [ "$n_draw" -eq "$n_clear" ] || fail "progress line: $n_draw drawings, $n_clear ESC[K"
echo "item 8: ok"

# --- item 11
cat > dt.toml <<'TOML'
[mesh]
generator = "interval"
lower = [0.0]
upper = [1.0]
cells = 10
[boundary]
clamped = "left"
contact = "right"
[elasticity]
E = 1.0
nu = 0.0
[loads]
f0 = ["t"]
[time]
dt = 0.1
[output]
every = 2
TOML
"$vpcontact" check dt.toml --set time.steps=20 --set 'output.times=[0.5]' -q || fail "--set time.steps on a case with dt"
sed -e 's/^dt = 0.1/steps = 10/' -e 's/^every = 2/times = [0.5]/' dt.toml > steps.toml
"$vpcontact" check steps.toml --set time.dt=0.25 --set output.every=1 -q || fail "--set time.dt on a case with steps"
expect_error "conflicting --set" "--set time.dt=0.5: conflicts with --set time.steps=4" check dt.toml --set time.steps=4 --set time.dt=0.5
expect_error "--n on a Gmsh case" "--n 4: --n sets the cells per edge of a generated mesh only; dome-3d.toml \(built-in\) reads its mesh from" check dome-3d --n 4
echo "item 11: ok"
echo "test_cli: all passed"
