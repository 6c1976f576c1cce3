#!/usr/bin/env bash
# The quick tier (`make test`, CTest label quick; issue 48 item 19) touches every module of
# src/, the command line, the paper's 1D and 2D examples and, where built, the Python module
# and one MPI run: each needs at least one test of the tier.
#   quick_tier.sh CTEST BUILD_DIR PYTHON(ON/OFF) PETSC(ON/OFF)
set -euo pipefail
ctest=$1 build=$2 python=$3 petsc=$4

names=$(cd "$build" && "$ctest" -N -L quick | sed -n 's/^ *Test *#[0-9]*: //p')
[ -n "$names" ] || { echo "quick_tier: no test labelled quick in $build"; exit 1; }

# what: a regular expression on the test names (suites as in tests/unit/<module>/).
declare -A need=(
  [core]='^Expression\.'
  [mesh]='^Mesh\.'
  [fem]='^(Assembly|Quadrature)\.'
  [material]='^(Laws|Elasticity|Sources)\.'
  [contact]='^FrictionLaw\.'
  [mortar]='^Mortar'
  [la]='^La'
  [solvers]='^DamageSolver\.'
  [scheme]='^StepStability\.'
  [io]='^CaseFile\.'
  [cli]='^cli\.'
  ["paper's 1D example"]='^Paper1D\.'
  ["paper's 2D example"]='^Paper2D\.'
)
[ "$python" = ON ] && need[python]='^python\.'
[ "$petsc" = ON ] && need[mpi]='^mpi\.'

missing=0
for what in "${!need[@]}"; do
  if ! grep -Eq "${need[$what]}" <<< "$names"; then
    echo "quick_tier: no quick test for $what (a name matching ${need[$what]})"
    missing=1
  fi
done
[ $missing = 0 ] && echo "quick_tier: $(wc -l <<< "$names") tests, every module touched"
exit $missing
