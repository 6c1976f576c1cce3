// Issue 13: contact laws per part (Signorini or normal compliance, linear or a power
// law σ_ν = −c (u_ν − g)₊^e) and obstacles restricted to parts (SPEC §6).
#include "io/case_file.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "../error_of.hpp"
#include "../run_to_end.hpp"

namespace vpc {
namespace {

/// An elastic plane-strain block [0, 2] × [0, 1] clamped on top and pressed down by its
/// weight onto the foundation y = 0 (gap 0) along its bottom, which is two contact
/// parts, "pad_left" (x < 1) and "pad_right" (x > 1), sharing the node (1, 0).
/// `contact` is the [contact] section's body and whatever follows.
Case pads(const std::string& contact) {
  return parse_case(R"toml(
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [8, 4]
[[mesh.part]]
name = "pad_left"
where = "abs(y) < 1e-12 && x < 1"
[[mesh.part]]
name = "pad_right"
where = "abs(y) < 1e-12 && x > 1"
[boundary]
clamped = ["top"]
contact = ["pad_left", "pad_right"]
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[loads]
f0 = ["0", "-50*t"]
[time]
T = 1.0
steps = 2
[contact]
)toml" + contact,
                    "pads.toml", ".", {});
}


/// The penetration u_ν − g of each contact row (ν = (0, −1), g = 0 here).
std::vector<double> penetration(const TimeStepper& s) {
  std::vector<double> d(s.part().n_contact);
  for (const PartContactNode& c : s.contact().nodes) d[c.row] = -s.state().u[2 * c.local_node + 1];
  return d;
}

// λ_i = c |Γ3|_i (u_ν − g)₊^e at every contact node for a power law, after the
// semismooth Newton of solve_compliance_dual.
TEST(ContactLaws, PowerLawHoldsAtEveryNode) {
  const auto s = run_to_end(pads("law = \"normal-compliance\"\nstiffness = 1e5\nexponent = 2.0\n"));
  const std::vector<double> d = penetration(*s);
  int pressed = 0;
  for (const PartContactNode& c : s->contact().nodes) {
    const double lambda = s->state().lambda[c.row];
    EXPECT_NEAR(lambda, 1e5 * c.measure * std::pow(std::max(d[c.row], 0.0), 2), 1e-9 * (1 + lambda)) << c.row;
    pressed += lambda > 0;
  }
  EXPECT_GT(pressed, 3);
  EXPECT_NE(s->contact_method().find("semismooth Newton"), std::string::npos);
}

// c → ∞ recovers the Signorini answer, at the rate of the penetration (λ/c)^{1/e}.
TEST(ContactLaws, StiffPowerLawTendsToSignorini) {
  const auto signorini = run_to_end(pads(""));
  auto force_error = [&](double c) {
    const auto s = run_to_end(pads(fmt::format("law = \"normal-compliance\"\nstiffness = {}\nexponent = 2.0\n", c)));
    return std::abs(s->state().lambda.sum() - signorini->state().lambda.sum()) / signorini->state().lambda.sum();
  };
  const double e4 = force_error(1e4), e8 = force_error(1e8), e12 = force_error(1e12);
  std::printf("  power law e = 2: relative error of the total contact force against Signorini: c = 1e4: %.3e, "
              "1e8: %.3e, 1e12: %.3e\n", e4, e8, e12);
  EXPECT_LT(e8, e4 / 30);
  EXPECT_LT(e12, 1e-3) << e8;
  EXPECT_LT(e12, e8 / 30);  // (λ/c)^{1/2}: a factor 100 for c × 10⁴
}

// A Signorini part beside a compliant one: no penetration on the left and at the shared
// node (a Signorini facet there), λ = c |Γ3|_i (u_ν − g)₊ on the right.
TEST(ContactLaws, EachPartHasItsLaw) {
  const auto s = run_to_end(pads(R"toml(
[[contact.part]]
parts = ["pad_right"]
law = "normal-compliance"
stiffness = 1e3
)toml"));
  const std::vector<double> d = penetration(*s);
  double right_penetration = 0;
  for (const PartContactNode& c : s->contact().nodes) {
    const double x = s->mesh().node(c.local_node)[0], lambda = s->state().lambda[c.row];
    if (x <= 1) {
      EXPECT_EQ(c.datum, 0.0) << x;
      EXPECT_LE(d[c.row], 1e-12) << x;
    } else {
      EXPECT_NEAR(c.datum, 1e3 * c.measure, 1e-9) << x;
      EXPECT_NEAR(lambda, c.datum * std::max(d[c.row], 0.0), 1e-9 * (1 + lambda)) << x;
      right_penetration = std::max(right_penetration, d[c.row]);
    }
  }
  EXPECT_GT(right_penetration, 1e-4);
  // Signorini named on every part is the default law, bit for bit.
  const auto named = run_to_end(pads("[[contact.part]]\nparts = [\"pad_left\", \"pad_right\"]\nlaw = \"signorini\"\n"));
  const auto plain = run_to_end(pads(""));
  EXPECT_EQ(named->state().u, plain->state().u);
  EXPECT_EQ(named->state().lambda, plain->state().lambda);
}

// An obstacle acts on its parts only: the left pad sees the far plane, the right pad
// the near one, the shared node the nearer of both; each obstacle's force is that of its nodes.
TEST(ContactLaws, ObstaclesActOnTheirParts) {
  const Case c = pads(R"toml(
[[obstacle]]
name = "far"
shape = "plane"
point = [0.0, -0.05]
normal = [0.0, 1.0]
parts = ["pad_left"]
[[obstacle]]
name = "near"
shape = "plane"
point = [0.0, -0.001]
normal = [0.0, 1.0]
parts = ["pad_right"]
)toml");
  TimeStepper s(c.problem, c.solvers);
  for (const PartContactNode& node : s.contact().nodes) {
    const double x = s.mesh().node(node.local_node)[0];
    EXPECT_NEAR(node.gap, x < 1 ? 0.05 : 0.001, 1e-15) << x;
  }
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok);
    double far = 0, near = 0;
    for (const PartContactNode& node : s.contact().nodes)
      (s.mesh().node(node.local_node)[0] < 1 ? far : near) += s.state().lambda[node.row];
    ASSERT_EQ(r.obstacle_force.size(), 2u);
    EXPECT_NEAR(r.obstacle_force[0], far, 1e-12 * (1 + far));
    EXPECT_NEAR(r.obstacle_force[1], near, 1e-12 * (1 + near));
    EXPECT_GT(near, 0.0);
  }
}

TEST(ContactLaws, ErrorsAreLocated) {
  auto error = [](const std::string& contact) { return error_of([&] { pads(contact); }); };
  std::string m = error("[[contact.part]]\nparts = [\"top\"]\nlaw = \"signorini\"\n");
  EXPECT_NE(m.find("contact.part[0].parts: 'top' is not a contact part"), std::string::npos) << m;
  m = error("[[contact.part]]\nparts = [\"pad_left\"]\n[[contact.part]]\nparts = [\"pad_left\"]\n");
  EXPECT_NE(m.find("contact part 'pad_left' has a law already"), std::string::npos) << m;
  m = error("law = \"normal-compliance\"\nstiffness = 10.0\nexponent = 0.5\n");
  EXPECT_NE(m.find("contact.exponent: expected an exponent >= 1, got 0.5"), std::string::npos) << m;
  m = error("exponent = 2.0\n");
  EXPECT_NE(m.find("exponent belongs to law = \"normal-compliance\""), std::string::npos) << m;
  m = error(R"toml(law = "normal-compliance"
stiffness = 10.0
[[contact.part]]
parts = ["pad_right"]
law = "normal-compliance"
stiffness = 10.0
exponent = 3.0
)toml");
  EXPECT_NE(m.find("contact node"), std::string::npos) << m;
  EXPECT_NE(m.find("(1, 0, 0)"), std::string::npos) << m;
  EXPECT_NE(m.find("exponents 1 and 3"), std::string::npos) << m;
  m = error("[[obstacle]]\nshape = \"plane\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\nparts = [\"top\"]\n");
  EXPECT_NE(m.find("obstacle[0].parts: 'top' is not a contact part"), std::string::npos) << m;
}

}  // namespace
}  // namespace vpc
