// A failed step's message (scheme/step_failure): which solver and which residual failed,
// with its value against the tolerance, or the iteration limit, or NaN/Inf; never
// "converged" for a failure; --retry-halvings only where smaller steps can help (issue 26).
#include "scheme/step_failure.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace vpc {
namespace {

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

StepReport converged_step() {
  StepReport r;
  r.contact.converged = r.damage.converged = true;
  r.contact.iterations = 1;
  return r;
}

// The reporter's thin layer before the fix: the dual solver converged, its complementarity
// and penetration residuals were 1: named, with their values and the tolerance.
TEST(StepFailure, NamesTheContactResidualAboveTheTolerance) {
  StepReport r = converged_step();
  r.contact.residuals = {1e-17, 1.0, 0.0, 0.5};
  const std::string s = step_failure(r, 1e-8);
  EXPECT_EQ(s,
            "the contact solver ended after 1 iteration with its penetration residual 1.00e+00 (feasibility: Nu <= g), "
            "complementarity residual 5.00e-01 (lambda_i (g - Nu)_i = 0) above the tolerance 1.0e-08");
  EXPECT_FALSE(has(s, "converged"));
  EXPECT_FALSE(has(s, "damage"));  // the damage solver met the tolerance
  EXPECT_FALSE(halving_can_help(r, 1e-8));  // the step size does not change that residual
}

TEST(StepFailure, NamesEquilibriumAndNegativeForce) {
  StepReport r = converged_step();
  r.contact.iterations = 3;
  r.contact.residuals = {2e-6, 0.0, 3e-7, 0.0};
  const std::string s = step_failure(r, 1e-8);
  EXPECT_TRUE(has(s, "after 3 iterations with its equilibrium residual 2.00e-06 (KKT stationarity: Ku = F - N^T lambda), "
                     "negative-force residual 3.00e-07 (feasibility: lambda >= 0) above the tolerance 1.0e-08"))
      << s;
}

TEST(StepFailure, IterationLimitIsSaidAndHalvingOffered) {
  StepReport r = converged_step();
  r.contact.converged = false;
  r.contact.iterations = 200;
  const std::string s = step_failure(r, 1e-8);
  EXPECT_EQ(s, "the contact solver stopped at its iteration limit after 200 iterations without converging");
  EXPECT_TRUE(halving_can_help(r, 1e-8));
}

TEST(StepFailure, DamageKktResidual) {
  StepReport r = converged_step();
  r.damage.iterations = 4;
  r.damage.kkt_residual = 3e-5;
  const std::string s = step_failure(r, 1e-8);
  EXPECT_EQ(s, "the damage solver ended after 4 iterations with its KKT residual 3.00e-05 (stationarity, "
               "0 <= beta <= 1 and complementarity) above the tolerance 1.0e-08");
  EXPECT_TRUE(halving_can_help(r, 1e-8));  // H = M + k kappa A depends on k
}

TEST(StepFailure, NotFiniteData) {
  StepReport r = converged_step();
  const double inf = std::numeric_limits<double>::infinity();
  r.contact.residuals = {inf, inf, inf, inf};
  EXPECT_EQ(step_failure(r, 1e-8), "the contact solver met NaN or Inf in its data or solution");
  EXPECT_TRUE(halving_can_help(r, 1e-8));
}

// Both solvers within the tolerance: the state's own check failed (TimeStepper::step).
TEST(StepFailure, StateNotFinite) {
  const StepReport r = converged_step();
  EXPECT_TRUE(has(step_failure(r, 1e-8), "NaN or Inf although both solvers met the tolerance"));
  EXPECT_TRUE(halving_can_help(r, 1e-8));
}

}  // namespace
}  // namespace vpc
