// Issue 27: the contact laws as objects (contact/): the registry by name, each law reading
// its own keys, and each built-in law's functions against their formulas.
#include "contact/normal_compliance.hpp"
#include "contact/registry.hpp"
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "../error_of.hpp"

namespace vpc {
namespace {

/// A law's keys from a map, located as "t: key".
class MapKeys final : public LawKeys {
 public:
  explicit MapKeys(std::map<std::string, double> values) : values_(std::move(values)) {}
  bool has(const std::string& key) override { return values_.count(key) > 0; }
  double number(const std::string& key) override {
    if (!has(key)) fail("t: missing key '{}'", key);
    return values_.at(key);
  }
  double number(const std::string& key, double fallback) override { return has(key) ? number(key) : fallback; }
  std::string where(const std::string& key) override { return "t: " + key; }

 private:
  std::map<std::string, double> values_;
};

std::shared_ptr<const ContactLaw> law(const std::string& name, std::map<std::string, double> values) {
  MapKeys keys(std::move(values));
  return make_contact_law(name, keys);
}

TEST(ContactLawRegistry, NamesAndErrors) {
  const auto names = contact_law_names();
  ASSERT_GE(names.size(), 2u);
  EXPECT_EQ(names[0], "signorini");
  EXPECT_EQ(names[1], "normal-compliance");
  std::string m = error_of([] { law("penalty", {}); });
  EXPECT_NE(m.find("unknown contact law 'penalty'; expected one of: signorini, normal-compliance"), std::string::npos) << m;
  m = error_of([] { law("signorini", {{"exponent", 2}}); });
  EXPECT_NE(m.find("t: exponent: exponent belongs to law = \"normal-compliance\""), std::string::npos) << m;
  m = error_of([] { law("normal-compliance", {}); });
  EXPECT_NE(m.find("missing key 'stiffness'"), std::string::npos) << m;
  m = error_of([] { law("normal-compliance", {{"stiffness", -1}}); });
  EXPECT_NE(m.find("t: stiffness: expected a stiffness > 0, got -1"), std::string::npos) << m;
  m = error_of([] { law("normal-compliance", {{"stiffness", 1}, {"exponent", 0.5}}); });
  EXPECT_NE(m.find("t: exponent: expected an exponent >= 1, got 0.5"), std::string::npos) << m;
  EXPECT_THROW(register_contact_law("signorini", nullptr), Error);
}

TEST(ContactLaw, Signorini) {
  const auto s = law("signorini", {});
  EXPECT_EQ(s->name(), "signorini");
  EXPECT_EQ(s->describe(), "Signorini");
  EXPECT_TRUE(s->rigid());
  EXPECT_EQ(s->block_size(3), 1);
  EXPECT_EQ(s->lumped(2.0, 2), 0.0);
  EXPECT_EQ(s->gap_left(0.25, 7.0, 0.0), 0.25);  // λ ⟂ g − N u: nothing added
  EXPECT_EQ(s->dual_lower(1.0), 0.0);
  EXPECT_EQ(s->compliance(1.0), 0.0);
  EXPECT_TRUE(std::isinf(s->dual_upper()));
  EXPECT_TRUE(signorini_law()->rigid());
}

// λ = k d₊ (e = 1): a spring of compliance 1/k, δ(λ) = λ/k; lumped c |f| / nodes.
TEST(ContactLaw, LinearNormalCompliance) {
  const auto l = law("normal-compliance", {{"stiffness", 100}});
  EXPECT_FALSE(l->rigid());
  EXPECT_TRUE(l->linear());
  EXPECT_EQ(l->describe(), "normal compliance c = 100");
  EXPECT_EQ(l->kind(), "linear normal compliance");
  EXPECT_DOUBLE_EQ(l->lumped(0.5, 2), 25.0);
  const double compliance = 0.04;  // k = 25
  EXPECT_EQ(l->compliance(25.0), compliance);  // the datum is k_i
  EXPECT_EQ(l->dual_lower(25.0), 0.0);
  EXPECT_DOUBLE_EQ(l->force(0.2, compliance), 5.0);
  EXPECT_EQ(l->force(-0.2, compliance), 0.0);
  EXPECT_DOUBLE_EQ(l->force_slope(0.2, compliance), 25.0);
  EXPECT_DOUBLE_EQ(l->gap_left(-0.2, 5.0, compliance), 0.0);  // at the law: the gap left is 0
  EXPECT_EQ(l->spring_compliance(compliance), compliance);
  EXPECT_EQ(l->conflict(*law("normal-compliance", {{"stiffness", 5}})), "");  // k_i sums both shares
}

// λ = k d₊^e: δ(λ) = (λ/k)^{1/e}; nodes of different exponents cannot share a node.
TEST(ContactLaw, PowerLawCompliance) {
  const auto l = law("normal-compliance", {{"stiffness", 10}, {"exponent", 2}});
  EXPECT_FALSE(l->linear());
  EXPECT_EQ(l->describe(), "normal compliance c = 10, e = 2");
  EXPECT_EQ(l->kind(), "power-law compliance");
  const double compliance = 0.1;  // k = 10
  EXPECT_DOUBLE_EQ(l->force(0.3, compliance), 10 * 0.09);
  EXPECT_DOUBLE_EQ(l->force_slope(0.3, compliance), 10 * 2 * 0.3);
  EXPECT_EQ(l->force_slope(0.0, compliance), 0.0);
  EXPECT_NEAR(l->gap_left(-0.3, 0.9, compliance), 0.0, 1e-15);
  EXPECT_NEAR(l->gap_left(0.25, -1.0, compliance), 0.25, 1e-15);  // a negative force: (λ/k)₊^{1/e} = 0
  const std::string why = l->conflict(*law("normal-compliance", {{"stiffness", 10}}));
  EXPECT_NE(why.find("exponents 2 and 1"), std::string::npos) << why;
  EXPECT_NE(l->conflict(*signorini_law()), "");
}

}  // namespace
}  // namespace vpc
