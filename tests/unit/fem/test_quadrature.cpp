// The degree-2 simplex rules integrate every polynomial of degree ≤ 2 exactly:
// ∫_T λ^α = |T| d! α! / (d + |α|)!  (barycentric monomials).
#include "fem/quadrature.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace vpc {
namespace {

double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

TEST(Quadrature, ExactForDegreeTwoBarycentricMonomials) {
  for (int d = 1; d <= 3; ++d) {
    const auto& rule = simplex_rule(d);
    double wsum = 0;
    for (const auto& q : rule) wsum += q.weight;
    EXPECT_NEAR(wsum, 1.0, 1e-15) << "d = " << d;
    for (int a = 0; a <= d; ++a)
      for (int b = 0; b <= d; ++b) {
        double s = 0;
        for (const auto& q : rule) s += q.weight * q.lambda[a] * q.lambda[b];
        // ∫ λa λb / |T| = d! (1 + δab) / (d + 2)!
        const double exact = factorial(d) * (a == b ? 2.0 : 1.0) / factorial(d + 2);
        EXPECT_NEAR(s, exact, 1e-15) << "d = " << d << " a = " << a << " b = " << b;
        double l = 0;
        for (const auto& q : rule) l += q.weight * q.lambda[a];
        EXPECT_NEAR(l, 1.0 / (d + 1), 1e-15);
      }
  }
}

TEST(Quadrature, DegreeThreeIsNotExactInOneDimension) {
  // Guards the test above against a rule that happens to be exact for everything.
  double s = 0;
  for (const auto& q : simplex_rule(1)) s += q.weight * std::pow(q.lambda[0], 4);
  EXPECT_GT(std::abs(s - 1.0 / 5.0), 1e-4);
}

}  // namespace
}  // namespace vpc
