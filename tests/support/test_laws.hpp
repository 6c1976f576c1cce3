#pragma once
// Test-only contact laws (issue 49): they show that a new law is one class plus one registry line,
// and that the solvers run any law through its block alone, never asking which law it is.
//   "elliptic-coulomb": Coulomb's bound s = μ λ_ν with an elliptic set of tangential forces,
//     C_s = {(λ_1/a_1)² + (λ_2/a_2)² ≤ s²} along the node's tangents (keys mu, axis_1, axis_2;
//     axes 1 and 1 are Coulomb's disc): anisotropic friction by the maximum dissipation principle.
//   "test-adhesive": Signorini with adhesion, a normal law with its own per-node datum: the force
//     may go down to the tension −a_i, a_i = strength |Γ3|_i (lumped like the compliance's k_i; key
//     strength >= 0): (λ_i + a_i) ⟂ (g_i − N_i u) ≥ 0, λ_i + a_i ≥ 0. A node that separates carries
//     exactly −a_i; strength 0 is Signorini.
#include "contact/contact_law.hpp"
#include "contact/friction_law.hpp"

namespace vpc::test {

class EllipticCoulomb final : public FrictionLaw {
 public:
  EllipticCoulomb(double mu, double a1, double a2);
  explicit EllipticCoulomb(FrictionKeys& keys);
  std::string name() const override { return "elliptic-coulomb"; }
  std::string describe() const override;
  double coefficient(const Point&) const override { return mu_; }
  double gauge(const double* l, int t) const override;
  double dual_gauge(const double* d, int t) const override;
  void project(const double* z, int t, double r, double* p) const override;
  void project_derivative(const double* z, int t, double s, double* dp_dz, double* dp_ds) const override;
  bool disc() const override { return false; }
  double axis(int j) const { return j == 0 ? a1_ : a2_; }

 private:
  /// θ ≥ 0 of the projection onto C_r of a z outside it: p_j = z_j A_j / (A_j + θ), A_j = (r a_j)².
  double multiplier(const double* z, int t, double r) const;
  double mu_, a1_, a2_;
};

class AdhesiveSignorini final : public ContactLaw {
 public:
  explicit AdhesiveSignorini(double strength);
  explicit AdhesiveSignorini(LawKeys& keys);
  std::string name() const override { return "test-adhesive"; }
  std::string describe() const override;
  std::string kind() const override { return "adhesive Signorini law"; }
  bool rigid() const override { return true; }
  /// a_i's share of one facet: strength |f| / nodes.
  double lumped(double facet_measure, int nodes) const override { return strength_ * facet_measure / nodes; }
  /// Another law's facets may not meet this one's at a node (the datum would mix two meanings).
  std::string conflict(const ContactLaw& other) const override;
  double dual_lower(double datum) const override { return -datum; }
  double strength() const { return strength_; }

 private:
  double strength_;
};

/// Registers the test-only laws (once; every later call does nothing).
void register_test_laws();

}  // namespace vpc::test
