// Issue 26 item 1: the lagged viscoplastic step z_n = z_{n−1} + k G_{n−1} is explicit, stable only
// for k L ≤ 2 (problem/stability.hpp). Each law states L; set-up refuses a step beyond the bound;
// a run that becomes unstable anyway stops; error-controlled steps never exceed the bound.
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "material/viscoplastic_law.hpp"
#include "problem/stability.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../error_of.hpp"

namespace vpc {
namespace {

const std::vector<std::string> kPerzyna = {"viscoplasticity.law=perzyna", "viscoplasticity.lambda=1.0",
                                           "viscoplasticity.sigma_y=2.0"};
const std::vector<std::string> kMaxwell = {"viscoplasticity.law=maxwell-damage", "viscoplasticity.rate=1000",
                                           "damage.c=1"};

/// paper-2d (E = 1000) on a 10 × 10 mesh with these keys set.
Case block(std::vector<std::string> sets, std::optional<int> steps) {
  return load_case("paper-2d", {.sets = std::move(sets), .steps = steps}, {.cells = 10});
}

TEST(StepStability, EachLawStatesItsLipschitzConstant) {
  const auto perzyna = make_viscoplastic_law("perzyna", {{"E", 1000.0}, {"lambda", 1.0}, {"sigma_y", 2.0}});
  const auto von_mises = make_viscoplastic_law("perzyna-von-mises", {{"E", 1000.0}, {"lambda", 1.0}, {"sigma_y", 2.0}});
  const auto maxwell = make_viscoplastic_law("maxwell-damage", {{"rate", 1000.0}});
  const auto elastic = make_viscoplastic_law("elastic", {});
  EXPECT_EQ(perzyna->lipschitz(1).value, 500);  // E/(2λ)
  EXPECT_EQ(perzyna->lipschitz(0).value, 500);
  EXPECT_EQ(von_mises->lipschitz(0.5).value, 500);
  EXPECT_EQ(maxwell->lipschitz(1).value, 0);  // r (1 − β)
  EXPECT_NEAR(maxwell->lipschitz(0.8).value, 200, 1e-9);
  EXPECT_EQ(maxwell->lipschitz(0).value, 1000);
  EXPECT_EQ(elastic->lipschitz(0).value, 0);
  EXPECT_EQ(stable_step(*perzyna, 1), 0.004);  // 4λ/E
  EXPECT_EQ(stable_step(*maxwell, 0), 0.002);
  EXPECT_EQ(stable_step(*elastic, 0), INFINITY);

  // L is G's Lipschitz constant in σ, and attained: far outside the yield set G ≈ −L σ.
  for (const auto* law : {perzyna.get(), von_mises.get(), maxwell.get()})
    for (int dim : {1, 2, 3})
      for (double beta : {0.0, 0.5, 1.0}) {
        const double L = law->lipschitz(beta).value;
        double largest = 0;
        for (int i = 0; i < 50; ++i) {
          SymTensor s, ds;
          for (int j = 0; j < 6; ++j) {
            s[j] = 1e3 * std::sin(1.7 * i + 2.3 * j);
            ds[j] = 1e-2 * std::cos(3.1 * i + 0.7 * j);
          }
          PointState a{.sigma = s, .eps = {}, .beta = beta, .dim = dim}, b = a;
          b.sigma = s + ds;
          const double q = (law->rate(b) - law->rate(a)).norm() / ds.norm();
          EXPECT_LE(q, L * (1 + 1e-6)) << law->describe() << " d = " << dim << " beta = " << beta;
          largest = std::max(largest, q);
        }
        EXPECT_GE(largest, 0.9 * L) << law->describe() << " d = " << dim << " beta = " << beta;
      }
}

TEST(StepStability, ASetUpWhoseStepIsBeyondTheBoundIsRefused) {
  // The reporter's run: k = 0.01 > 4λ/E = 0.004 blew up to a von Mises stress of 3e49.
  const std::string e = error_of([] { block(kPerzyna, 100); });
  EXPECT_NE(e.find("the time step k = 0.01 is unstable for material 'body', perzyna (E = 1000, lambda = 1, sigma_y = 2)"),
            std::string::npos) << e;
  EXPECT_NE(e.find("stable only for k <= 2/L = 0.004, L = E/(2 lambda) = 500"), std::string::npos) << e;
  EXPECT_NE(e.find("--steps 250 or more (--steps 500 for k L <= 1"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_NO_THROW(block(kPerzyna, 250));  // k L = 2

  // Maxwell: L = r (1 − β) at the initial β (β0 = 0.5: L = 500, 2/L = 0.004).
  std::vector<std::string> damaged = kMaxwell;
  damaged.push_back("damage.beta0=0.5");
  const std::string m = error_of([&] { block(damaged, 100); });
  EXPECT_NE(m.find("L = |rate| (1 - beta) = 500 at beta = 0.5"), std::string::npos) << m;
  EXPECT_NE(m.find("Use --steps 500 or more (--steps 1000 for k L <= 1, without overshoot) (stable at every beta)"),
            std::string::npos) << m;  // the steps stable at β = 0, not only at β0
  EXPECT_NO_THROW(block(kMaxwell, 100));  // β0 = 1: stable until β falls below 0.8
}

TEST(StepStability, ARunThatBecomesUnstableStops) {
  // The reporter's second run: k r = 10, unstable once β < 0.8; it reached F = 1e40 and exit 0.
  TimeStepper s(block(kMaxwell, 100).problem);
  const std::string e = error_of([&] {
    while (!s.done()) {
      const StepReport r = s.step();
      ASSERT_LT(r.max_von_mises, 1e6) << "t = " << r.t;  // stopped before the answer is garbage
    }
  });
  EXPECT_NE(e.find("the explicit viscoplastic step is unstable and the run is stopped"), std::string::npos) << e;
  EXPECT_NE(e.find("maxwell-damage (rate = 1000): L = |rate| (1 - beta) ="), std::string::npos) << e;
  EXPECT_NE(e.find("--steps 500 or more (--steps 1000 for k L <= 1, without overshoot) (stable at every beta)"),
            std::string::npos) << e;
  EXPECT_LT(s.state().n, 100);

  // The same with stable steps runs to the end.
  TimeStepper fine(block(kMaxwell, 500).problem);
  while (!fine.done()) ASSERT_TRUE(fine.step().ok);
}

TEST(StepStability, ErrorControlledStepsStayWithinTheBound) {
  // A loose tolerance lets the steps grow to dt_max = T/10, far beyond 4λ/E = 0.004.
  std::vector<std::string> sets = kPerzyna;
  sets.push_back("time.tolerance=100");
  const Case c = block(sets, std::nullopt);
  EXPECT_EQ(c.problem->largest_step(), 0.004);
  EXPECT_NE(c.problem->describe_steps().find("in [1e-06, 0.004]"), std::string::npos) << c.problem->describe_steps();
  TimeStepper s(c.problem);
  double largest = 0;
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok);
    largest = std::max(largest, r.k);
  }
  EXPECT_LE(largest, 0.004 * (1 + 1e-9));
  EXPECT_GT(largest, 0.003);  // the cap, not the estimate, limits the steps

  // dt_min beyond the bound cannot be honoured: refused.
  sets.push_back("time.dt_min=0.005");
  sets.push_back("time.dt_initial=0.01");
  const std::string e = error_of([&] { block(sets, std::nullopt); });
  EXPECT_NE(e.find("dt_min = 0.005 exceeds the largest stable step 0.004 of material 'body'"), std::string::npos) << e;
}

TEST(StepStability, TheHeaderPrintsStepsToSixDigits) {
  // Issue 26 item 22: T/100 with T = 1.3 is 0.013000000000000001 in its shortest round-trip form.
  Case c = block({"time.T=1.3", "time.tolerance=1e-3"}, std::nullopt);
  EXPECT_NE(c.problem->describe_steps().find("k from 0.013 in [1.3e-06, 0.13]"), std::string::npos)
      << c.problem->describe_steps();
  c = block({"time.T=1.3"}, 100);
  EXPECT_EQ(c.problem->describe_steps(), "k = 0.013, N = 100");
}

}  // namespace
}  // namespace vpc
