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

/// The primal solver's basis on contact pairs (SPEC §8): u = P w with N_i P = α_i e_{k_i}ᵀ for every
/// row, a pair's too, whose entries off its own node's dofs (`node_dofs[i]`) are its masters'
/// (−w_m ν, problem/contact_pairs.hpp). P = H + E: H the reflections of the rows' own parts
/// (contact_reflections), E the slave node's shift along H e_k by its row's master part over α, so
/// that w_k is the row's weighted gap variable itself: N_i P w = α_i w_k, and an active row is one
/// fixed dof as on a rigid obstacle (the "relative displacement" basis in which dual mortar's
/// condensation of the slave side is a change of variables: Wohlmuth 2000; Hüeber & Wohlmuth 2005).
/// P is fixed for the run, so K_rot = Pᵀ K P keeps one pattern: a factor keeps its analysis.
struct ContactBasis {
  SparseMatrix P, P_inverse;      // empty: the identity; without master entries P = P⁻¹ = Pᵀ = H
  std::vector<RotatedRow> rows;   // each row's dof k and α in w
  bool pairs() const { return P_inverse.size() > 0; }
};

/// `node_dofs` empty: every entry of a row is its node's (P = contact_reflections(N)). A master
/// dof that is also some row's own dof (a node both slave and master) cannot be written so: an
/// error (masters_apart_from_slaves tells beforehand). `master_mean` (ContactConstraints::
/// master_mean; friction on pairs) moves the slave node's every dof by its masters' mean, not only
/// along ν, so that its tangential dofs in w are the slip relative to the master too (set_tangents).
ContactBasis contact_basis(const SparseMatrix& N, const std::vector<std::vector<int>>& node_dofs,
                           const SparseMatrix& master_mean = {});

/// Whether no master entry of a row (nor of `master_mean`) is on any row's own dofs (contact_basis can be built).
bool masters_apart_from_slaves(const SparseMatrix& N, const std::vector<std::vector<int>>& node_dofs,
                               const SparseMatrix& master_mean = {});

}  // namespace vpc
