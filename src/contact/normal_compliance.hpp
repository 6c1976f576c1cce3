#pragma once
// Normal compliance (the paper's reference [4]; SPEC §6): σ_ν = −c (u_ν − g)₊^e, c > 0 a
// pressure per unit of penetration^e, e ≥ 1 (1: the linear law). Lumped at a node as
// λ_i = k_i (N_i u − g_i)₊^{e_i}, k_i = c |Γ3|_i. Linear (e = 1) it is the box QP's
// S + diag(1/k) on the dual and a spring k_i on the primal; with e > 1 it is not linear and
// the dual's Newton solves it.
#include "contact/contact_law.hpp"

namespace vpc {

class NormalComplianceLaw final : public ContactLaw {
 public:
  NormalComplianceLaw(double stiffness, double exponent) : c_(stiffness), e_(exponent) {}
  /// From a case file: stiffness (> 0, required) and exponent (≥ 1, default 1).
  explicit NormalComplianceLaw(LawKeys& keys);
  std::string name() const override { return "normal-compliance"; }
  std::string describe() const override;
  std::string kind() const override { return e_ == 1 ? "linear normal compliance" : "power-law compliance"; }
  bool linear() const override { return e_ == 1; }
  double lumped(double facet_measure, int nodes) const override { return c_ * facet_measure / nodes; }
  std::string conflict(const ContactLaw& other) const override;
  double gap_left(double s0, double lambda, double compliance) const override;
  double force(double d, double compliance) const override;
  double force_slope(double d, double compliance) const override;
  double exponent() const { return e_; }

 private:
  double c_, e_;
};

}  // namespace vpc
