#!/usr/bin/env bash
# SIGTERM (timeout -s TERM, a cluster's wall-time limit) and SIGINT (Ctrl-C)
# during a run: exit 143 / 130, a checkpoint written at the signal, the exact
# --resume command printed (run here as printed, through the shell, from an
# output directory whose name needs quoting), and the resumed run's results
# identical to an uninterrupted run's. A signal during set-up exits cleanly too.
# No *.tmp.* file is left behind.
#
# Usage: tests/cli/test_interrupt.sh PATH/TO/vpcontact TMPDIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
fail() { echo "test_interrupt: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1
args=(run paper-2d --n 40 --steps 3000 --every 1000)

"$vpcontact" "${args[@]}" -q -o reference || fail "the uninterrupted run failed"

check_interrupted() {  # NAME EXPECTED_RC RC LOG
  local dir=$1 want=$2 rc=$3 log=$4
  [ "$rc" -eq "$want" ] || fail "$dir: exit code $rc, expected $want: $(cat "$log")"
  grep -q "interrupted by SIG" "$log" || fail "$dir: no 'interrupted' message: $(cat "$log")"
  ls "$dir"/checkpoint_*.bin > /dev/null 2>&1 || fail "$dir: no checkpoint written"
  ! ls "$dir"/*.tmp.* > /dev/null 2>&1 || fail "$dir: temporary files left: $(ls "$dir")"
  resume=$(grep -A1 "To continue:" "$log" | tail -n 1)
  case "$resume" in *"--resume "*) ;; *) fail "$dir: no --resume command printed: $(cat "$log")" ;; esac
  # The command as printed, through a shell, as a user would paste it.
  bash -c "$resume -q" || fail "$dir: the printed command failed: $resume"
  for f in history.csv probes.csv solution.pvd solution_03000.vtu solution_01000.vtu; do
    cmp -s "reference/$f" "$dir/$f" || fail "$dir: $f differs from the uninterrupted run"
  done
  echo "$dir: exit $rc, resumed with: $resume"
}

# A signal once a few steps are written (never during set-up, however loaded the
# machine): SIGTERM as timeout(1) or a batch system sends it, SIGINT as Ctrl-C.
interrupt_after_steps() {  # SIGNAL DIR LOG
  local sig=$1 dir=$2 log=$3
  "$vpcontact" "${args[@]}" -o "$dir" > "$log" 2>&1 &
  local pid=$!
  for _ in $(seq 1 1200); do
    [ -f "$dir/history.csv" ] && [ "$(wc -l < "$dir/history.csv")" -gt 5 ] && break
    sleep 0.05
  done
  kill -"$sig" "$pid"
  wait "$pid"
}
dir="term run's \$dir"
interrupt_after_steps TERM "$dir" term.log
check_interrupted "$dir" 143 $? term.log
dir="int run"
interrupt_after_steps INT "$dir" int.log
check_interrupted "$dir" 130 $? int.log

# SIGINT during set-up (the factorization of K): a clean exit with 130.
"$vpcontact" run block-3d --n 30 -o setup > setup.log 2>&1 &
pid=$!
for _ in $(seq 1 600); do grep -q "factorization of K" setup.log && break; sleep 0.05; done
kill -INT "$pid"
wait "$pid"
rc=$?
[ "$rc" -eq 130 ] || fail "signal during set-up: exit code $rc, expected 130: $(cat setup.log)"
grep -q "interrupted by SIGINT during set-up" setup.log || fail "signal during set-up: no message: $(cat setup.log)"
echo "set-up: exit $rc"
echo "test_interrupt: all passed"
