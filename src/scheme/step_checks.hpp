#pragma once
// The checks and report of a step (SPEC §2) after steps 1–5: the contact totals, the
// reactions, β's range, whether the step is accepted (solvers converged, residuals within
// tolerance, fields finite), and the backstop against an unstable explicit G.
#include "la/comm.hpp"
#include "scheme/discrete_system.hpp"
#include "scheme/state.hpp"
#include "scheme/step_report.hpp"

#include <span>
#include <string>
#include <vector>

namespace vpc {

/// The minimum of `values` by MinimumAt's rule; `index[i]` is the node number of
/// values[i] (empty: i itself). `values` empty: index −1. NaN entries are
/// passed over unless they come first.
MinimumAt minimum_at(std::span<const double> values, std::span<const int> index = {});
/// The minimum of two candidates by that rule (the reduction over ranks).
MinimumAt minimum_at(const MinimumAt& a, const MinimumAt& b);
/// The minimum of every process's `values` by that rule (`index` as for minimum_at): the
/// least value, then the least node holding it. No value anywhere: index −1. Collective.
MinimumAt global_minimum_at(const la::Comm& comm, std::span<const double> values, std::span<const int> index = {});

/// The contact area and the force on each obstacle, from λ of the step ending at rep.t. Collective.
void contact_totals(const DiscreteSystem& sys, const State& s, StepReport& rep);
/// The reactions on the Dirichlet parts from σ_n and the load F_n (the part's full dofs). Collective.
void reactions(const DiscreteSystem& sys, const State& s, const Vector& F, StepReport& rep);
/// min β over all processes by MinimumAt's rule, and max β. Collective.
void beta_range(const DiscreteSystem& sys, const State& s, StepReport& rep);
/// The warning of a step whose Tresca bound acted through nodes not in contact (rep.contact.n_open
/// > 0), located at the friction key of the law; empty where none did.
std::string open_friction_warning(const Problem& p, const StepReport& rep);
/// contact_totals, reactions and beta_range of the step that ended in s with the load F. Collective.
void report_step(const DiscreteSystem& sys, const State& s, const Vector& F, StepReport& rep);
/// Whether the step is accepted: both solvers converged, every residual is within `tolerance`, no
/// surface law's step limit is passed (rep.surface) and the owned u (u_free) and β are finite on
/// every process. Collective.
bool step_accepted(const la::Comm& comm, const StepReport& rep, double tolerance, const Vector& u_free,
                   const Vector& beta_owned);

/// The backstop for an unstable explicit G (problem/stability.hpp), from the change of the lagged
/// rate ΔG_n = G_n − G_{n−1} (L2 over Ω) that each attempt's error estimate measures.
class LaggedStepBackstop {
 public:
  /// ΔG of the last accepted step (empty before the first).
  const std::vector<SymTensor>& last() const { return dG_last_; }
  /// An attempt's ΔG, |ΔG|² and (ΔG, ΔG of the last accepted step).
  void attempted(std::vector<SymTensor> dG, double dG2, double dot_last);
  /// After the last attempt was accepted as step rep.n ending in s: throws vpc::Error when ΔG
  /// flipped sign and grew in a row. Collective.
  void check_accepted(const DiscreteSystem& sys, const State& s, const StepReport& rep);

 private:
  std::vector<SymTensor> dG_last_, dG_attempt_;
  double dG2_last_ = 0, dG2_attempt_ = 0, dG_dot_attempt_ = 0;
  int growing_steps_ = 0;  // accepted steps in a row in which ΔG flipped sign and grew
  double growth_product_ = 1;  // its growth over them
};

}  // namespace vpc
