#!/usr/bin/env bash
# Checkpoints of the PETSc engine (one piece per rank) resume on another number of
# ranks and in the serial engine (and a serial checkpoint on the PETSc engine):
#   A: mpirun -np 2, uninterrupted (the reference)
#   B: mpirun -np 3 with --checkpoint-every 10; the last checkpoints removed (as
#      if killed after step 10); resumed with mpirun -np 2
#   C: the same interrupted files resumed by the serial engine
#   D: a serial run's checkpoint of step 10 resumed by mpirun -np 3
#   E: mpirun -np 2 with --checkpoint-every 10 (2 pieces, each about half the state),
#      interrupted, resumed with mpirun -np 3, mpirun -np 1 and the serial engine
#   F: E's files with one piece of step 20 missing: the resume passes step 20 over,
#      says why, and continues from step 10
#   H, I: contact pairs (owned together, and spread: --spread-pairs), and a Gmsh mesh refined on
#      every rank, across rank counts
#   G: mpirun -np 1 (the PETSc engine on one process) writes the one-file format,
#      byte for byte the serial engine's layout; interrupted, resumed with mpirun -np 1:
#      the history and the last fields bit-identical to an uninterrupted run
# Each must end with the reference's history (to 1e-10 relative) and final state.
#   resume_across_ranks.sh VPCONTACT MPIEXEC WORKDIR
set -euo pipefail
VPC=$1 MPIEXEC=$2 WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK"
LOUD=(paper-2d --n 20 --steps 20 --every 5)
CASE=("${LOUD[@]}" -q)
# --engine petsc: distributed even where auto would let rank 0 run these small cases alone.
run() { "$MPIEXEC" -n "$1" --oversubscribe "$VPC" "$2" --engine petsc "${@:3}"; }
interrupt() {  # keep the checkpoints up to step 10 and the rows of the run beyond them
  rm -f "$1"/checkpoint_00020*.bin
  ls "$1"/checkpoint_*.bin > /dev/null
}
compare() { compare_to "$WORK/A" "$1" "$2" 20; }
compare_to() {  # REFERENCE DIR LABEL STEPS
  /usr/bin/python3 - "$1/history.csv" "$2/history.csv" "$3" "$4" <<'PY'
import csv, sys
a = list(csv.reader(open(sys.argv[1]))); b = list(csv.reader(open(sys.argv[2])))
n = int(sys.argv[4])
assert a[0] == b[0] and len(a) == len(b) == n + 1, f"{sys.argv[3]}: {len(b) - 1} rows, expected {n}"
# As tests/mpi/equivalence.py: the solvers' residuals and the error estimate are round-off-sized
# numbers (each run checks its own against the tolerance: column ok), compared as |a - b| <= 1e-10;
# relative to the 1e-3 floor they would be held to 1e-13 (refine-2d, 2 ranks -> serial:
# contact_equilibrium 5e-14 apart, up to 1.05e-10 of the floor under load).
residual = lambda c: ("residual" in c or c == "error_estimate" or c.startswith("friction_")
                      or c.startswith("contact_") and c not in ("contact_iterations", "contact_area"))
worst = 0.0
for ra, rb in zip(a[1:], b[1:]):
    for c, x, y in zip(a[0], ra, rb):
        x, y = float(x), float(y)
        worst = max(worst, abs(x - y) / (1.0 if residual(c) else max(abs(x), 1e-3)))
assert worst < 1e-10, f"{sys.argv[3]}: history differs from the uninterrupted run by {worst:.2e}"
print(f"{sys.argv[3]}: history equal to the uninterrupted run (largest relative difference {worst:.1e})")
PY
}
# Each piece of a checkpoint written on P ranks holds about 1/P of it: none over
# 1.5 × total / P plus 4 KB (what piece 0 adds: λ, the run's data, the list of pieces).
pieces_share() {  # DIR STEP P
  local files=("$1"/checkpoint_$(printf %05d "$2")*.bin) total=0 f
  [ ${#files[@]} -eq "$3" ] || { echo "step $2 in $1: ${#files[@]} files, expected $3 pieces"; exit 1; }
  for f in "${files[@]}"; do total=$((total + $(stat -c %s "$f"))); done
  for f in "${files[@]}"; do
    [ $(( 2 * $3 * $(stat -c %s "$f") )) -le $(( 3 * total + 2 * $3 * 4096 )) ] ||
      { echo "$f: $(stat -c %s "$f") bytes of $total in $3 pieces: more than its share"; exit 1; }
  done
  echo "checkpoint of step $2 on $3 ranks: ${#files[@]} pieces, $total bytes, each about its share"
}
run 2 run "${CASE[@]}" -o "$WORK/A"
run 3 run "${CASE[@]}" --checkpoint-every 10 -o "$WORK/B"
pieces_share "$WORK/B" 10 3
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

run 2 run "${CASE[@]}" --checkpoint-every 10 -o "$WORK/E"
pieces_share "$WORK/E" 20 2
for to in 3 1 serial F; do cp -r "$WORK/E" "$WORK/E$to"; done
for to in 3 1 serial; do
  interrupt "$WORK/E$to"
  if [ $to = serial ]; then "$VPC" run "${CASE[@]}" --engine serial --resume "$WORK/E$to"
  else run $to run "${CASE[@]}" --resume "$WORK/E$to"; fi
  compare "$WORK/E$to" "2 ranks -> $to"
done
rm "$WORK/EF/checkpoint_00020.p0001-of-0002.bin"
run 3 run "${LOUD[@]}" --resume "$WORK/EF" > "$WORK/EF.log" 2>&1
grep -q "skipping checkpoint '.*checkpoint_00020.bin': piece 1 of 2 ('checkpoint_00020.p0001-of-0002.bin') is missing" "$WORK/EF.log" &&
  grep -q "resuming from the checkpoint of step 10" "$WORK/EF.log" ||
  { cat "$WORK/EF.log"; echo "a missing piece: step 20 not passed over"; exit 1; }
compare "$WORK/EF" "2 ranks, a piece missing -> 3 ranks from the step before"

# K: a changed case (issue 48): refused on every rank, naming the key and both values; a change
# that may happen on resume (T, the steps after the checkpoint) is printed and recorded.
cp -r "$WORK/E" "$WORK/EK"
if run 2 run "${LOUD[@]}" --set elasticity.E=2000 --resume "$WORK/EK" > "$WORK/EK.log" 2>&1; then
  cat "$WORK/EK.log"; echo "2 ranks: a checkpoint of E = 1000 continued with E = 2000"; exit 1
fi
grep -q "was written for another case: elasticity.E: 1000 → 2000" "$WORK/EK.log" ||
  { cat "$WORK/EK.log"; echo "2 ranks: another E not refused by its key"; exit 1; }
run 3 run paper-2d --n 20 --every 5 --set time.T=2 --steps 40 --resume "$WORK/EK" > "$WORK/EK.log" 2>&1
grep -q "changed on resume: time.T: 1 → 2" "$WORK/EK.log" && grep -q '"key": "time.T"' "$WORK/EK/summary.json" ||
  { cat "$WORK/EK.log"; echo "2 ranks -> 3 ranks: a later T not reported"; exit 1; }
echo "a changed case: refused on 2 ranks naming elasticity.E; a later T continued on 3 ranks and reported"

run 1 run "${CASE[@]}" -o "$WORK/G0"
run 1 run "${CASE[@]}" --checkpoint-every 10 -o "$WORK/G"
ls "$WORK"/G/checkpoint_*.bin | grep -q -- "-of-" && { echo "one rank wrote pieces"; exit 1; }
head -c 12 "$WORK/G/checkpoint_00020.bin" | od -An -tx1 | grep -q "56 50 43 43 4b 50 54 00 06 00 00 00" ||
  { echo "one rank: not the version-6 file"; exit 1; }
interrupt "$WORK/G"
run 1 run "${CASE[@]}" --resume "$WORK/G"
for f in history.csv probes.csv solution_00020.vtu; do
  cmp "$WORK/G0/$f" "$WORK/G/$f" || { echo "1 rank -> 1 rank: $f differs from the uninterrupted run"; exit 1; }
done
echo "1 rank -> 1 rank: history, probes and last fields bit-identical to the uninterrupted run"

# A 6-step case from the checkpoint of step 4: run on WRITER (a rank count or "serial"),
# its last checkpoint removed, resumed on READER, against the uninterrupted 2-rank run REFERENCE.
#   resumed REFERENCE DIR WRITER READER LABEL CASE...
on() { if [ "$1" = serial ]; then "$VPC" "${@:2}" --engine serial; else run "$@"; fi; }
resumed() {
  local ref=$1 dir=$2 writer=$3 reader=$4 label=$5; shift 5
  on "$writer" run "$@" --checkpoint-every 2 -o "$dir"
  rm -f "$dir"/checkpoint_00006*.bin
  on "$reader" run "$@" --resume "$dir"
  compare_to "$ref" "$dir" "$label" 6
}

# H: contact pairs between bodies (issue 29): the pair's rows are owned by one rank, which changes
# with the rank count; the checkpoint holds λ by row and the fields by node, so 3 ranks -> 2 and
# the serial engine -> 3 continue the uninterrupted run.
PAIRS=("$(dirname "$0")/cases/pairs-2d.toml" -q)
run 2 run "${PAIRS[@]}" -o "$WORK/H"
resumed "$WORK/H" "$WORK/H3" 3 2 "contact pairs: 3 ranks -> 2 ranks" "${PAIRS[@]}"
resumed "$WORK/H" "$WORK/Hs" serial 3 "contact pairs: serial engine -> 3 ranks" "${PAIRS[@]}"
# ... and spread over the ranks (--spread-pairs: a row's ghost masters' u from the checkpoint's
# values at its ghosts), 3 ranks -> 2 ranks.
resumed "$WORK/H" "$WORK/Hspread" 3 2 "spread contact pairs: 3 ranks -> 2 ranks" "${PAIRS[@]}" --spread-pairs

# I: a Gmsh mesh refined on every rank (`[mesh] refine`, issue 30): each rank's block numbered from the
# coarse mesh, so 3 ranks -> 2 ranks and 2 ranks -> the serial engine (which refines it whole) continue.
REFINED=("$(dirname "$0")/cases/refine-2d.toml" -q)
run 2 run "${REFINED[@]}" -o "$WORK/I"
resumed "$WORK/I" "$WORK/I3" 3 2 "refined Gmsh mesh: 3 ranks -> 2 ranks" "${REFINED[@]}"
resumed "$WORK/I" "$WORK/I2" 2 serial "refined Gmsh mesh: 2 ranks -> serial engine" "${REFINED[@]}"
echo "resume across rank counts: ok"
