#pragma once
// Which contact rows stick and which slip after a frictional solve: the solver's report counts
// them (ContactReport::n_stick, n_slip) and the state keeps them per node (State::contact_status,
// scheme/friction_data), from this one classification.
#include "solvers/contact_solver.hpp"

#include <vector>

namespace vpc {

/// contact_status of this rank's rows at λ (m × c.block numbers, replicated), with c's bounds and
/// `slack` (kSlipForceShare of the step's force scale): where λ_ν ≤ active_threshold (as
/// ContactReport::n_active counts a row) Open if |λ_τ| > slack (Tresca's bound acts there), else Free.
std::vector<ContactStatus> stick_slip(const ContactConstraints& c, const Vector& lambda, double slack,
                                      double active_threshold = 0);

}  // namespace vpc
