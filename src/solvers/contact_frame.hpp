#pragma once
// The node-local frame of the primal contact solver (issue 14) and of friction's tangents (issue 28):
// every row of N is one node's direction ν (‖ν‖ = ρ); a node-local reflection Q (Householder,
// identity where ν is along an axis) turns it into one dof k, N_i Q = α_i e_kᵀ, |α_i| = ρ, and
// the node's other dofs into unit tangents (set_tangents, declared in contact_solver.hpp).
#include "solvers/contact_solver.hpp"

#include <vector>

namespace vpc {

/// Q (n × n over the dofs N's columns number, symmetric and orthogonal): the
/// reflection of each row's dofs that maps e_k to ±ν (see above); the identity on
/// every other dof. Empty (0 × 0) when every row has one entry: no rotation.
SparseMatrix contact_reflections(const SparseMatrix& N);

/// Row i of N in the rotated dofs: α_i w_{k_i} (|α_i| = ρ; see contact_reflections for its sign).
struct RotatedRow {
  int dof = -1;
  double alpha = 0;
};

/// Each row's dof k and α (the dof of its largest entry).
std::vector<RotatedRow> rotated_rows(const SparseMatrix& N);

}  // namespace vpc
