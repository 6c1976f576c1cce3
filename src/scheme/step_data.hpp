#pragma once
// The data of the step ending at t_n (SPEC §2, §6): the load F_n of (3.3) without the Bᵀz
// term, the prescribed displacement u_D(t_n) and the gap g(t_n) of (3.9), evaluated together
// and then checked once: every formula that reached them gave a finite value (issue 26).
#include "la/vector.hpp"
#include "scheme/discrete_system.hpp"

#include <string>

namespace vpc {

struct StepData {
  double t = 0;
  Vector F;    // the loads f0, f2 and the pressures at t (the part's full dofs)
  Vector u_D;  // the prescribed values at t, zero elsewhere; empty when every prescribed value is zero
  Vector gap;  // g(t) at the owned contact rows, in row order (with gap_shift)
  /// What the contact laws' per-node state adds to g (surface_gap_shift; empty: nothing).
  Vector gap_shift;
  /// Adhesion's bonds of the step per owned row (surface_bond; empty: no law bonds).
  StepBonds bond;
};

/// F_n, u_D and g at t, then check_step_data. Collective.
StepData step_data(const DiscreteSystem& sys, double t);

/// F_n of (3.3) without the Bᵀz term: the loads f0, f2 and the pressures at time t (the part's full dofs).
Vector load(const DiscreteSystem& sys, double t);
/// u_D(t) of SPEC §6 on the part's full dofs: the prescribed values, zero elsewhere;
/// empty when no displacement is prescribed other than zero.
Vector prescribed_displacement(const DiscreteSystem& sys, double t);
/// g(t) at this process's contact rows (the owned ones, in row order): the gap of the step
/// ending at t. A value that is not finite is described in `bad` (the first one; else empty).
Vector contact_gap(const DiscreteSystem& sys, double t, std::string& bad);
/// g(t) alone, checked as step_data checks (the contact rows' set-up at t = 0). Collective.
Vector checked_contact_gap(const DiscreteSystem& sys, double t);
/// Throws vpc::Error on every process when a formula of the problem gave a value that is not
/// finite (check_formulas) or `bad` (a gap's description) is not empty on some process. Collective.
void check_step_data(const DiscreteSystem& sys, const std::string& bad);

}  // namespace vpc
