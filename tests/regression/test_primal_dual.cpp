// Issue 14: the primal active-set contact solver and the dual one solve every shipped case
// alike: u, λ, σ and β to 1e-8 (relative to each field's largest value) over the first
// steps of each case (the steps where contact starts and grows), and both report the KKT
// residuals within the run's tolerance.
#include "cases/builtin_cases.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace vpc {
namespace {

double largest(const Vector& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

State run_steps(const std::string& name, const std::string& solver, int steps, int* active) {
  Case c = load_case(name);
  c.solvers.contact = solver;
  TimeStepper s(c.problem, c.solvers);
  EXPECT_EQ(s.contact_solver(), solver);
  for (int n = 0; n < steps && !s.done(); ++n) {
    const StepReport r = s.step();
    EXPECT_TRUE(r.ok) << name << " " << solver << " step " << n + 1;
    EXPECT_LE(r.contact.residuals.max(), c.solvers.residual_tolerance);
    *active = std::max(*active, r.contact.n_active);
  }
  return s.state();
}

TEST(PrimalDual, EveryShippedCaseAgrees) {
  for (const std::string& name : builtin_case_names()) {
    SCOPED_TRACE(name);
    int active_dual = 0, active_primal = 0;
    const State dual = run_steps(name, "active-set", 5, &active_dual);
    const State primal = run_steps(name, "primal-active-set", 5, &active_primal);
    EXPECT_EQ(active_primal, active_dual);
    EXPECT_LE(largest(primal.u - dual.u), 1e-8 * largest(dual.u));
    EXPECT_LE(largest(primal.lambda - dual.lambda), 1e-8 * std::max(largest(dual.lambda), 1e-300));
    EXPECT_LE(largest(primal.beta - dual.beta), 1e-8);
    double sigma = 0, scale = 0;
    for (std::size_t c = 0; c < dual.sigma.size(); ++c)
      for (int i = 0; i < 6; ++i) {
        sigma = std::max(sigma, std::abs(primal.sigma[c][i] - dual.sigma[c][i]));
        scale = std::max(scale, std::abs(dual.sigma[c][i]));
      }
    EXPECT_LE(sigma, 1e-8 * scale);
  }
}

}  // namespace
}  // namespace vpc
