// Issue 13: the shipped patch-3d case (docs/verification.md "Patch test"): a cube on
// three symmetry planes compressed by a prescribed u_z = −0.01 t on its top. The exact
// solution is a uniform uniaxial stress, which P1 elements reproduce: every cell's state
// must be the same to round-off, the lateral stresses zero, and the reactions the
// stress times the faces' areas.
#include "cases/builtin_cases.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vpc {
namespace {

/// The largest deviation of any cell's σ from cell 0's, relative to |σ_zz|, and of β from node 0's.
struct Uniformity {
  double sigma = 0, beta = 0, lateral = 0;  // lateral: max |σ_ij| over ij ≠ zz, relative to |σ_zz|
};

Uniformity uniformity(const TimeStepper& s) {
  const State& st = s.state();
  const double szz = std::abs(st.sigma[0](2, 2));
  Uniformity u;
  for (const SymTensor& sigma : st.sigma)
    for (int k = 0; k < 6; ++k) {
      u.sigma = std::max(u.sigma, std::abs(sigma[k] - st.sigma[0][k]) / szz);
      if (k != 2) u.lateral = std::max(u.lateral, std::abs(sigma[k]) / szz);
    }
  for (Eigen::Index i = 0; i < st.beta.size(); ++i) u.beta = std::max(u.beta, std::abs(st.beta[i] - st.beta[0]));
  return u;
}

/// A reaction of the step: each of these parts prescribes one component (top and bottom z, left x).
double reaction(const TimeStepper& s, const StepReport& r, const std::string& part) {
  const auto parts = dirichlet_parts(s.problem());
  return r.reaction.at(static_cast<std::size_t>(std::find(parts.begin(), parts.end(), part) - parts.begin()));
}

TEST(PatchTest, ElasticCubeOnRollersHasTheExactUniaxialStress) {
  const Case c = load_case("patch-3d", {.sets = {"viscoplasticity.law=\"elastic\"", "damage.c=0"}});
  TimeStepper s(c.problem, c.solvers);
  double worst = 0;
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok);
    const double exact = -1000.0 * 0.01 * r.t;  // σ_zz = E ε_zz, uniaxial
    const Uniformity u = uniformity(s);
    const double szz = s.state().sigma[0](2, 2);
    worst = std::max({worst, u.sigma, u.lateral, std::abs(szz / exact - 1)});
    // Reactions: −σ_zz on the top (outward normal +z), +σ_zz on the bottom, the unit area.
    EXPECT_NEAR(reaction(s, r, "top"), exact, 1e-12 * std::abs(exact));
    EXPECT_NEAR(reaction(s, r, "bottom"), -exact, 1e-12 * std::abs(exact));
    EXPECT_NEAR(reaction(s, r, "left"), 0.0, 1e-12 * std::abs(exact));
    // u = (ν 0.01 t x, ν 0.01 t y, −0.01 t z): the lateral expansion, exactly.
    for (int i = 0; i < s.mesh().n_nodes(); ++i) {
      const Point& x = s.mesh().node(i);
      EXPECT_NEAR(s.state().u[3 * i + 0], 0.3 * 0.01 * r.t * x[0], 1e-14);
      EXPECT_NEAR(s.state().u[3 * i + 2], -0.01 * r.t * x[2], 1e-14);
    }
  }
  std::printf("  patch-3d elastic: largest relative deviation from the exact uniform stress %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(PatchTest, ThePapersMaterialStaysUniform) {
  const Case c = load_case("patch-3d");
  TimeStepper s(c.problem, c.solvers);
  Uniformity worst;
  StepReport r;
  while (!s.done()) {
    r = s.step();
    ASSERT_TRUE(r.ok);
    const Uniformity u = uniformity(s);
    worst = {std::max(worst.sigma, u.sigma), std::max(worst.beta, u.beta), std::max(worst.lateral, u.lateral)};
    EXPECT_NEAR(reaction(s, r, "top"), s.state().sigma[0](2, 2), 1e-12 * std::abs(s.state().sigma[0](2, 2)));
  }
  std::printf("  patch-3d (Maxwell-type G, von Mises source): sigma %.2e, lateral %.2e, beta %.2e; beta = %.6f\n",
              worst.sigma, worst.lateral, worst.beta, s.state().beta[0]);
  EXPECT_LT(worst.sigma, 1e-12);
  EXPECT_LT(worst.lateral, 1e-12);
  EXPECT_LT(worst.beta, 1e-13);
  EXPECT_LT(s.state().beta[0], 0.99);  // the damage did grow
}

}  // namespace
}  // namespace vpc
