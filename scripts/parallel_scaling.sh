#!/usr/bin/env bash
# Strong scaling of the PETSc engine (docs/parallel.md): each case at 1 and 2
# MPI ranks (one thread each), and the serial engine for reference, REPEAT
# times; prints one CSV row per run with the phases from summary.json.
#   scripts/parallel_scaling.sh [BUILD_DIR] [REPEAT]
set -euo pipefail
BUILD=${1:-build-mpi}
REPEAT=${2:-3}
VPC=$(realpath "$BUILD/app/vpcontact")
OUT=$(mktemp -d)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
cases=("paper-2d --n 320" "block-3d --n 25")
echo "case,engine,ranks,repeat,wall,setup,assembly,factor_K,factor_H,contact_setup,steps_damage,steps_contact,steps_sources_stress,total_contact_force"
for r in $(seq "$REPEAT"); do
  for c in "${cases[@]}"; do
    for np in serial 1 2; do
      dir="$OUT/run"
      rm -rf "$dir"
      if [ "$np" = serial ]; then
        "$VPC" run $c --engine serial --no-vtu -q -o "$dir" --checkpoint-every 0
      else
        mpirun -np "$np" --bind-to core "$VPC" run $c --engine petsc --no-vtu -q -o "$dir"
      fi
      /usr/bin/python3 - "$dir/summary.json" "$c" "$np" "$r" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); t = d["timing_seconds"]; s = d["setup_seconds"]
eng = "serial" if sys.argv[3] == "serial" else "petsc"
ranks = 1 if eng == "serial" else int(sys.argv[3])
print(f'{sys.argv[2].replace(" ", "")},{eng},{ranks},{sys.argv[4]},{t["wall"]:.3f},{t["setup"]:.3f},{s["assembly"]:.3f},'
      f'{s["factor_K"]:.3f},{s["factor_H"]:.3f},{s["contact"]:.3f},{t["damage"]:.3f},{t["contact"]:.3f},'
      f'{t["sources"] + t["stress"]:.3f},{d["final"]["total_contact_force"]:.15g}')
PY
    done
  done
done
rm -rf "$OUT"
