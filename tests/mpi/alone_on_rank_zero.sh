#!/usr/bin/env bash
# --engine auto under mpirun (run/solver_plan.hpp SolverRequest::auto_route): a small case is run by rank 0
# alone on CHOLMOD, which says so; its files are one process's (history.csv byte for byte, one
# checkpoint file a step, no pieces); with --engine petsc the same case is distributed.
#   alone_on_rank_zero.sh VPCONTACT MPIEXEC WORKDIR
set -euo pipefail
VPC=$1 MPIEXEC=$2 WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK"
CASE=(paper-2d --n 10 --steps 6 --every 3)
fail() { echo "alone on rank 0: FAILED: $*"; exit 1; }
"$VPC" run "${CASE[@]}" -q -o "$WORK/one"
"$MPIEXEC" -n 2 --oversubscribe "$VPC" run "${CASE[@]}" -o "$WORK/alone" > "$WORK/alone.log" 2>&1 ||
  fail "mpirun -n 2: exit $? ($(tail -1 "$WORK/alone.log"))"
grep -q "auto under mpirun: rank 0 runs the case alone on CHOLMOD, the other 1 rank waiting" "$WORK/alone.log" ||
  fail "the run does not say that rank 0 ran it alone"
grep -q "linear solver CHOLMOD on one process" "$WORK/alone.log" || fail "not CHOLMOD"
cmp -s "$WORK/one/history.csv" "$WORK/alone/history.csv" || fail "history.csv differs from one process's"
[ -z "$(ls "$WORK/alone" | grep -- '-of-')" ] || fail "checkpoint pieces written: $(ls "$WORK/alone")"
"$MPIEXEC" -n 2 --oversubscribe "$VPC" run "${CASE[@]}" --engine petsc -o "$WORK/petsc" > "$WORK/petsc.log" 2>&1 ||
  fail "--engine petsc: exit $?"
grep -q "PETSc engine on 2 MPI ranks" "$WORK/petsc.log" || fail "--engine petsc did not distribute the case"
echo "alone on rank 0: PASSED"
