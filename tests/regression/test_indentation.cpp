// Issue 13: the shipped indentation-3d case (docs/verification.md "Indentation with
// damage"): a spherical punch indents the paper's material, quarter model. What must hold:
// the base's reaction balances the punch's force every step (the symmetry planes take only
// normal forces, the punch only vertical ones on the axis-symmetric load); the damage
// concentrates below the surface on the axis, where Hertz's von Mises stress peaks; and the
// force-indentation curve lies below the elastic one of the same mesh, since damage softens.
#include "cases/builtin_cases.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace vpc {
namespace {

/// The force on the punch at every step.
std::vector<double> force_curve(TimeStepper& s, std::vector<StepReport>* reports = nullptr) {
  std::vector<double> force;
  while (!s.done()) {
    const StepReport r = s.step();
    EXPECT_TRUE(r.ok) << "step " << r.n;
    force.push_back(r.obstacle_force.at(0));
    if (reports) reports->push_back(r);
  }
  return force;
}

TEST(Indentation, DamageGrowsUnderThePunchAndSoftensTheResponse) {
  const Case c = load_case("indentation-3d");
  TimeStepper s(c.problem, c.solvers);
  std::vector<StepReport> reports;
  const std::vector<double> damaged = force_curve(s, &reports);
  const auto parts = dirichlet_parts(*c.problem);  // symmetry_x (x), symmetry_y (y), base (z)
  ASSERT_EQ(parts.back(), "base");
  for (std::size_t n = 0; n < reports.size(); ++n) {
    if (n > 0) {
      EXPECT_GT(damaged[n], damaged[n - 1]);
    }
    EXPECT_NEAR(reports[n].reaction.back(), damaged[n], 1e-10 * damaged[n]);  // base z against the punch
  }
  const StepReport& last = reports.back();
  const Point& x = s.mesh().node(last.beta_min_node);
  std::printf("  indentation-3d: force %.5g at T, min beta %.4f at (%.4f, %.4f, %.4f)\n", damaged.back(),
              last.beta_min, x[0], x[1], x[2]);
  EXPECT_LT(last.beta_min, 0.5);
  EXPECT_LT(std::hypot(x[0], x[1]), 0.03);  // on the axis (within a few elements) ...
  EXPECT_LT(x[2], -0.02);                   // ... and below the surface
  EXPECT_GT(x[2], -0.12);

  const Case elastic = load_case("indentation-3d", {.sets = {"viscoplasticity.law=\"elastic\"", "damage.c=0"}});
  TimeStepper e(elastic.problem, elastic.solvers);
  const std::vector<double> intact = force_curve(e);
  std::printf("  indentation-3d: elastic force %.5g at T: the damaged one is %.2f %% lower\n", intact.back(),
              100 * (1 - damaged.back() / intact.back()));
  EXPECT_LT(damaged.back(), 0.98 * intact.back());
}

}  // namespace
}  // namespace vpc
