// Issue 13: a gap that depends on t (a rigid obstacle that moves). Each step's
// contact problem uses g(x, t_n): an obstacle that moves into the body pushes it
// back (g < 0 is allowed after t = 0), and the contact node then sits on it.
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <string>

#include "../error_of.hpp"
#include "bar_case.hpp"

namespace vpc {
namespace {

/// The test bar (bar_case.hpp) with this gap.
Case bar(const std::string& gap) { return parse_case(test::bar_text("[contact]\ngap = " + gap + "\n"), "moving-gap.toml", ".", {}); }

TEST(MovingGap, TheTipFollowsTheObstacleIntoTheBody) {
  const Case c = bar("\"0.6 - t\"");
  TimeStepper s(c.problem, c.solvers);
  const int tip = s.contact().nodes.front().local_node;
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok) << "step " << r.n;
    const double g = 0.6 - r.t;
    EXPECT_LE(s.state().u[tip], g + 1e-12) << "t = " << r.t;  // never through the obstacle
    if (s.state().lambda[0] > 0) {
      EXPECT_NEAR(s.state().u[tip], g, 1e-12) << "t = " << r.t;
    }
  }
  // At T the obstacle is 0.4 inside the reference body: the tip was pushed back there.
  EXPECT_NEAR(s.state().u[tip], -0.4, 1e-12);
  EXPECT_GT(s.state().lambda[0], 0.0);
}

TEST(MovingGap, AFormulaConstantInTimeIsTheFixedGap) {
  const Case fixed = bar("0.3"), formula = bar("\"0.3 + 0*t\"");
  EXPECT_FALSE(fixed.problem->contact.gap_moves);
  EXPECT_TRUE(formula.problem->contact.gap_moves);
  TimeStepper a(fixed.problem, fixed.solvers), b(formula.problem, formula.solvers);
  while (!a.done()) {
    a.step();
    b.step();
    EXPECT_EQ(a.state().u, b.state().u);
    EXPECT_EQ(a.state().lambda, b.state().lambda);
  }
}

TEST(MovingGap, AGapThatStopsBeingANumberIsNamedWithItsTime) {
  const Case c = bar("\"sqrt(0.55 - t)\"");
  TimeStepper s(c.problem, c.solvers);
  const std::string msg = error_of([&] {
    while (!s.done()) s.step();
  });
  EXPECT_NE(msg.find("contact.gap: the formula \"sqrt(0.55 - t)\" gives NaN at t = 0.6"), std::string::npos) << msg;
}

TEST(MovingGap, TheGapAtTheStartMustStillBeNonNegative) {
  const std::string msg = error_of([] { bar("\"-0.1 + t\""); });
  EXPECT_NE(msg.find("moving-gap.toml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("must be >= 0"), std::string::npos) << msg;
}

}  // namespace
}  // namespace vpc

namespace vpc {
namespace {

// [contact] law = "normal-compliance": the paper's case with a stiff law is the
// Signorini answer (c → ∞), a soft one lets the body in; bad keys are located.
TEST(NormalCompliance, StiffLawRecoversSignoriniAndSoftLawPenetrates) {
  auto run = [](const std::string& law) {
    const Case c = bar("0.3\n" + law);
    TimeStepper s(c.problem, c.solvers);
    while (!s.done()) EXPECT_TRUE(s.step().ok);
    return std::make_pair(s.state().u[8], s.state().lambda[0]);
  };
  const auto [u_s, l_s] = run("");
  const auto [u_stiff, l_stiff] = run("law = \"normal-compliance\"\nstiffness = 1e10");
  const auto [u_soft, l_soft] = run("law = \"normal-compliance\"\nstiffness = 2");
  EXPECT_NEAR(u_s, 0.3, 1e-12);
  EXPECT_NEAR(u_stiff, u_s, 1e-9);
  EXPECT_NEAR(l_stiff, l_s, 1e-8 * l_s);
  EXPECT_GT(u_soft, 0.3 + 1e-3);
  EXPECT_NEAR(l_soft, 2 * (u_soft - 0.3), 1e-12);  // λ = c |Γ3| (u − g), |Γ3| = 1 in 1D
  std::string m = error_of([] { bar("0.3\nlaw = \"normal-compliance\"\n"); });
  EXPECT_NE(m.find("missing key 'contact.stiffness'"), std::string::npos) << m;
  m = error_of([] { bar("0.3\nstiffness = 5"); });
  EXPECT_NE(m.find("contact.stiffness: stiffness belongs to law = \"normal-compliance\""), std::string::npos) << m;
  m = error_of([] { bar("0.3\nlaw = \"penalty\""); });
  EXPECT_NE(m.find("contact.law"), std::string::npos) << m;
}

}  // namespace
}  // namespace vpc
