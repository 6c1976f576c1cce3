#pragma once
// Contact (3.9) by the paper's penalty–duality iteration (solvers/penalty_duality.hpp) on u,
// with H = K and E = N: "penalty-duality" of make_contact_solver, the cross-check of the
// active-set solvers (frictionless, Signorini only: make_contact_solver checks).
#include "solvers/contact_solver.hpp"

namespace vpc {

/// K and its factor (for the default ω, ContactSolverOptions::omega = 0); `make_factor` makes the
/// factor of K + ωNᵀN.
std::unique_ptr<ContactSolver> make_penalty_duality_contact_solver(std::shared_ptr<const la::SpdOperator> K,
                                                                   const la::LinearSolver& K_factor,
                                                                   ContactConstraints constraints,
                                                                   const la::LinearSolverFactory& make_factor,
                                                                   const ContactSolverOptions& opt);

}  // namespace vpc
