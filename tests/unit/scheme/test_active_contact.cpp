// The active contact set of both contact solvers on whole steps (issue 11 item 12).
#include "cases/builtin_cases.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

namespace vpc {
namespace {

// Both contact solvers report the same number of active nodes at every step (the
// penalty–duality multiplier is counted against its own tolerance).
TEST(ActiveContact, BothSolversCountTheSameNodes) {
  // A Hertz-like contact: the whole base over a parabolic gap, the zone grows from x = 1.
  auto p = load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem;
  p->contact.parts = {"bottom"};
  p->contact.gap = [](const Point& x, double) { return 0.05 * (x[0] - 1) * (x[0] - 1); };
  SolverChoice pd;
  pd.contact = "penalty-duality";
  TimeStepper a(p), b(p, pd);
  while (!a.done()) {
    const StepReport ra = a.step(), rb = b.step();
    ASSERT_TRUE(ra.ok);
    ASSERT_TRUE(rb.ok);
    EXPECT_GT(ra.contact.n_active, 0);
    EXPECT_LT(ra.contact.n_active, a.part().n_contact);
    EXPECT_EQ(rb.contact.n_active, ra.contact.n_active) << "step " << ra.n;
  }
}

}  // namespace
}  // namespace vpc
