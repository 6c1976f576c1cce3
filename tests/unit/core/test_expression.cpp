#include "core/expression.hpp"

#include "../error_of.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace vpc {
namespace {

// Issue 26: a formula that gives NaN or ±inf is reported with its key, the time and the
// point, and the same evaluation whichever thread of an OpenMP loop met it first.
TEST(Expression, AValueThatIsNotFiniteIsReportedWithItsKeyTimeAndPoint) {
  const Expression e("x > 0.5 ? log(x - t) : x", Expression::Kind::SpaceTime, "c.toml:3:7: loads.f0[0]");
  EXPECT_NO_THROW(e.check_finite());
#pragma omp parallel for
  for (int i = 0; i < 1000; ++i) (void)e(Point{i / 999.0, 0.25, 0}, 0.9);
  EXPECT_TRUE(std::isnan(e(Point{0.75, 0, 0}, 1.0)));  // a later time does not replace the earliest
  const std::string m = error_of([&] { e.check_finite(); });
  EXPECT_NE(m.find("c.toml:3:7: loads.f0[0]: the formula \"x > 0.5 ? log(x - t) : x\" gives NaN at t = 0.9 at the "
                   "point (0.5005005005005005, 0.25, 0)"),
            std::string::npos)
      << m;
  // A formula of t alone names no point; an infinite value is named as such.
  const Expression f("1/(t - 0.5)", Expression::Kind::SpaceTime, "c.toml:4:1: obstacle[0].point[1]");
  (void)f(Point{1, 2, 3}, 0.5);
  EXPECT_NE(error_of([&] { f.check_finite(); }).find("gives inf at t = 0.5; every value"), std::string::npos);
}

}  // namespace
}  // namespace vpc
