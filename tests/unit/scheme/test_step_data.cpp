// The step's data (scheme/step_data.hpp): F_n, u_D(t_n) and g(t_n) evaluated together at t_n,
// then checked once, so that a formula that stops being a number is named with its time
// whichever datum it feeds (issue 26).
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "scheme/discrete_system.hpp"
#include "scheme/step_data.hpp"

#include <gtest/gtest.h>

#include <string>

#include "../error_of.hpp"
#include "bar_case.hpp"

namespace vpc {
namespace {

Case bar(const std::string& gap) { return parse_case(test::bar_text("[contact]\ngap = " + gap + "\n"), "step-data.toml", ".", {}); }

DiscreteSystem system_of(const Case& c) {
  return DiscreteSystem(c.problem, whole_mesh_part(c.problem), la::serial_backend(), SolverChoice{});
}

TEST(StepData, IsTheLoadDisplacementAndGapAtT) {
  const Case c = bar("\"0.6 - t\"");
  const DiscreteSystem sys = system_of(c);
  const StepData data = step_data(sys, 0.25);
  EXPECT_EQ(data.t, 0.25);
  EXPECT_EQ(data.F, load(sys, 0.25));
  EXPECT_EQ(data.u_D.size(), 0);  // no prescribed displacement but zero
  ASSERT_EQ(data.gap.size(), 1);
  EXPECT_DOUBLE_EQ(data.gap[0], 0.6 - 0.25);
}

TEST(StepData, AFormulaThatStopsBeingANumberIsNamedWithItsTime) {
  const Case c = bar("\"sqrt(0.55 - t)\"");
  const DiscreteSystem sys = system_of(c);
  EXPECT_NO_THROW(step_data(sys, 0.5));
  const std::string msg = error_of([&] { step_data(sys, 0.6); });
  EXPECT_NE(msg.find("contact.gap: the formula \"sqrt(0.55 - t)\" gives NaN at t = 0.6"), std::string::npos) << msg;
}

}  // namespace
}  // namespace vpc
