#!/usr/bin/env bash
# `run --plot` and `vpcontact plot` with output directories whose names a shell
# would interpret (' " ; $(…) backticks spaces non-ASCII), given with -o and as
# [output] directory in a case file: the figures are drawn and nothing is
# executed (no INJECTED file appears). Then: without matplotlib a run with
# --plot warns and succeeds, while `vpcontact plot` fails with one line.
#
# Usage: tests/cli/test_plot_paths.sh PATH/TO/vpcontact TMPDIR
set -uo pipefail
vpcontact=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$2
fail() { echo "test_plot_paths: FAIL: $*" >&2; exit 1; }
rm -rf "$tmp" && mkdir -p "$tmp" && cd "$tmp" || exit 1

names=("bob's run" 'say "hi"' 'a; touch INJECTED; b' '$(touch INJECTED)' '`touch INJECTED`'
       "x'; touch INJECTED; echo '" 'dé jà vu ∂Ω')
# Half the names with -o, the others as [output] directory (drawing is slow).
i=0
for name in "${names[@]}"; do
  i=$((i + 1))
  if [ $((i % 2)) -eq 1 ]; then
    dir="out$i/$name"
    "$vpcontact" run paper-1d -q --no-vtu --plot -o "$dir" > "log$i" 2>&1 || fail "-o '$dir': $(cat "log$i")"
    [ -f "$dir/figures/fig_4_3_time_histories.png" ] || fail "-o '$dir': no figure: $(cat "log$i")"
    continue
  fi
  # A case file's [output] directory (a TOML literal string).
  toml_dir="case$i/$name"
  sed -e "s|^\[output\]|[output]\ndirectory = '''$toml_dir'''|" > "case$i.toml" <<'TOML'
[mesh]
generator = "interval"
lower = [0.0]
upper = [1.0]
cells = 20
[boundary]
clamped = "left"
contact = "right"
[elasticity]
E = 1.0
nu = 0.0
[damage]
kappa = 1.0
[loads]
f0 = ["t"]
[contact]
gap = 0.25
[time]
steps = 10
[output]
TOML
  "$vpcontact" run "case$i.toml" -q --plot > "clog$i" 2>&1 || fail "case file directory '$toml_dir': $(cat "clog$i")"
  [ -f "$toml_dir/figures/history.png" ] || fail "case file directory '$toml_dir': no figure: $(ls -R "case$i")"
done
"$vpcontact" plot "$toml_dir" --format svg --dpi 50 > plog 2>&1 || fail "plot '$toml_dir': $(cat plog)"
[ -f "$toml_dir/figures/history.svg" ] || fail "plot --format svg '$toml_dir': no SVG"
found=$(find "$tmp" "$(dirname "$vpcontact")" -name INJECTED 2>/dev/null | head -n 3)
[ -z "$found" ] || fail "a shell ran a command in a directory name: $found"
echo "no command executed; figures drawn for ${#names[@]} directory names, with -o and [output] directory"

# No matplotlib: a python3 without its site packages.
printf '#!/bin/sh\nexec /usr/bin/python3 -S "$@"\n' > nompl && chmod +x nompl
VPCONTACT_PYTHON=$PWD/nompl "$vpcontact" run paper-1d -q --no-vtu --plot -o nompl_run > nompl.log 2>&1 ||
  fail "a run with --plot without matplotlib failed: $(cat nompl.log)"
grep -q "warning: figures not drawn: .* has no numpy or matplotlib" nompl.log || fail "no warning: $(cat nompl.log)"
VPCONTACT_PYTHON=$PWD/nompl "$vpcontact" plot nompl_run > nompl_plot.log 2>&1 && fail "vpcontact plot without matplotlib succeeded"
[ "$(wc -l < nompl_plot.log)" -eq 1 ] && grep -q "^vpcontact: error: plot: .* has no numpy or matplotlib" nompl_plot.log ||
  fail "vpcontact plot without matplotlib: $(cat nompl_plot.log)"
VPCONTACT_PYTHON=/no/python3 "$vpcontact" run paper-1d -q --no-vtu --plot -o nompl_run > nopy.log 2>&1 ||
  fail "a run with --plot without python3 failed: $(cat nopy.log)"
grep -q "warning: figures not drawn: python3 ('/no/python3') cannot be started: No such file" nopy.log ||
  fail "no warning without python3: $(cat nopy.log)"
echo "without matplotlib or python3: run --plot warns (exit 0), plot fails with one line"
echo "test_plot_paths: all passed"
