#pragma once
// The contact inequality (3.9) by a primal–dual active-set (semismooth Newton)
// method on u itself, which never forms S = N K⁻¹Nᵀ (issue 14; Hintermüller, Ito &
// Kunisch 2002; deal.II step-42). Each iteration solves K with the active contact
// rows as constraints, by the backend's solver (CHOLMOD, MUMPS or CG + AMG): the
// cost of a step is one or two such solves once the active set is warm, and the
// memory is K's, whatever the number m of contact nodes.
//
// Every row of N is one node's direction ν (‖ν‖ = ρ): a node-local reflection Q
// (Householder, identity where ν is along an axis) turns it into one dof k,
// N_i Q = α_i e_kᵀ, |α_i| = ρ. In w = Qu an active Signorini row is the
// Dirichlet condition w_k = g_i/α_i, an active compliance row a spring k_i α_i² on
// w_k; the system is K_rot = Q K Q with those rows and columns replaced by the
// identity (the layout and the pattern kept: a factor reuses its analysis, AMG its
// block size), and λ_i = (QF − K_rot w)_k /(ρs) the reaction there. A contact pair's row
// (issue 29) reads its master nodes too: the basis u = P w also writes the slave node in its
// masters' dofs (contact_basis), so that the row is again one dof of w, K_rot = Pᵀ K P, b = PᵀF:
// dual mortar's condensation of the active slave side, as a fixed change of variables. With friction
// (primal_friction.hpp) Coulomb's coupling makes the system K_rot + C, C nonsymmetric: GMRES
// with K_rot's own factor or multigrid hierarchy as preconditioner.
#include "solvers/contact_frame.hpp"
#include "solvers/contact_solver.hpp"

namespace vpc {

/// Solves before the primal solver gives up: without friction, and with it (Coulomb's bound in
/// Newton's step: frictional foundation-3d 3–5 solves a step, docs/performance.md; more where the
/// sets cycle and the bound is lagged).
constexpr int kPrimalMaxIterations = 200, kPrimalFrictionMaxIterations = 500;

/// "primal-active-set" (make_contact_solver): K and, where some row is not along an axis or has
/// masters, K_rot = Pᵀ K P (contact_basis of the constraints' N and node_dofs; Q K Q without
/// masters) assembled over the same layout (nullptr: K_rot = K); `factor` is
/// unfactorized (its coordinates set for AMG) and refactorized whenever the active set changes.
/// `max_iterations`: solves before it gives up (converged = false; 0: kPrimalMaxIterations, or
/// kPrimalFrictionMaxIterations with friction); tests lower it. `friction_tolerance`:
/// ContactSolverOptions::friction_tolerance.
std::unique_ptr<ContactSolver> make_primal_active_set_solver(std::shared_ptr<const la::SpdOperator> K,
                                                             std::shared_ptr<const la::SpdOperator> K_rot,
                                                             std::shared_ptr<la::LinearSolver> factor,
                                                             ContactConstraints constraints,
                                                             int max_iterations = 0,
                                                             double friction_tolerance = 1e-12);

}  // namespace vpc
