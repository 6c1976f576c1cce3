// Issue 13: the shipped hertz-2d case against Hertz's line contact (docs/verification.md):
// with P the computed total contact force per unit length, a = √(4PR/(πE*)),
// p0 = 2P/(πa), p(x) = p0 √(1 − x²/a²). Tolerances of the issue: p0 within 2 %, the
// contact half-width within one element, RMS of p/p0 − √(1 − x²/a²) under 3 %.
#include "cases/builtin_cases.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace vpc {
namespace {

TEST(Hertz, LineContactOnARigidCylinder) {
  const Case c = load_case("hertz-2d");
  TimeStepper s(c.problem, c.solvers);
  const StepReport r = s.step();
  ASSERT_TRUE(r.ok);
  const double P = r.contact.total_force, R = 1.0, h = 0.02;
  const double E_star = c.problem->elasticity.young() / (1 - 0.3 * 0.3);
  const double a = std::sqrt(4 * P * R / (M_PI * E_star)), p0 = 2 * P / (M_PI * a);
  double p_max = 0, x_active = 0, sum_sq = 0;
  int n_inside = 0;
  for (const PartContactNode& node : s.part().contact) {
    const double lambda = s.state().lambda[node.row], x = s.mesh().node(node.local_node)[0];
    const double p = lambda / node.measure;  // the nodal contact pressure (VTU contact_pressure)
    p_max = std::max(p_max, p);
    if (lambda > 0) x_active = std::max(x_active, std::abs(x));
    if (std::abs(x) < a) {
      const double e = p / p0 - std::sqrt(1 - x * x / (a * a));
      sum_sq += e * e;
      ++n_inside;
    }
  }
  const double rms = std::sqrt(sum_sq / n_inside);
  std::printf("  hertz-2d: P = %.6g, a = %.5f (active to %.5f, a/h = %.1f), p0 = %.6g (computed %.6g, %+.2f %%), RMS %.2f %%\n",
              P, a, x_active, a / h, p0, p_max, 100 * (p_max / p0 - 1), 100 * rms);
  EXPECT_GE(a / h, 10.0);
  EXPECT_NEAR(p_max / p0, 1.0, 0.02);
  EXPECT_LE(std::abs(x_active - a), h);
  EXPECT_LT(rms, 0.03);
}

// Hertz's sphere contact, quarter model (hertz-3d): with P the force on the whole sphere
// (four times the quarter's), a = (3PR/(4E*))^(1/3), p0 = 3P/(2πa²), p(r) = p0 √(1 − r²/a²).
// The tolerances: p0 within 2 %, the contact radius within one element, RMS of
// p/p0 − √(1 − r²/a²) under 3 % (docs/verification.md §8c: on the unstructured mesh the
// nodal pressure λ_i/m_i scatters; the RMS is 5.1 % at a/h = 10, 2.8 % at a/h = 21).
TEST(Hertz, SphereIntoAHalfSpaceQuarterModel) {
  const Case c = load_case("hertz-3d");
  TimeStepper s(c.problem, c.solvers);
  const StepReport r = s.step();
  ASSERT_TRUE(r.ok);
  const double P = 4 * r.contact.total_force, R = 1.0, h = 0.005;
  const double E_star = c.problem->elasticity.young() / (1 - 0.3 * 0.3);
  const double a = std::cbrt(3 * P * R / (4 * E_star)), p0 = 3 * P / (2 * M_PI * a * a);
  double p_center = 0, r_active = 0, sum_sq = 0;
  int n_inside = 0;
  for (const PartContactNode& node : s.part().contact) {
    const double lambda = s.state().lambda[node.row];
    const Point& x = s.mesh().node(node.local_node);
    const double rho = std::hypot(x[0], x[1]), p = lambda / node.measure;
    if (rho < 1e-12) p_center = p;  // the node on the axis
    if (lambda > 0) r_active = std::max(r_active, rho);
    if (rho < a) {
      const double e = p / p0 - std::sqrt(1 - rho * rho / (a * a));
      sum_sq += e * e;
      ++n_inside;
    }
  }
  const double rms = std::sqrt(sum_sq / n_inside);
  std::printf("  hertz-3d: P = %.6g, a = %.5f (active to %.5f, a/h = %.1f), p0 = %.6g (computed %.6g, %+.2f %%), "
              "RMS %.2f %% over %d nodes\n",
              P, a, r_active, a / h, p0, p_center, 100 * (p_center / p0 - 1), 100 * rms, n_inside);
  EXPECT_GE(a / h, 20.0);
  EXPECT_NEAR(p_center / p0, 1.0, 0.02);
  EXPECT_LE(std::abs(r_active - a), h);
  EXPECT_LT(rms, 0.03);
}

}  // namespace
}  // namespace vpc
