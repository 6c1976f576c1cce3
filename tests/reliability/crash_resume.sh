#!/usr/bin/env bash
# Crash-and-resume trials: kill -9 a run at random moments (several times per
# trial), resume it each time from its last good checkpoint, and check that the
# final fields, probe histories and step histories are bit-identical to an
# uninterrupted run.
#   crash_resume.sh VPCONTACT WORKDIR [TRIALS] [CASE ARGS...]
set -euo pipefail
bin=$1; work=$2; trials=${3:-5}; shift 3 || true
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(paper-2d --n 40)
common=("${args[@]}" -q --every 10 --checkpoint-every 3)
rm -rf "$work"; mkdir -p "$work"
"$bin" run "${common[@]}" -o "$work/reference" > /dev/null
final=$(ls "$work/reference"/solution_*.vtu | sort | tail -n 1); final=$(basename "$final")
steps=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['steps'])" "$work/reference/summary.json")
kills=0
for trial in $(seq 1 "$trials"); do
  out="$work/trial$trial"
  # First attempt from scratch, then resumes, each killed at a random moment
  # within about the run's duration, until one finishes.
  mode=(-o "$out")
  for attempt in 1 2 3 4 5 6 7 8; do
    "$bin" run "${common[@]}" "${mode[@]}" > "$out.log.$attempt" 2>&1 &
    pid=$!
    # Kill when the run has written a random number of history rows (or, now
    # and then, right away: before or during setup).
    target=$(/usr/bin/python3 -c "import random; print(random.choice([0, random.randint(1, $steps)]))")
    while [ "$target" -gt 0 ] && kill -0 "$pid" 2> /dev/null; do
      rows=0
      [ -f "$out/history.csv" ] && rows=$(( $(wc -l < "$out/history.csv") - 1 ))
      [ "$rows" -ge "$target" ] && break
      sleep 0.005
    done
    [ "$target" -eq 0 ] && sleep 0.0$((RANDOM % 10))
    # kill succeeds on a run that has exited but is not yet reaped, so its
    # status tells the two apart: 137 is SIGKILL, anything else is how it ended.
    kill -9 "$pid" 2> /dev/null || true
    status=0; wait "$pid" 2> /dev/null || status=$?
    if [ "$status" -ne 137 ]; then
      [ "$status" -eq 0 ] || { echo "trial $trial: attempt $attempt failed (exit $status)"; cat "$out.log.$attempt"; exit 1; }
      break   # it had finished
    fi
    kills=$((kills + 1))
    if ls "$out"/checkpoint_*.bin > /dev/null 2>&1; then
      mode=(--resume "$out")
    else
      mode=(-o "$out")   # killed before the first checkpoint: start again
    fi
  done
  # Finish whatever is left: resume if the last attempt was killed after a
  # checkpoint, start again if every attempt was killed before the first one.
  if ! grep -q '"all_steps_ok"' "$out/summary.json" 2> /dev/null || [ ! -f "$out/$final" ]; then
    "$bin" run "${common[@]}" "${mode[@]}" > "$out.log.final" 2>&1
  fi
  for f in "$final" probes.csv history.csv solution.pvd; do
    cmp -s "$work/reference/$f" "$out/$f" || { echo "trial $trial: $f differs from the uninterrupted run"; exit 1; }
  done
  echo "trial $trial: bit-identical ($(ls "$out".log.* | wc -l) attempts)"
done
echo "$trials trials, $kills kills, all bit-identical"
