// Issue 27: a contact law the library does not know, in this one file plus its one
// registry line (register_contact_law below): a bilinear, stiffening normal compliance
//   λ = k d₊                     for d = u_ν − g ≤ d0 (the knee),
//   λ = k d0 + r k (d − d0)      beyond,                      k = c |Γ3|_i,
// not linear (ContactLaw::linear): the dual ("active-set") solves it with its Newton
// (solve_compliance_dual), the primal refuses it. A 1D bar run end to end from a case file
// meets the hand value, and the solvers' residuals are those of the law.
#include "contact/registry.hpp"
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../error_of.hpp"
#include "../scheme/bar_case.hpp"

namespace vpc {
namespace {

class BilinearCompliance final : public ContactLaw {
 public:
  explicit BilinearCompliance(LawKeys& keys)
      : c_(keys.number("stiffness")), knee_(keys.number("knee")), ratio_(keys.number("ratio", 2.0)) {
    if (!(c_ > 0 && knee_ > 0 && ratio_ > 0))
      fail("{}: expected stiffness, knee and ratio > 0, got {}, {}, {}", keys.where("stiffness"), c_, knee_, ratio_);
  }
  std::string name() const override { return "bilinear"; }
  std::string describe() const override { return fmt::format("bilinear compliance c = {}, knee {}", c_, knee_); }
  std::string kind() const override { return "bilinear compliance"; }
  bool linear() const override { return false; }
  double lumped(double facet_measure, int nodes) const override { return c_ * facet_measure / nodes; }
  std::string conflict(const ContactLaw& other) const override {
    const auto* o = dynamic_cast<const BilinearCompliance*>(&other);
    return o && o->knee_ == knee_ && o->ratio_ == ratio_ ? "" : "laws differ; they cannot share a node";
  }
  // δ(λ), the inverse of the force law, added to the gap left.
  double gap_left(double s0, double lambda, double compliance) const override {
    const double l = std::max(lambda, 0.0), l_knee = knee_ / compliance;
    return s0 + (l <= l_knee ? l * compliance : knee_ + (l - l_knee) * compliance / ratio_);
  }
  double force(double d, double compliance) const override {
    const double pen = std::max(d, 0.0), k = 1 / compliance;
    return pen <= knee_ ? k * pen : k * knee_ + ratio_ * k * (pen - knee_);
  }
  double force_slope(double d, double compliance) const override {
    return d <= 0 ? 0.0 : (d <= knee_ ? 1 : ratio_) / compliance;
  }

 private:
  double c_, knee_, ratio_;
};

// The registry line.
const bool registered = register_contact_law(
    "bilinear", [](LawKeys& keys) { return std::make_shared<const BilinearCompliance>(keys); });

/// The contact-law tests' bar (scheme/bar_case.hpp: [0, 1], E = 1, clamped at x = 0, pushed by
/// f0 = 1) made elastic, against the obstacle at x = 1 + g, g = 0.3: alone the tip would move by
/// 1/2 (P1 is exact at the nodes in 1D). With the tip force λ, u(1) = 1/2 − λ, so the
/// penetration is d = 0.2 − λ.
Case bar(const std::string& law, const std::string& contact_solver = "auto") {
  return parse_case(test::bar_text("[contact]\ngap = 0.3\n" + law), "bilinear.toml", ".",
                    {.sets = {"viscoplasticity.law=\"elastic\"", "solver.contact=\"" + contact_solver + "\""}});
}

TEST(BilinearContactLaw, IsRegisteredByItsLine) {
  ASSERT_TRUE(registered);
  const auto names = contact_law_names();
  EXPECT_EQ(names.front(), "signorini");
  EXPECT_NE(std::ranges::find(names, "bilinear"), names.end());
  const std::string msg = error_of([] { bar("law = \"bilinar\"\n"); });
  EXPECT_NE(msg.find("bilinear"), std::string::npos) << msg;  // the unknown name lists the registered ones
}

// Beyond the knee d0 = 0.05 with k = 1, r = 3: λ = 0.05 + 3 (d − 0.05) and d = 0.2 − λ give
// λ = 0.125, d = 0.075; below it (d0 = 0.5, all on the first branch) λ = d = 0.1.
TEST(BilinearContactLaw, ABarMeetsTheHandValue) {
  for (const auto& [knee, lambda] : {std::pair{0.05, 0.125}, std::pair{0.5, 0.1}}) {
    SCOPED_TRACE(knee);
    const Case c = bar(fmt::format("law = \"bilinear\"\nstiffness = 1.0\nknee = {}\nratio = 3.0\n", knee));
    TimeStepper s(c.problem, c.solvers);
    EXPECT_EQ(s.contact_solver(), "active-set");  // auto: only the dual solves a nonlinear law
    while (!s.done()) {
      const StepReport r = s.step();
      ASSERT_TRUE(r.ok);
      EXPECT_LE(r.contact.residuals.max(), 1e-12);
    }
    EXPECT_NEAR(s.state().lambda[0], lambda, 1e-12);
    EXPECT_NEAR(s.state().u[8], 0.5 - lambda, 1e-12);
    // The residuals' gap left s = g − u(1) + δ(λ) is 0 at the answer, not at a wrong λ.
    const ContactLaw& law = *c.problem->contact.law;
    const double s0 = 0.3 - s.state().u[8];
    EXPECT_NEAR(law.gap_left(s0, lambda, 1.0), 0.0, 1e-12);
    EXPECT_GT(std::abs(law.gap_left(s0, 1.01 * lambda, 1.0)), 1e-4);
  }
  const std::string msg = error_of([] {
    const Case c = bar("law = \"bilinear\"\nstiffness = 1.0\nknee = 0.05\n", "primal-active-set");
    TimeStepper s(c.problem, c.solvers);
  });
  EXPECT_NE(msg.find("a bilinear compliance needs 'active-set'"), std::string::npos) << msg;
  EXPECT_NE(error_of([] { bar("law = \"bilinear\"\nstiffness = 1.0\n"); }).find("missing key 'contact.knee'"),
            std::string::npos);
}

}  // namespace
}  // namespace vpc
