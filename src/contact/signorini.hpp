#pragma once
// Signorini's conditions (the paper's (2.8)): u_ν ≤ g, σ_ν ≤ 0, σ_ν (u_ν − g) = 0 — the
// rigid law: no parameter, λ_i ⟂ g − N_i u ≥ 0.
#include "contact/contact_law.hpp"

namespace vpc {

class SignoriniLaw final : public ContactLaw {
 public:
  SignoriniLaw() = default;
  /// From a case file: no keys (a compliance key here is a located error).
  explicit SignoriniLaw(LawKeys& keys);
  std::string name() const override { return "signorini"; }
  std::string describe() const override { return "Signorini"; }
  std::string kind() const override { return "Signorini"; }
  bool rigid() const override { return true; }
};

}  // namespace vpc
