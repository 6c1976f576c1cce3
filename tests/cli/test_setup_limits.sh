#!/usr/bin/env bash
# Issue 26 items 15 and 16: set-up cannot hang or write outside output/.
#  - a .geo whose meshing does not end is stopped at [mesh] time_limit, with a message;
#  - the first Ctrl-C while Gmsh meshes stops the run at once (it waited for Gmsh);
#  - a case file that is a FIFO or a directory is refused (a FIFO blocked for ever);
#  - case.name must be one safe path component: nothing is made or cleaned outside output/.
#
# Usage: tests/cli/test_setup_limits.sh PATH/TO/vpcontact TMPDIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
fail() { echo "test_setup_limits: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp/work" && cd "$tmp/work" || exit 1

# A script that never ends (Gmsh's loop counts to 1e15), in a case.
cat > loop.geo <<'EOF'
For i In {1:1e15}
  x = i;
EndFor
Point(1) = {0, 0, 0, 0.5};
EOF
cat > loop.toml <<'EOF'
[mesh]
file = "loop.geo"
[boundary]
clamped = ["a"]
contact = ["b"]
[elasticity]
kind = "plane-strain"
E = 1.0
nu = 0.3
[time]
steps = 1
EOF

# The time limit: an error naming the limit and its key, within seconds.
start=$SECONDS
out=$(timeout 60 "$vpcontact" check loop.toml -q --set mesh.time_limit=2 2>&1)
rc=$?
[ "$rc" -eq 1 ] || fail "time limit: exit code $rc, expected 1: $out"
echo "$out" | grep -q "loop.geo: Gmsh did not finish within 2 s and was stopped (a loop that does not end, or elements far too small?); \[mesh\] time_limit sets the limit" \
  || fail "time limit: wrong message: $out"
[ $((SECONDS - start)) -le 20 ] || fail "time limit: took $((SECONDS - start)) s"
echo "time limit: $out"

# Ctrl-C while Gmsh meshes: exit 130 at once, with the set-up message, and no Gmsh left running.
"$vpcontact" check loop.toml > int.log 2>&1 &
pid=$!
for _ in $(seq 1 200); do grep -q "building the mesh" int.log && break; sleep 0.05; done
sleep 0.5
kill -INT "$pid"
start=$SECONDS
for _ in $(seq 1 100); do kill -0 "$pid" 2> /dev/null || break; sleep 0.05; done
if kill -0 "$pid" 2> /dev/null; then
  kill -KILL "$pid"
  fail "Ctrl-C during meshing: still running 5 s later: $(cat int.log)"
fi
wait "$pid"
rc=$?
[ "$rc" -eq 130 ] || fail "Ctrl-C during meshing: exit code $rc, expected 130: $(cat int.log)"
grep -q "interrupted by SIGINT during set-up; nothing was computed" int.log || fail "Ctrl-C: no message: $(cat int.log)"
sleep 0.5
! pgrep -P "$pid" > /dev/null 2>&1 || fail "Ctrl-C: Gmsh's process is left running"
echo "Ctrl-C during meshing: exit $rc"

# Case files that are not regular files are refused (a FIFO blocked for ever).
mkfifo pipe.toml
out=$(timeout 10 "$vpcontact" check pipe.toml 2>&1)
rc=$?
[ "$rc" -eq 1 ] || fail "FIFO case file: exit code $rc, expected 1: $out"
echo "$out" | grep -q "cannot read case file 'pipe.toml': it is a named pipe (FIFO); expected a regular file" \
  || fail "FIFO case file: wrong message: $out"
mkdir dir.toml
out=$("$vpcontact" check dir.toml 2>&1)
echo "$out" | grep -q "cannot read case file 'dir.toml': it is a directory; expected a regular file" \
  || fail "directory case file: wrong message: $out"
echo "FIFO: $out"

# case.name is one path component: ../../escaped was made (and cleaned) outside output/.
mkdir -p deep/er && cd deep/er || exit 1
for name in ../../escaped /tmp/abs . .. 'a b'; do
  out=$("$vpcontact" run paper-1d -q --no-vtu --set "case.name=$name" 2>&1)
  rc=$?
  [ "$rc" -eq 1 ] || fail "case.name=$name: exit code $rc, expected 1: $out"
  echo "$out" | grep -q "\-\-set case.name=.*: expected a name of at most 100 letters, digits, '-', '_' and '.'" \
    || fail "case.name=$name: wrong message: $out"
done
[ ! -e ../../escaped ] && [ ! -e ../escaped ] || fail "case.name: a directory was made outside output/"
[ ! -e output ] || fail "case.name: output/ was made for a refused name: $(find output)"
"$vpcontact" cases --show paper-1d > p1.toml
"$vpcontact" run p1.toml -q --no-vtu --steps 2 --set case.name=my-case_1.0 || fail "a safe case.name failed"
[ -f output/my-case_1.0/history.csv ] || fail "case.name=my-case_1.0: no output/my-case_1.0/history.csv"
echo "case.name: $out"
echo "test_setup_limits: all passed"
