#include "problem/time_grid.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

namespace {

constexpr double kMaxSteps = 1e7;

}  // namespace

StepControl StepControl::completed(double T) const {
  StepControl c = *this;
  if (c.dt_initial == 0) c.dt_initial = T / 100;
  if (c.dt_max == 0) c.dt_max = T / 10;
  if (c.dt_min == 0) c.dt_min = std::min(T * 1e-6, c.dt_initial);
  if (c.event_dt == 0) c.event_dt = c.dt_initial;
  auto positive = [](double v, const char* what) {
    require(std::isfinite(v) && v > 0, "{} must be a number > 0 (got {})", what, v);
  };
  positive(c.tolerance, "the tolerance");
  positive(c.dt_initial, "dt_initial");
  positive(c.dt_min, "dt_min");
  positive(c.dt_max, "dt_max");
  positive(c.event_dt, "event_dt");
  require(c.dt_min <= c.dt_initial && c.dt_initial <= c.dt_max,
          "the step sizes must satisfy dt_min <= dt_initial <= dt_max (got {}, {}, {})", c.dt_min, c.dt_initial, c.dt_max);
  require(c.dt_max <= T, "dt_max must be <= T = {} (got {})", T, c.dt_max);
  require(T / c.dt_min <= kMaxSteps, "dt_min = {} allows {:.3g} steps over T = {}; at most {:.0e}", c.dt_min,
          T / c.dt_min, T, kMaxSteps);
  require(std::isfinite(c.growth) && c.growth >= 1 && c.growth <= 10, "growth must lie in [1, 10] (got {})", c.growth);
  require(std::isfinite(c.cut) && c.cut > 0 && c.cut < 1, "cut must lie in (0, 1) (got {})", c.cut);
  require(std::isfinite(c.safety) && c.safety > 0 && c.safety <= 1, "safety must lie in (0, 1] (got {})", c.safety);
  require(c.max_rejections >= 1, "max_rejections must be >= 1 (got {})", c.max_rejections);
  std::sort(c.landings.begin(), c.landings.end());
  for (double t : c.landings)
    require(std::isfinite(t) && t >= 0 && t <= T, "a time a step must end at ({}) lies outside [0, T = {}]", t, T);
  c.landings.erase(std::unique(c.landings.begin(), c.landings.end()), c.landings.end());
  return c;
}

std::string StepControl::describe() const {
  std::string events;
  if (contact_events) events = "contact set";
  if (damage_events) events += events.empty() ? "damage bounds" : " and damage bounds";
  // 6 significant digits: the defaults T/100, T/10, T·1e-6 are rarely the decimals they look like
  // (T = 1.3: "k from 0.013000000000000001").
  return fmt::format("error-controlled: tolerance {:.6g}, k from {:.6g} in [{:.6g}, {:.6g}]{}", tolerance, dt_initial,
                     dt_min, dt_max, events.empty() ? "" : fmt::format(", events ({}) located to {:.6g}", events, event_dt));
}

void check_fixed_grid(double T, std::span<const double> times, std::span<const double> sizes) {
  require(!times.empty(), "no time steps");
  require(static_cast<double>(times.size()) <= kMaxSteps, "{} time steps; at most {:.0e}", times.size(), kMaxSteps);
  require(sizes.empty() || sizes.size() == times.size(), "{} step sizes for {} steps", sizes.size(), times.size());
  double before = 0;
  for (std::size_t n = 0; n < times.size(); ++n) {
    require(std::isfinite(times[n]) && times[n] > before, "the times must increase: t_{} = {} after t_{} = {}", n + 1,
            times[n], n, before);
    require(sizes.empty() || std::abs(sizes[n] - (times[n] - before)) <= 1e-9 * sizes[n],
            "step {}: the size {} is not t_{} - t_{} = {}", n + 1, sizes.empty() ? 0.0 : sizes[n], n + 1, n,
            times[n] - before);
    before = times[n];
  }
  require(times.back() == T, "the last step ends at t = {}, not at T = {}", times.back(), T);
}

FixedGrid fixed_grid_of_steps(double T, std::span<const double> dt) {
  require(!dt.empty(), "the list of step sizes is empty");
  FixedGrid g;
  double t = 0;
  for (std::size_t i = 0; i < dt.size(); ++i) {
    require(std::isfinite(dt[i]) && dt[i] > 0, "step size {} (the {}. of the list) must be > 0", dt[i], i + 1);
    t += dt[i];
    g.times.push_back(t);
  }
  require(std::abs(t - T) <= 1e-9 * T, "the step sizes add up to {}, not to T = {}", t, T);
  g.times.back() = T;
  g.sizes.assign(dt.begin(), dt.end());
  check_fixed_grid(T, g.times, g.sizes);
  return g;
}

FixedGrid fixed_grid_of_intervals(double T, std::span<const double> breakpoints, std::span<const double> dt) {
  require(dt.size() == breakpoints.size() + 1,
          "{} breakpoints divide [0, T] into {} intervals: expected {} step sizes, got {}", breakpoints.size(),
          breakpoints.size() + 1, breakpoints.size() + 1, dt.size());
  FixedGrid g;
  double a = 0;
  for (std::size_t i = 0; i < dt.size(); ++i) {
    const double b = i < breakpoints.size() ? breakpoints[i] : T;
    require(std::isfinite(b) && b > a && b <= T, "breakpoint {} must lie in ({}, T = {}) and follow the one before", b,
            a, T);
    require(std::isfinite(dt[i]) && dt[i] > 0, "the step size of [{}, {}] must be > 0 (got {})", a, b, dt[i]);
    const double n = (b - a) / dt[i];
    require(n <= kMaxSteps, "the step size {} gives {:.3g} steps in [{}, {}]; at most {:.0e}", dt[i], n, a, b, kMaxSteps);
    require(std::abs(n - std::round(n)) <= 1e-9 * n, "the step size {} does not divide [{}, {}] into whole steps",
            dt[i], a, b);
    const long m = std::lround(n);
    for (long j = 1; j < m; ++j) g.times.push_back(a + static_cast<double>(j) * dt[i]);
    g.times.push_back(b);  // each interval ends exactly at its breakpoint
    g.sizes.insert(g.sizes.end(), static_cast<std::size_t>(m), dt[i]);
    a = b;
  }
  check_fixed_grid(T, g.times, g.sizes);
  return g;
}

FixedGrid fixed_grid_of_formula(double T, const std::function<double(double)>& k) {
  FixedGrid g;
  double t = 0;
  while (t < T) {
    const double kt = k(t);
    require(std::isfinite(kt) && kt > 0, "the step size k(t) must be > 0; it is {} at t = {}", kt, t);
    require(static_cast<double>(g.times.size()) < kMaxSteps, "k(t) gives more than {:.0e} steps over [0, T = {}]",
            kMaxSteps, T);
    const bool last = T - (t + kt) <= 1e-9 * T;
    g.sizes.push_back(last ? T - t : kt);
    t = last ? T : t + kt;
    g.times.push_back(t);
  }
  return g;
}

double step_end(double t, double k, double T, std::span<const double> landings) {
  const double eps = 1e-12 * T;
  const auto next = std::upper_bound(landings.begin(), landings.end(), t + eps);
  const double L = next == landings.end() ? T : std::min(*next, T);
  if (L - t <= k * (1 + 1e-9)) return L;
  if (L - t < 2 * k) return t + (L - t) / 2;
  return t + k;
}

}  // namespace vpc

namespace vpc {

double step_on_ladder(double k, double dt_min, double dt_max) {
  if (k >= dt_max) return dt_max;
  const double j = std::ceil(4 * std::log2(dt_max / k) - 1e-9);
  return std::max(dt_min, dt_max * std::exp2(-j / 4));
}

}  // namespace vpc
