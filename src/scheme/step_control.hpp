#pragma once
// Step-size control (like PETSc's TSAdapt): the estimate of the error a step adds, the
// error-controlled step (accept, or reject and redo from a snapshot with a smaller step;
// StepControl, problem/time_grid.hpp), halving of a failed step on a fixed grid, and what
// the step sizes carry from step to step.
#include "la/vector.hpp"
#include "problem/time_grid.hpp"
#include "scheme/discrete_system.hpp"
#include "scheme/scheme_step.hpp"
#include "scheme/state.hpp"
#include "scheme/step_report.hpp"

#include <functional>
#include <vector>

namespace vpc {

/// Everything a step changes, on this process: the state and the solvers' warm
/// starts. Restoring a snapshot makes the following steps bit-identical to a run
/// that never left it.
struct Snapshot {
  State state;
  Vector u_free;                     // owned free dofs
  Vector contact_warm, damage_warm;  // ContactSolver / DamageSolver::warm_state
};

/// Whether s can be restored into a run of `problem` whose state is `now` and whose owned free
/// dofs number n_u_free: the same sizes, a step within the run.
bool snapshot_fits(const Snapshot& s, const State& now, Eigen::Index n_u_free, const Problem& problem);

/// What the step sizes carry from step to step (kept in checkpoints, so that a resumed
/// run takes the same steps as one that was never stopped).
struct StepControlState {
  double k_next = 0;       // error-controlled: the next step's size before landings (0: dt_initial)
  double sigma_scale = 0;  // max over the steps so far of |σ_n|_L2 (the estimate's scale)
  double n_active = 0, n_beta_zero = 0, n_beta_one = 0;  // the last step's sets (events)
  double rejected = 0;     // steps rejected over the run
  /// As values (checkpoints), and back; throws vpc::Error for a wrong count.
  Vector values() const;
  static StepControlState from_values(const Vector& v);
  /// The accepted step rep: its |σ_n| joins the scale, its sets are the last ones.
  void accept(const StepReport& rep);
};

/// The error estimate of a step and what the stability backstop takes from it.
struct ErrorEstimate {
  double error = 0;       // StepReport::error_estimate
  double sigma_norm = 0;  // |σ_n|_L2
  std::vector<SymTensor> dG;  // ΔG = G_n − G_{n−1} per cell
  double dG2 = 0;         // |ΔG|² (L2)
  double dG_dot_last = 0; // (ΔG, dG_last) (L2)
};

/// The estimate (StepControl, problem/time_grid.hpp) of the relative error the step `taken` (of
/// size k, ending in the state s) adds: the local error (k/2)|x'(t_n) − x'(t_{n−1})| of the
/// explicit rate of z, G (3.6), weighted by 1/(μT) where the law damps it (error_damping), of
/// β's rate in (3.8), and of the surface laws' lagged rates (SurfaceLimits::rate_change). `now`: G_n, φ_n; dG_last: ΔG of the last accepted step; sigma_scale:
/// StepControlState::sigma_scale. Collective.
ErrorEstimate estimate_error(const DiscreteSystem& sys, const State& s, const StepTaken& taken, const LaggedRates& now,
                             double k, const std::vector<SymTensor>& dG_last, double sigma_scale);

/// Per cell, ⟨ΔG, J ΔG⟩ with ΔG = G_n − G_{n−1} and J = ∂G/∂σ at the state s (a difference
/// quotient of the law): how fast the law damps an error of z in the direction of the step's
/// local error (the error estimate's μ). `now`: G_n at s.
std::vector<double> error_damping(const DiscreteSystem& sys, const State& s, const std::vector<SymTensor>& G_now,
                                  const std::vector<SymTensor>& G_before);

/// What step-size control asks of the scheme: an attempt of a step from the current state
/// to t_end with the step k, and a return to a state saved before it.
struct StepAttempts {
  std::function<StepReport(double k, double t_end)> advance;
  std::function<Snapshot()> snapshot;
  std::function<void(const Snapshot&)> restore;
};

/// A step of a fixed grid to t_end with the step k; a failed one is redone as two half steps,
/// nested at most max_halvings − level times. Collective.
StepReport advance_or_halve(const StepAttempts& a, int level, int max_halvings, double k, double t_end);

/// An error-controlled step (Problem::step_control) from the current state, as `c` with the
/// final time T allows; updates cs.k_next and cs.rejected when the step is accepted. Collective.
StepReport controlled_step(const StepAttempts& a, const StepControl& c, StepControlState& cs, double T);

/// Whether the step's sets changed from cs's in a way c redoes with a smaller step.
bool is_event(const StepControl& c, const StepControlState& cs, const StepReport& rep);

}  // namespace vpc
