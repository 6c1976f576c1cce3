#!/usr/bin/env bash
# Checkpoints of the PETSc engine resume on another number of ranks and in the
# serial engine (and a serial checkpoint on the PETSc engine):
#   A: mpirun -np 2, uninterrupted (the reference)
#   B: mpirun -np 3 with --checkpoint-every 10; the last checkpoints removed (as
#      if killed after step 10); resumed with mpirun -np 2
#   C: the same interrupted files resumed by the serial engine
#   D: a serial run's checkpoint of step 10 resumed by mpirun -np 3
# Each must end with the reference's history (to 1e-10 relative) and final state.
#   resume_across_ranks.sh VPCONTACT MPIEXEC WORKDIR
set -euo pipefail
VPC=$1 MPIEXEC=$2 WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK"
CASE=(paper-2d --n 20 --steps 20 --every 5 -q)
run() { "$MPIEXEC" -n "$1" --oversubscribe "$VPC" "${@:2}"; }
interrupt() {  # keep the checkpoints up to step 10 and the rows of the run beyond them
  rm -f "$1"/checkpoint_00020.bin
  ls "$1"/checkpoint_*.bin > /dev/null
}
compare() {
  /usr/bin/python3 - "$WORK/A/history.csv" "$1/history.csv" "$2" <<'PY'
import csv, sys
a = list(csv.reader(open(sys.argv[1]))); b = list(csv.reader(open(sys.argv[2])))
assert a[0] == b[0] and len(a) == len(b) == 21, f"{sys.argv[3]}: {len(b) - 1} rows, expected 20"
worst = 0.0
for ra, rb in zip(a[1:], b[1:]):
    for x, y in zip(ra, rb):
        x, y = float(x), float(y)
        worst = max(worst, abs(x - y) / max(abs(x), 1e-3))
assert worst < 1e-10, f"{sys.argv[3]}: history differs from the uninterrupted run by {worst:.2e}"
print(f"{sys.argv[3]}: history equal to the uninterrupted run (largest relative difference {worst:.1e})")
PY
}
run 2 run "${CASE[@]}" -o "$WORK/A"
run 3 run "${CASE[@]}" --checkpoint-every 10 -o "$WORK/B"
cp -r "$WORK/B" "$WORK/C"
interrupt "$WORK/B"
run 2 run "${CASE[@]}" --resume "$WORK/B"
compare "$WORK/B" "3 ranks -> 2 ranks"
test -s "$WORK/B/solution_00020.pvtu" && test -s "$WORK/B/solution_00020_p0001.vtu"
interrupt "$WORK/C"
"$VPC" run "${CASE[@]}" --engine serial --resume "$WORK/C"
compare "$WORK/C" "3 ranks -> serial engine"
"$VPC" run "${CASE[@]}" --engine serial --checkpoint-every 10 -o "$WORK/D"
interrupt "$WORK/D"
run 3 run "${CASE[@]}" --resume "$WORK/D"
compare "$WORK/D" "serial engine -> 3 ranks"
echo "resume across rank counts: ok"
