#!/usr/bin/env bash
# Installs the Debian packages vpcontact builds and runs with. Idempotent and
# non-interactive: packages already present are left alone; apt is only called
# when something is missing. Run as root (or with sudo available).
#   scripts/install-deps.sh            everything (the default build has the PETSc engine)
#   scripts/install-deps.sh --serial   without PETSc and OpenMPI (-DVPCONTACT_ENABLE_PETSC=OFF)
# (--mpi, from before PETSc was in the default build, is the same as no option.)
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev            # Eigen: sparse/dense linear algebra
  libsuitesparse-dev       # CHOLMOD: supernodal sparse Cholesky
  libopenblas-dev          # fast BLAS for CHOLMOD (replaces the reference BLAS)
  libtomlplusplus-dev      # case files
  libcli11-dev             # command line
  libfmt-dev               # formatting
  libmuparser-dev          # expressions
  nlohmann-json3-dev       # summary.json
  zlib1g-dev               # compressed VTU files
  libgmsh-dev gmsh         # meshes
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev         # benchmarks
  python3-matplotlib python3-numpy  # figures
  python3-dev pybind11-dev python3-pybind11  # the Python module (python/, docs/python.md)
  python3-scipy python3-pytest  # its sparse matrices and its tests
)
# The PETSc engine (docs/parallel.md): CG + AMG for large runs, MPI for many processes.
if [ "${1:-}" != "--serial" ]; then
  packages+=(
    libpetsc-real-dev        # PETSc 3.18 with MUMPS, hypre, PTScotch
    libmumps-dev             # MUMPS itself (PETSc's): its Schur complements (la/mumps_schur.hpp)
    libopenmpi-dev openmpi-bin  # MPI and mpirun
  )
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
