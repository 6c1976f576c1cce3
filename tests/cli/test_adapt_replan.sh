#!/usr/bin/env bash
# Issue 51: under --engine auto an adaptive run plans the engine and linear solver of each adapted mesh
# (run/solver_plan.hpp), as its first mesh's. hertz-2d-adapt under a memory limit between CHOLMOD's estimate
# and CG + GAMG's on its finer meshes (14,858 cells: CHOLMOD about 43 MiB; 19,864: CHOLMOD 60 MiB, CG + GAMG
# 33 MiB; 26,652: CG + GAMG 34 MiB, its refusal's figure under --memory-limit 30M) starts on CHOLMOD, goes on with CG + GAMG on the PETSc engine at
# one rank, says so, and ends where the serial run without a limit ends (the same meshes, the same force).
#
# Usage: tests/cli/test_adapt_replan.sh PATH/TO/vpcontact TMPDIR
set -uo pipefail
vpcontact=$1
tmp=$2
fail() { echo "test_adapt_replan: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" || exit 1
run() { "$vpcontact" run hertz-2d-adapt --set adapt.resolve=15 --no-vtu "$@" 2>&1; }

out=$(run --memory-limit 52M -o "$tmp/auto") || fail "the run with --memory-limit 52M failed: $out"
grep -q "each adapted mesh's engine and linear solver planned for it" <<<"$out" || fail "no re-planning in the [adapt] line: $out"
grep -Eq "^  \[adapt\] the adapted mesh \([0-9]+ cells, [0-9]+ nodes\): CG \+ GAMG on one process \(the PETSc engine\): CHOLMOD's factors would need about .* more than the limit of 52 MiB" <<<"$out" \
  || fail "the change to CG + GAMG is not said: $out"
grep -Eq "undone|could not be set up" <<<"$out" && fail "an adaptation was undone or refused: $out"

out_free=$(run --engine serial -o "$tmp/unlimited") || fail "the run without a limit failed: $out_free"
grep -q "each adapted mesh on CHOLMOD, as the first (the serial engine)" <<<"$out_free" || fail "the serial [adapt] line: $out_free"

python3 - "$tmp" <<'PY' || exit 1
import csv, json, sys
tmp = sys.argv[1]
def load(d):
    s = json.load(open(f"{tmp}/{d}/summary.json"))
    rows = list(csv.DictReader(open(f"{tmp}/{d}/history.csv")))
    return s, rows
auto, auto_rows = load("auto")
free, free_rows = load("unlimited")
solvers = [a["linear_solver"] for a in auto["adaptations"]]
assert solvers[0] == "cholmod" and solvers[-1] == "cg-gamg", f"the adaptations' linear solvers: {solvers}"
assert "cg-gamg" not in solvers[:solvers.index("cg-gamg")], solvers
assert all(s == "cholmod" for s in (a["linear_solver"] for a in free["adaptations"])), "the unlimited run left CHOLMOD"
assert all(r["ok"] == "1" for r in auto_rows + free_rows), "a step not ok"
cells = [a["cells_after"] for a in auto["adaptations"]]
assert cells == [a["cells_after"] for a in free["adaptations"]], f"other meshes: {cells}"
fa, ff = float(auto_rows[-1]["total_contact_force"]), float(free_rows[-1]["total_contact_force"])
assert abs(fa - ff) <= 1e-7 * abs(ff), f"the force {fa} against {ff} without the limit"
print(f"test_adapt_replan: all passed ({len(solvers)} adaptations, {solvers.count('cg-gamg')} on CG + GAMG, "
      f"{cells[-1]} cells; force {fa:.9g} against {ff:.9g})")
PY
