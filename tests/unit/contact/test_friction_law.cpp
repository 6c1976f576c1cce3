// Issue 28: friction laws (SPEC §7) read from [contact] and [[contact.part]]: Coulomb's μ and
// Tresca's bound as numbers or formulas, the block of unknowns they make, inheritance by the
// part tables, and the located errors of the ways users get them wrong.
#include "../../case_text.hpp"
#include "contact/friction_law.hpp"
#include "core/error.hpp"
#include "io/case_file.hpp"

#include <gtest/gtest.h>

namespace vpc {
namespace {

const char* kCase = R"(
[case]
name = "shear"
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [4, 2]
[[mesh.part]]
name = "left-half"
where = "abs(y) < 1e-9 && x < 1 + 1e-9"
[boundary]
contact = ["bottom"]
[[boundary.displacement]]
parts = ["top"]
ux = "0.01*t"
uy = "-0.01*t"
[elasticity]
kind = "plane-strain"
E = 100.0
nu = 0.3
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[contact]
gap = 0.0
friction = "coulomb"
mu = 0.3
[time]
T = 1.0
steps = 2
)";

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  return test::case_error(text, "f.toml", sets);
}

TEST(FrictionLaw, CoulombAndTrescaFromTheCaseFile) {
  Case c = parse_case(kCase, "f.toml", ".");
  const ContactSpec& contact = c.problem->contact;
  ASSERT_NE(contact.friction, nullptr);
  EXPECT_EQ(contact.friction->name(), "coulomb");
  EXPECT_EQ(contact.friction->describe(), "Coulomb friction mu = 0.3");
  EXPECT_DOUBLE_EQ(contact.friction->coefficient({1, 0, 0}), 0.3);
  EXPECT_DOUBLE_EQ(contact.friction->bound({1, 0, 0}, 0.5), 0.0);
  EXPECT_TRUE(contact.frictional());
  EXPECT_EQ(contact.block_size(2), 2);
  EXPECT_EQ(contact.block_size(3), 3);

  const std::string tresca_text =
      test::replaced(kCase, "friction = \"coulomb\"\nmu = 0.3", "friction = \"tresca\"\nfriction_bound = \"2*x + t\"");
  c = parse_case(tresca_text, "f.toml", ".");
  // --set of another friction law drops the old law's keys (as a change of material law does).
  const Case switched = parse_case(kCase, "f.toml", ".", {.sets = {"contact.friction=\"tresca\"", "contact.friction_bound=2"}});
  EXPECT_EQ(switched.problem->contact.friction->name(), "tresca");
  EXPECT_EQ(parse_case(kCase, "f.toml", ".", {.sets = {"contact.friction=\"none\""}}).problem->contact.friction, nullptr);
  const FrictionLaw& tresca = *c.problem->contact.friction;
  EXPECT_EQ(tresca.name(), "tresca");
  EXPECT_TRUE(tresca.bound_moves());
  EXPECT_DOUBLE_EQ(tresca.bound({1.5, 0, 0}, 0.25), 3.25);
  EXPECT_DOUBLE_EQ(tresca.coefficient({1.5, 0, 0}), 0.0);
}

TEST(FrictionLaw, PartTablesInheritOrOverride) {
  // left-half is not a contact part of its own: make it one.
  const std::string text =
      test::replaced(kCase, "contact = [\"bottom\"]", "contact = [\"bottom\", \"left-half\"]") + R"(
[[contact.part]]
parts = ["left-half"]
mu = 0.5
friction = "coulomb"
)";
  const Case c = parse_case(text, "f.toml", ".");
  const auto frictions = c.problem->contact.frictions();
  ASSERT_EQ(frictions.size(), 2u);
  EXPECT_DOUBLE_EQ(frictions[0]->coefficient({}), 0.3);
  EXPECT_DOUBLE_EQ(frictions[1]->coefficient({}), 0.5);

  const std::string inherit = test::replaced(text, "mu = 0.5\nfriction = \"coulomb\"\n", "");
  EXPECT_DOUBLE_EQ(parse_case(inherit, "f.toml", ".").problem->contact.frictions()[1]->coefficient({}), 0.3);

  const std::string none = test::replaced(text, "mu = 0.5\nfriction = \"coulomb\"\n", "friction = \"none\"\n");
  const Case n = parse_case(none, "f.toml", ".");
  EXPECT_EQ(n.problem->contact.frictions()[1], nullptr);
  EXPECT_TRUE(n.problem->contact.frictional());  // [contact]'s Coulomb on the other parts
}

TEST(FrictionLaw, BadInputsAreLocatedErrors) {
  auto has = [](const std::string& m, const std::string& part) {
    EXPECT_NE(m.find(part), std::string::npos) << m;
  };
  has(error_of(kCase, {"contact.mu=-0.1"}), "expected a friction coefficient mu >= 0, got -0.1");
  has(error_of(kCase, {"contact.friction=\"colomb\""}), "unknown value 'colomb'; expected one of: none, coulomb, tresca");
  has(error_of(kCase, {"contact.friction=\"tresca\""}), "missing key friction_bound (a friction bound (a traction)");
  has(error_of(test::replaced(kCase, "\"coulomb\"", "\"tresca\"")),
      "f.toml:29:6: contact.mu: mu does not belong to friction = \"tresca\"");
  has(error_of(kCase, {"contact.mu=\"0.3*t\""}), "Available variables: x, y, z");  // μ is a function of x only
  has(error_of(test::replaced(kCase, "friction = \"coulomb\"\n", "")),
      "f.toml:28:6: contact.mu: mu needs friction = \"coulomb\" in the same table");
  has(error_of(test::replaced(kCase, "mu = 0.3\n", "")), "missing key mu (a friction coefficient mu: a number or a formula)");
}

TEST(FrictionLaw, RegistryNamesAndDirectConstruction) {
  const auto names = friction_law_names();
  ASSERT_GE(names.size(), 3u);
  EXPECT_EQ(names[0], "none");
  EXPECT_EQ(names[1], "coulomb");
  EXPECT_EQ(names[2], "tresca");
  EXPECT_THROW(register_friction_law("coulomb", nullptr), Error);
  EXPECT_THROW(CoulombFriction(-1.0), Error);
  EXPECT_THROW(TrescaFriction(std::nan("")), Error);
  EXPECT_DOUBLE_EQ(TrescaFriction(2.0).bound({}, 7), 2.0);
}

}  // namespace
}  // namespace vpc
