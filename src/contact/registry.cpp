// The registry: one line per law maps its name to its class.
#include "contact/registry.hpp"

#include "contact/normal_compliance.hpp"
#include "contact/signorini.hpp"
#include "core/error.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <utility>

namespace vpc {

namespace {

template <typename T>
ContactLawFactory entry() {
  return [](LawKeys& keys) -> std::shared_ptr<const ContactLaw> { return std::make_shared<const T>(keys); };
}

/// In registration order (the order of the names in messages).
std::vector<std::pair<std::string, ContactLawFactory>>& table() {
  static std::vector<std::pair<std::string, ContactLawFactory>> t = {
      {"signorini", entry<SignoriniLaw>()},
      {"normal-compliance", entry<NormalComplianceLaw>()},
  };
  return t;
}

}  // namespace

std::vector<std::string> compliance_keys() { return {"stiffness", "exponent"}; }

SignoriniLaw::SignoriniLaw(LawKeys& keys) {
  for (const std::string& key : compliance_keys())
    if (keys.has(key)) fail("{}: {} belongs to law = \"normal-compliance\" (the law here is Signorini)", keys.where(key), key);
}

std::shared_ptr<const ContactLaw> signorini_law() {
  static const auto law = std::make_shared<const SignoriniLaw>();
  return law;
}

bool register_contact_law(const std::string& name, ContactLawFactory make) {
  auto& t = table();
  require(std::none_of(t.begin(), t.end(), [&](const auto& e) { return e.first == name; }),
          "internal: the contact law '{}' is registered twice", name);
  t.emplace_back(name, std::move(make));
  return true;
}

std::vector<std::string> contact_law_names() {
  std::vector<std::string> names;
  for (const auto& [name, make] : table()) names.push_back(name);
  return names;
}

std::shared_ptr<const ContactLaw> make_contact_law(const std::string& name, LawKeys& keys) {
  for (const auto& [n, make] : table())
    if (n == name) return make(keys);
  fail("unknown contact law '{}'; expected one of: {}", name, fmt::join(contact_law_names(), ", "));
}

}  // namespace vpc
