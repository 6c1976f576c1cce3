#!/usr/bin/env bash
# Issue 48 item 11: the set-up header names each contact pair's normal law, friction law and
# sliding mode (it said "(Signorini)" for punch-3d's Coulomb, large-sliding pair), and Γ3's laws
# after Γ3's parts as before.
#
# Usage: tests/cli/test_setup_header.sh PATH/TO/vpcontact SOURCE_DIR
set -uo pipefail
vpcontact=$1 src=$2
fail() { echo "test_setup_header: FAIL: $*" >&2; exit 1; }
# has CASE TEXT: `vpcontact check CASE` prints a header line containing TEXT (a fixed string).
has() {
  local out
  out=$("$vpcontact" check "$src/cases/$1.toml" 2>&1) || fail "check $1: $out"
  grep -qF -- "$2" <<< "$out" || fail "check $1: no '$2' in its header:
$out"
  echo "$out"
}
out=$(has punch-3d "pair: slave punch.bottom, master top (Signorini, Coulomb friction mu = 0.3, large sliding)") || exit 1
grep -qF "(Signorini)" <<< "$out" && fail "punch-3d: a frictionless Signorini law is still printed for its pair"
has contact-patch-2d "pair: slave upper.bottom, master top (Signorini, frictionless, small sliding)" > /dev/null || exit 1
has cattaneo-mindlin-pair-2d "pair: slave bottom, master disc.arc (Signorini, Coulomb friction mu = 0.5, small sliding)" \
  > /dev/null || exit 1
has shear-2d "Γ3 (contact): bottom (Signorini, Coulomb friction mu = 0.3)" > /dev/null || exit 1
echo "test_setup_header: all passed"
