#pragma once
// Solvers of the contact inequality (3.9) in matrix form:
//     min ½ uᵀKu − Fᵀu   subject to  N u ≤ g,
// K the constant elastic stiffness on the free dofs, one row of N per contact
// node (its contact direction). The multipliers λ ≥ 0 are the nodal contact
// forces: K u = F − Nᵀλ, λ ⟂ (g − N u) ≥ 0. Neither solver knows about meshes.
#include "la/linear_solver.hpp"

#include <memory>
#include <string>
#include <vector>

namespace vpc {

/// Residuals of the KKT conditions of (3.9), each relative (see contact_residuals).
struct ContactResiduals {
  double equilibrium = 0;           // ‖Ku − F + Nᵀλ‖∞ / max(‖F‖∞, ‖Ku‖∞)
  double penetration = 0;           // max(0, max(Nu − g)) / scale_u
  double negative_force = 0;        // max(0, −min λ) / scale_λ
  double complementarity = 0;       // max |λ_i (g − Nu)_i| / (scale_λ scale_u)
  double max() const;
};

struct ContactReport {
  bool converged = false;
  int iterations = 0;
  /// Contact nodes with λ_i > active_threshold. The active-set method's λ is exactly 0
  /// off its active set (threshold 0); penalty–duality's multiplier only tends to 0
  /// there, so a node counts as active when λ_i > tolerance · max(‖λ‖∞, ‖F‖∞), the
  /// size below which its own KKT test takes a multiplier for zero.
  int n_active = 0;
  double active_threshold = 0;
  double total_force = 0;  // Σ λ_i
  ContactResiduals residuals;
};

ContactResiduals contact_residuals(const SparseMatrix& K, const SparseMatrix& N, const Vector& F,
                                   const Vector& g, const Vector& u, const Vector& lambda);

class ContactSolver {
 public:
  virtual ~ContactSolver() = default;
  /// Solves for u (free dofs) and λ (one per row of N); both are warm starts on entry.
  virtual ContactReport solve(const Vector& F, const Vector& g, Vector& u, Vector& lambda) = 0;
  virtual std::string name() const = 0;
  /// Internal warm-start state carried from step to step (penalty–duality's
  /// multiplier; empty for the active-set method, whose warm start is the
  /// solution itself): saved in checkpoints so that a resumed run is bit-identical.
  virtual Vector warm_state() const { return {}; }
  virtual void set_warm_state(const Vector&) {}
};

struct ContactSolverOptions {
  double tolerance = 1e-12;    // penalty–duality stopping tolerance
  int max_iterations = 200000; // penalty–duality; the active-set method stops far earlier
  double omega = 0;            // penalty–duality ω; 0: 1 / (mean compliance N_i K⁻¹ N_iᵀ)
  /// Active set: Y = L⁻¹PNᵀ is kept (a step then costs one solve) while it takes at
  /// most this share of the memory of K's factor (and 256 MiB); else two solves a step.
  double max_cached_share = 0.5;

  bool operator==(const ContactSolverOptions&) const = default;
};

/// K and N are copied; K_factor must be the factor of K.
/// "active-set": primal–dual active set on the contact unknowns (the dual QP with
/// S = N K⁻¹ Nᵀ = YᵀY with Y = L⁻¹PNᵀ, formed once with the cached factor
/// K = PᵀLLᵀP); one solve with K per step, as a forward and a backward half.
/// "penalty-duality": the paper's Bermúdez–Moreno iteration on u (cross-check).
std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, const SparseMatrix& K,
                                                   std::shared_ptr<const LinearSolver> K_factor,
                                                   const SparseMatrix& N, const ContactSolverOptions& opt = {});
/// The same, sharing K instead of copying it (K must not change afterwards).
std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, std::shared_ptr<const SparseMatrix> K,
                                                   std::shared_ptr<const LinearSolver> K_factor,
                                                   const SparseMatrix& N, const ContactSolverOptions& opt = {});

}  // namespace vpc
