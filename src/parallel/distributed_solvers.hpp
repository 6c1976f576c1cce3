#pragma once
// The contact inequality of a step on distributed vectors, with the algorithm,
// tolerances and checks of the serial solver (src/solvers/); the damage inequality
// is solved by the serial engine's solver over la/'s PETSc backend.
//
// DistributedContactSolver: (3.9) in dual form. S = N K⁻¹ Nᵀ (m × m, m the contact
//   nodes) is formed once with the factor of K and kept on every rank; a step is
//   one distributed solve u_free = K⁻¹F, the m numbers b = N u_free − g summed over
//   the ranks, the serial dense active-set box QP (solvers/box_qp.hpp) on every
//   rank (the same data, so the same λ), and u = u_free − Wλ with W = K⁻¹Nᵀ kept
//   distributed (or a second solve when W would be too large).

#include "parallel/distributed_mesh.hpp"
#include "la/petsc_linear_solver.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/contact_solver.hpp"

#include <memory>
#include <vector>

namespace vpc {

class DistributedContactSolver {
 public:
  /// K: the assembled stiffness; K_solver: its factor. Collective.
  DistributedContactSolver(const DistributedMesh& part, Mat K, const PetscLinearSolver& K_solver);
  /// u: warm start on entry (ignored by the direct solver), solution on exit;
  /// lambda: m contact forces, the same on every rank. Collective.
  ContactReport solve(Vec F, Vec u, Vector& lambda);
  /// m and the gaps g (every rank holds all of them).
  const Vector& gap() const { return g_; }
  /// KKT residuals of (3.9) for (u, λ), as contact_residuals, computed globally.
  ContactResiduals residuals(Vec F, Vec u, const Vector& lambda);
  bool keeps_w() const { return W_.size() > 0; }

 private:
  /// N u over all ranks (m numbers, every rank gets them).
  Vector apply_N(Vec u) const;
  /// out += Nᵀλ on the owned dofs.
  void add_Nt(const Vector& lambda, double scale, Vec out) const;

  struct OwnedRow {
    int row;
    int dof[3];  // owned local dof of each component (all free: clamped nodes have no row)
    double nu[3];
  };
  MPI_Comm comm_;
  int d_, m_;
  Mat K_;
  const PetscLinearSolver& K_solver_;
  std::vector<OwnedRow> rows_;
  Vector g_;
  Eigen::MatrixXd W_;  // owned dofs × m, or empty
  std::unique_ptr<DenseBoxQpOperator> S_;
  PVec u_free_, work_, rhs_;
  static constexpr double kMaxWBytesPerRank = 256.0 * 1024 * 1024;
  static constexpr int kBlock = 64;  // right-hand sides per block when forming S
};

}  // namespace vpc
