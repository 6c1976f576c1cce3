#pragma once
// The dual active-set contact solver ("active-set" of make_contact_solver): the box QP on the
// contact unknowns with the dense S = N K⁻¹Nᵀ (with friction S = B K⁻¹Bᵀ, B = [N; T]),
// formed once from K's factor (K and N never change); a step is then one or two solves with K.
#include "solvers/contact_solver.hpp"

namespace vpc {

/// K, its factor (factorized) and the constraints. Y = L⁻¹PNᵀ (or W = K⁻¹Nᵀ) is kept while it
/// takes at most `max_cached_share` of the factor's memory (ContactSolverOptions::max_cached_share).
std::unique_ptr<ContactSolver> make_dual_active_set_solver(std::shared_ptr<const la::SpdOperator> K,
                                                           std::shared_ptr<const la::LinearSolver> factor,
                                                           ContactConstraints constraints, double max_cached_share);

}  // namespace vpc
