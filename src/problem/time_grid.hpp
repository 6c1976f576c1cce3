#pragma once
// The partition 0 = t_0 < t_1 < … < t_N = T of (3.4)–(3.9) when it is not uniform.
// The paper's analysis (Theorem 3.5) holds for any partition, with k = max_n k_n;
// the scheme only needs k_n = t_n − t_{n−1} at each step (H_n = M + k_n κ A).
//   - a fixed grid: a list of step sizes, steps per interval between breakpoints,
//     or a formula k(t) (fixed_grid_* below: the times t_1 … t_N);
//   - error-controlled steps (StepControl): each step's size follows an estimate
//     of its local error (TimeStepper, docs/scheme.md "Step sizes").
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace vpc {

/// Error-controlled steps. The estimate of a step from t_{n−1} to t_n is the local error
/// (k_n/2)|x'(t_n) − x'(t_{n−1})| of a first-order step, for the rates of (3.6) and (3.8):
///   e_σ = (k_n / 2) |G_n − G_{n−1}|_{L2} / max_{m ≤ n} |σ_m|_{L2} · min(1, 1 / (μ_n T)),
///   e_β = (k_n / 2) |M_L⁻¹ (F_φ(n) − F_φ(n−1) − κ A (β_n − β_{n−1}))|_{M_L} / |Ω|^{1/2}
/// (M β' = F_φ − κAβ; M_L the lumped mass; nodes at β = 0 or 1 left out),
/// e_n = max(e_σ, e_β): the relative error the step adds in the norms of Theorem 3.5
/// (u follows z through K, so σ's error bounds u's). μ_n is the rate at which the law damps
/// an error of z along ΔG = G_n − G_{n−1}: −⟨ΔG, J ΔG⟩/|ΔG|² with J = ∂G/∂σ, as the explicit
/// step keeps it (min(μ, −ln|1 − k_n μ| / k_n), 0 from k_n μ ≥ 2 on). Such an error lasts
/// about 1/μ_n, not until T: counted as lasting to T, a Perzyna law with E/(2λ) = 50 had its
/// errors overstated 50 times (issue 26). A step is accepted when e_n ≤ tolerance · k_n (an
/// error per unit of time: the errors add up to about tolerance · T at any time up to T; the
/// criterion depends on T only where μ_n T > 1); the next step is
/// k_n · safety / r, r = e_n / (tolerance k_n),
/// limited to [cut, growth] times k_n and to [dt_min, dt_max]. A rejected step is redone
/// from the exact state before it with k_n · max(cut, safety / r).
struct StepControl {
  double tolerance = 1e-3;
  double dt_initial = 0, dt_min = 0, dt_max = 0;  // 0: T / 100, T · 1e-6, T / 10
  double growth = 2, cut = 0.5, safety = 0.9;
  /// Events: a step in which the contact active set changes (contact_events) or a
  /// node reaches β = 0 or β = 1 (damage_events) is redone with smaller steps until
  /// it is at most event_dt long, so that the event is located to within event_dt
  /// (0: dt_initial). A step whose solver fails is always redone with a smaller step.
  double event_dt = 0;
  bool contact_events = true, damage_events = true;
  /// Rejections of one step before the run fails.
  int max_rejections = 30;
  /// Times a step must end at (breakpoints, output times), besides T.
  std::vector<double> landings;

  /// The defaults that depend on T filled in; throws vpc::Error for a bad value.
  StepControl completed(double final_time) const;
  std::string describe() const;
};

/// A fixed grid: the times t_1 … t_N = T and the step sizes k_n the scheme uses, as given
/// (t_n − t_{n−1} to round-off: a size given once is one damage matrix, not one per
/// rounding of t_n − t_{n−1}).
struct FixedGrid {
  std::vector<double> times, sizes;
};

/// The steps `dt` (their sum must be T to a relative 1e-9; t_N = T exactly).
FixedGrid fixed_grid_of_steps(double final_time, std::span<const double> dt);
/// Steps of size dt[i] from breakpoint b_{i−1} to b_i (b_{−1} = 0, the last interval ends at T);
/// each interval must hold whole steps (to a relative 1e-9) and end exactly at its breakpoint.
FixedGrid fixed_grid_of_intervals(double final_time, std::span<const double> breakpoints, std::span<const double> dt);
/// t_{n+1} = t_n + k(t_n), the last step shortened to end at T (a remainder below 1e-9 T
/// joins the step before). Throws for k(t) ≤ 0, not finite, or more than 1e7 steps.
FixedGrid fixed_grid_of_formula(double final_time, const std::function<double(double)>& k);
/// Throws unless `times` increase strictly and end at T, and `sizes` (if any) are their differences.
void check_fixed_grid(double final_time, std::span<const double> times, std::span<const double> sizes = {});

/// The end of a step of size k from t: t + k, or the next landing (or T) where that
/// is within the step or less than half a step beyond it (no sliver of a step is left
/// before a landing: the remainder is split into two equal steps instead).
double step_end(double t, double k, double final_time, std::span<const double> landings);
/// The error control's step sizes: the largest dt_max 2^(−j/4) (j = 0, 1, …) that is ≤ k, so
/// that steps come in a few sizes whose damage matrices are kept (no less than dt_min).
double step_on_ladder(double k, double dt_min, double dt_max);

}  // namespace vpc
