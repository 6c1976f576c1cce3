#pragma once
// Contact laws by name, like the material laws (material/registry.cpp): [contact] law and
// [[contact.part]] law name one, and the law reads its own keys. A new law is one class and
// one register_contact_law line (docs/architecture.md, "Adding a contact law").
#include "contact/contact_law.hpp"

#include <functional>
#include <vector>

namespace vpc {

using ContactLawFactory = std::function<std::shared_ptr<const ContactLaw>(LawKeys&)>;

/// Adds a law under `name` (after the built-in ones, in the order of the calls); a name
/// registered already is an internal error. Returns true, for a static initializer.
bool register_contact_law(const std::string& name, ContactLawFactory make);
/// The registered names: "signorini", "normal-compliance", then the added ones.
std::vector<std::string> contact_law_names();
/// The keys of the built-in compliance law ("stiffness", "exponent"): a table whose law is
/// Signorini, or that names no law, may not have them.
std::vector<std::string> compliance_keys();
/// The law `name` with its keys; throws vpc::Error listing the names for an unknown one.
std::shared_ptr<const ContactLaw> make_contact_law(const std::string& name, LawKeys& keys);

}  // namespace vpc
