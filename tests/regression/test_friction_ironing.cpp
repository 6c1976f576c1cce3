// Issue 28: the shipped ironing-3d case (docs/verification.md "Ironing"): a rigid sphere pressed
// into the paper's damaging viscoplastic block and dragged across it, Coulomb μ = 0.3. It must run
// to its end with every step's residuals within the tolerance (run_to_end), the drag force must
// stay within μ times the normal force, and β must fall along the track.
#include "friction_runs.hpp"

#include <cstdio>

namespace vpc {
namespace {

using namespace friction_test;

TEST(FrictionIroning, RunsToTheEndWithEveryResidualWithinTolerance) {
  const Case c = load_case("ironing-3d");
  double worst = 0, drag_ratio = 0;
  int steps = 0, slip_steps = 0;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    const ContactResiduals& e = r.contact.residuals;
    worst = std::max(worst, e.max());
    ++steps;
    // The bottom is the only Dirichlet part: (R_x, R_y, R_z) balance the contact forces; the
    // top's contact directions are (0, 0, 1), so R_x is the drag alone.
    const double drag = std::abs(r.reaction[0]), normal = std::abs(r.reaction[2]);
    drag_ratio = std::max(drag_ratio, drag / normal);
    slip_steps += r.contact.n_slip > 0;
    if (r.n % 5 == 0)
      std::printf("  t = %.2f: %3d active (%3d stick, %3d slip), drag %.4g, normal %.4g (ratio %.4f), min beta %.4f, "
                  "residuals: friction bound %.1e, stick-slip %.1e, slip direction %.1e, largest %.1e; %d iterations\n",
                  r.t, r.contact.n_active, r.contact.n_stick, r.contact.n_slip, drag, normal, drag / normal, r.beta_min,
                  e.friction_bound, e.stick_slip, e.slip_direction, e.max(), r.contact.iterations);
    (void)s;
  });
  std::printf("  ironing-3d: %d steps, largest residual %.2e (tolerance %.0e), largest drag / normal %.4f (mu = 0.3)\n", steps,
              worst, c.solvers.residual_tolerance, drag_ratio);
  EXPECT_EQ(steps, c.problem->n_steps);
  EXPECT_LE(drag_ratio, 0.3 * (1 + 1e-6));
  EXPECT_GT(drag_ratio, 0.2);  // the sphere drags: most of the contact slides
  EXPECT_GT(slip_steps, steps / 2);
}

}  // namespace
}  // namespace vpc
