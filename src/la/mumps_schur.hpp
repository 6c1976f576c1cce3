#pragma once
// S = B A⁻¹ Bᵀ for a symmetric positive definite A (a distributed PETSc matrix) and a few rows B,
// as the Schur complement of the augmented matrix [A Bᵀ; B 0] (which is −S) by one MUMPS
// factorization (LDLᵀ, the m Schur unknowns eliminated last; ICNTL(19)). The sparse elimination
// reaches only what couples to B, as CHOLMOD's halves do on one process (S = YᵀY, Y = L⁻¹PBᵀ);
// block solves K⁻¹Bᵀ cost m full solves instead (dome-3d refine = 1 on 2 ranks: 19.7 s of
// contact set-up). PETSc's interface to MUMPS forms Schur complements on one process only, so
// MUMPS is called directly here (Debian: libmumps-dev, which PETSc is built on).
#include "la/petsc_util.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

namespace vpc::la {

/// `A`: assembled, symmetric (its lower triangle is read). `B_local`: this rank's rows of B, its
/// columns A's owned rows (owned numbering); `rows`: their places among B's `m` rows (each row on
/// one rank). Returns S (m × m), the same on every rank. Throws vpc::Error naming `what` where
/// MUMPS fails. Collective.
Eigen::MatrixXd mumps_schur_complement(MPI_Comm comm, Mat A, const Eigen::SparseMatrix<double>& B_local,
                                       const std::vector<int>& rows, int m, const char* what);

/// MUMPS's size of the factor of A a PETSc MUMPS factor holds (`F`): its entries (INFOG(29)) and
/// the flops of its elimination (RINFOG(3)), to weigh m solves against one more factorization.
struct MumpsFactorSize {
  double entries = 0;
  double flops = 0;
};
MumpsFactorSize mumps_factor_size(Mat F);

}  // namespace vpc::la
