// Issue 49: a normal law with its own per-node datum. The test-only adhesive law
// (tests/support/test_laws.hpp): its datum a_i = strength |Γ3|_i lumped from the facets like the
// compliance's k_i, its dual bound −a_i, its key read and checked by the law (a located error).
#include "test_laws.hpp"

#include "../case_text.hpp"
#include "contact/normal_compliance.hpp"
#include "contact/registry.hpp"
#include "problem/contact_rows.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/compliance_dual.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

namespace vpc {
namespace {

const char* const kBlock = R"toml([case]
name = "glued"

[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [1.0, 0.5]
cells = [4, 2]

[boundary]
symmetry = ["left"]
contact = ["bottom", "right"]

[[boundary.displacement]]
parts = ["top"]
uy = "0.01*t"

[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3

[viscoplasticity]
law = "elastic"

[damage]
source = "zero"

[contact]
gap = 0.0
{}

[time]
T = 1.0
steps = 1
)toml";

std::string block(const std::string& contact) { return fmt::format(fmt::runtime(kBlock), contact); }

TEST(AdhesiveLaw, IsRegisteredAndRigidWithALowerBoundAtItsDatum) {
  test::register_test_laws();
  test::register_test_laws();  // once: a second call does nothing
  const auto names = contact_law_names();
  EXPECT_EQ(std::count(names.begin(), names.end(), "test-adhesive"), 1);
  const test::AdhesiveSignorini law(2.5);
  EXPECT_TRUE(law.rigid());
  EXPECT_TRUE(law.linear());
  EXPECT_EQ(law.describe(), "adhesive Signorini, strength = 2.5");
  EXPECT_EQ(law.lumped(0.5, 2), 0.625);       // strength |f| / nodes
  EXPECT_EQ(law.dual_lower(0.625), -0.625);   // λ_i ≥ −a_i
  EXPECT_EQ(law.dual_lower(0.0), 0.0);        // debonded: Signorini's λ ≥ 0
  EXPECT_EQ(law.compliance(0.625), 0.0);      // rigid: no spring
  EXPECT_EQ(law.gap_left(0.25, -0.5, 0.0), 0.25);
  EXPECT_EQ(law.conflict(test::AdhesiveSignorini(1.0)), "");
  EXPECT_NE(law.conflict(*signorini_law()), "");
}

// a_i = strength × the node's tributary measure on Γ3 (its facets' shares summed), on every row.
TEST(AdhesiveLaw, ItsDatumIsTheStrengthLumpedAtTheNode) {
  test::register_test_laws();
  const Case c = parse_case(block("law = \"test-adhesive\"\nstrength = 3.0"), "glued.toml", ".");
  ASSERT_TRUE(c.contact_rows);
  const std::vector<double> measure = tributary_measures(c.problem->mesh, c.problem->contact.parts);
  int rows = 0;
  for (const ContactRow& row : *c.contact_rows) {
    ++rows;
    EXPECT_GT(measure[static_cast<std::size_t>(row.node)], 0);
    EXPECT_NEAR(row.datum, 3.0 * measure[static_cast<std::size_t>(row.node)], 1e-15) << "node " << row.node;
    EXPECT_EQ(c.problem->contact.laws()[static_cast<std::size_t>(row.law)]->name(), "test-adhesive");
  }
  EXPECT_EQ(rows, 5 + 3 - 1);  // the bottom's nodes and the right's, the corner once
  // Signorini's datum is nothing.
  const Case s = parse_case(block("law = \"signorini\""), "glued.toml", ".");
  for (const ContactRow& row : *s.contact_rows) EXPECT_EQ(row.datum, 0.0);
}

TEST(AdhesiveLaw, ABadStrengthIsALocatedError) {
  test::register_test_laws();
  std::string m = test::case_error(block("law = \"test-adhesive\"\nstrength = -1.0"), "glued.toml");
  EXPECT_NE(m.find("glued.toml:"), std::string::npos) << m;
  EXPECT_NE(m.find("contact.strength: expected a strength >= 0 (an adhesive traction), got -1"), std::string::npos) << m;
  m = test::case_error(block("law = \"test-adhesive\""), "glued.toml");
  EXPECT_NE(m.find("strength"), std::string::npos) << m;
  m = test::case_error(block("law = \"test-adhesive\"\nstrength = 1.0\nstiffness = 3.0"), "glued.toml");
  EXPECT_NE(m.find("stiffness"), std::string::npos) << m;  // not its key
}

// An adhesive part and a Signorini part that share a node: refused whichever facet comes first
// (ContactLaw::conflict is asked both ways; Signorini's own answer is empty).
TEST(AdhesiveLaw, ItCannotShareANodeWithAnotherRigidLaw) {
  test::register_test_laws();
  for (const auto& [main, part] : {std::pair{"law = \"test-adhesive\"\nstrength = 1.0", "law = \"signorini\""},
                                   std::pair{"law = \"signorini\"", "law = \"test-adhesive\"\nstrength = 1.0"}}) {
    const std::string m = test::case_error(
        block(fmt::format("{}\n\n[[contact.part]]\nparts = [\"right\"]\n{}", main, part)), "glued.toml");
    EXPECT_NE(m.find("lies on contact parts whose laws are an adhesive Signorini law and a Signorini"), std::string::npos)
        << m;
  }
}

// The dual's Newton for a nonlinear law elsewhere (solve_compliance_dual) takes an adhesive row's
// bound −a_i: on rows of the adhesive law alone it is the box QP over λ ≥ −a, and with a power-law
// row beside them the adhesive rows still hold λ_i ≥ −a_i ⟂ the gap left.
TEST(AdhesiveLaw, TheDualsNewtonTakesItsLowerBound) {
  const test::AdhesiveSignorini glue(1.0);
  const NormalComplianceLaw power(1.0, 2.0);
  Eigen::MatrixXd S(3, 3);
  S << 2, -1, 0, -1, 2, -1, 0, -1, 2;
  const Vector b = (Vector(3) << -3, 0.5, 1).finished();  // row 0 pulled apart, rows 1 and 2 pressed
  const Vector lower = (Vector(3) << -0.5, -0.5, 0).finished();
  Vector box = Vector::Zero(3);
  DenseBoxQpOperator H(S);
  ASSERT_TRUE(solve_box_qp(H, b, lower, Vector::Constant(3, std::numeric_limits<double>::infinity()), box).converged);
  Vector newton = Vector::Zero(3);
  const std::vector<const ContactLaw*> glued = {&glue, &glue, &glue};
  ASSERT_TRUE(solve_compliance_dual(S, b, glued, Vector::Zero(3), newton, kComplianceDualIterations, lower).converged);
  EXPECT_EQ(box[0], -0.5);  // let go: exactly −a
  EXPECT_EQ(newton[0], -0.5);
  EXPECT_NEAR((newton - box).cwiseAbs().maxCoeff(), 0.0, 1e-13);
  // Row 2 a power law λ = k d₊², k = 1/compliance = 4.
  const std::vector<const ContactLaw*> mixed = {&glue, &glue, &power};
  Vector lambda = Vector::Zero(3);
  ASSERT_TRUE(solve_compliance_dual(S, b, mixed, (Vector(3) << 0, 0, 0.25).finished(), lambda, kComplianceDualIterations,
                                    lower).converged);
  const Vector d = b - S * lambda;  // the penetration
  for (int i = 0; i < 2; ++i) {
    EXPECT_GE(lambda[i] - lower[i], -1e-14) << i;
    EXPECT_LE(d[i], 1e-13) << i;
    EXPECT_NEAR((lambda[i] - lower[i]) * d[i], 0.0, 1e-13) << i;
  }
  EXPECT_EQ(lambda[0], -0.5);
  EXPECT_NEAR(lambda[2], 4 * std::pow(std::max(d[2], 0.0), 2), 1e-12);
}

}  // namespace
}  // namespace vpc
