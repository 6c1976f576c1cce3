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

/// "worn-coulomb": Coulomb friction (key mu) that keeps Archard's worn depth as per-node state
/// (contact/surface_state.hpp), with no effect on the step: "worn" += wear λ_ν / |Γ3|_i |Δ_i| after each
/// step (key wear_factor ≥ 0, default 1), ∫_Γ3 worn in history.csv as worn_volume, and "slip_path" += |Δ_i|
/// (2 numbers per node: the path and the number of updates, one per accepted step), which must equal friction's own
/// State::slip. It shows that a law's state reaches checkpoints, rollback, VTU, Python and history.csv
/// with no code outside the law. With gap_share > 0 (default 0) the worn depth opens the gap of the
/// next step, u_ν ≤ g + gap_share ω (SPEC §9's lagged wear), showing state that acts on the step.
class WornCoulomb final : public FrictionLaw {
 public:
  WornCoulomb(double mu, double wear, double gap_share = 0);
  explicit WornCoulomb(FrictionKeys& keys);
  std::string name() const override { return "worn-coulomb"; }
  std::string describe() const override;
  double coefficient(const Point&) const override { return mu_; }
  std::vector<SurfaceVariable> surface_state() const override;
  SurfaceUpdate update_surface(const SurfaceNode& node, std::span<double* const> values) const override;
  double gap_shift(std::span<const double* const> values) const override { return gap_share_ * *values[0]; }

 private:
  double mu_, wear_, gap_share_;
};

/// "sized-coulomb": Coulomb friction (key mu) valid for contact nodes of tributary measure |Γ3|_i ≥ min_measure
/// only (key min_measure > 0), as a law calibrated at one element size would be: a step that ends with such
/// a node in contact (λ_ν > 0) below it is rejected (step_share = min_measure / |Γ3|_i, which no shorter step
/// lowers). It makes a step fail on a mesh refined at the contact and succeed on the mesh before: the
/// adaptive run's undo of an adaptation (issue 51). Its one state variable counts the accepted updates.
class SizedCoulomb final : public FrictionLaw {
 public:
  SizedCoulomb(double mu, double min_measure);
  explicit SizedCoulomb(FrictionKeys& keys);
  std::string name() const override { return "sized-coulomb"; }
  std::string describe() const override;
  double coefficient(const Point&) const override { return mu_; }
  std::vector<SurfaceVariable> surface_state() const override;
  SurfaceUpdate update_surface(const SurfaceNode& node, std::span<double* const> values) const override;
  LawText step_limit() const override;

 private:
  double mu_, min_measure_;
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
