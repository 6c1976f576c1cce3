#!/usr/bin/env bash
# Issue 48 item 11: the set-up header names each contact pair's normal law, friction law and
# sliding mode (it said "(Signorini)" for punch-3d's Coulomb, large-sliding pair), and Γ3's laws
# after Γ3's parts as before.
#
# Usage: tests/cli/test_setup_header.sh PATH/TO/vpcontact SOURCE_DIR
set -uo pipefail
vpcontact=$1 src=$2
fail() { echo "test_setup_header: FAIL: $*" >&2; exit 1; }
# has CASE TEXT [OPTION...]: `vpcontact check CASE OPTION...` prints a header line containing TEXT
# (a fixed string).
has() {
  local out case=$1 text=$2
  shift 2
  out=$("$vpcontact" check "$src/cases/$case.toml" "$@" 2>&1) || fail "check $case $*: $out"
  grep -qF -- "$text" <<< "$out" || fail "check $case $*: no '$text' in its header:
$out"
  echo "$out"
}
out=$(has punch-3d "pair: slave punch.bottom, master top (Signorini, Coulomb friction mu = 0.3, large sliding)") || exit 1
grep -qF "(Signorini)" <<< "$out" && fail "punch-3d: a frictionless Signorini law is still printed for its pair"
has contact-patch-2d "pair: slave upper.bottom, master top (Signorini, frictionless, small sliding)" > /dev/null || exit 1
has contact-patch-2d "pair: slave upper.bottom, master top (Signorini, Tresca friction bound = 0.1, small sliding)" \
  --set 'contact.pair[0].friction="tresca"' --set 'contact.pair[0].friction_bound=0.1' > /dev/null || exit 1
has shear-2d "Γ3 (contact): bottom (Signorini, Coulomb friction mu = 0.3)" > /dev/null || exit 1
echo "test_setup_header: all passed"
