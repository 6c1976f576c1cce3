#pragma once
// YᵀY for a sparse Y whose rows are of two kinds: the many with few entries and the few with
// entries in most columns. Y = L⁻¹PNᵀ (the forward half of K⁻¹Nᵀ, solvers/dual_active_set.cpp) is
// such a matrix: a column is nonzero on its dof's path up the elimination tree, so the rows at the
// tree's top are dense. A sparse-sparse product treats those rows entry by entry (ironing-3d
// adapted, 1,200 columns: 0.70 s); through BLAS-3 rank updates they cost 0.05 s.
#include "la/linear_solver.hpp"

namespace vpc {

/// YᵀY (dense, symmetric): rows of Y with more than cols/8 entries through dense rank updates
/// (BLAS dsyrk, in chunks of rows), the others' products added entry by entry.
Eigen::MatrixXd gram(const SparseMatrix& Y);

}  // namespace vpc
