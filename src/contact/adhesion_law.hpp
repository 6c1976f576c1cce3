#pragma once
// Adhesion (SPEC §9; Frémond's model as analysed by Chau, Fernández, Shillor and Sofonea 2003 and in
// Sofonea–Han–Shillor 2006): a bonding field α ∈ [0, 1] per contact node (1 bonded, 0 debonded) glues
// the surfaces. A node separated by s = g − u_ν > 0 is pulled back by the traction γ_ν α² R(s),
// R(s) = min(s, L) (beyond the bond length L the pull stays γ_ν α² L; the bond does not break there,
// it weakens through α), and the bond weakens while stretched:
//   b α̇ = −(α γ_ν R(s)² − ε_a)₊,  α(0) = α_0,
// b > 0 the bond viscosity (J s/m²), ε_a ≥ 0 the adhesion energy (J/m²) below which the bond holds.
// α never grows. Bonding is defined only where the initial gap is 0 (α_0 > 0 elsewhere is refused).
//
// Lagged as the scheme lags the damage source (SPEC §2): step n first carries α over the step with
// the separation of t_{n−1} frozen, where the rate law is linear in α and integrates exactly,
//   α_n = α_{n−1} if c α_{n−1} ≤ ε_a, else ε_a/c + (α_{n−1} − ε_a/c) e^{−c k/b},  c = γ_ν R(s_{n−1})²
// (positive, monotone, no step limit), then solves its contact problem exactly with the bond
// a_i = γ_ν α_n² |Γ3|_i: the normal law's graph gets the tension branch λ_i = −a_i min(s_i, L), one more
// piecewise-linear branch that both active-set solvers solve exactly (ContactConstraints::bond).
// Once the step is accepted the node keeps α_n and s_n. A node with α = 0 behaves exactly as without
// adhesion (its bond is 0).
//
// Keys of [contact], a [[contact.part]] or a [[contact.pair]] (a table without `adhesion` takes [contact]'s):
//   adhesion = "fremond" | "none"; bond_stiffness = γ_ν (Pa/m: a traction per unit of separation; a
//   number or a formula in x, y, z; >= 0); bond_length = L (m, > 0); bond_viscosity = b (J s/m^2, > 0);
//   adhesion_energy = ε_a (J/m^2, >= 0, default 0); bonding = α_0 (in [0, 1], a number or a formula in
//   x, y, z; default 1); bond_shear_stiffness = γ_τ (Pa/m, a number or a formula in x, y, z; >= 0; default: none):
//   SPEC §9's optional tangential part σ_τ = −γ_τ α² R_τ(u_τ − u_τ⁰), R_τ the projection onto the disc |v| ≤ L and
//   u_τ⁰ the relative tangential displacement at bonding (t_0), which adds γ_τ |R_τ|² to the rate's c. On
//   frictionless entries only (with friction the two tangential laws would act in parallel; refused).
// Its state (VTU arrays, Python views, checkpoints): bonding α, separation s (≥ 0), adhesive_traction
// γ_ν α² R(s), debonded (1 where α ≤ 1e-6), adhesive_energy γ_ν α² ∫_0^s R (stored in the bond) and
// debonding_energy (the bond energy released by debonding, Σ_n γ_ν (α_{n−1}² − α_n²) ∫_0^{s_{n−1}} R, at
// the separation that drove it); with γ_τ also bond_slip (v along the node's tangents, 2 numbers: the second 0
// in 2D) and adhesive_shear γ_τ α² |R_τ(v)|. history.csv: adhesive_force ∫_Γ3 γ_ν α² R(s), debonded_fraction,
// adhesive_energy and debonding_energy (integrals over Γ3).
#include "contact/friction_law.hpp"

#include <memory>
#include <string>
#include <vector>

namespace vpc {

class FremondAdhesion final : public SurfaceHistory {
 public:
  explicit FremondAdhesion(FrictionKeys& keys);
  /// γ_ν, L, b, ε_a and α_0 as numbers (tests).
  FremondAdhesion(double stiffness, double length, double viscosity, double energy = 0, double bonding = 1);
  std::string describe() const;
  double stiffness(const Point& x) const { return gamma_(x, 0.0); }
  /// α_0 at x.
  double bonding(const Point& x) const { return alpha0_(x, 0.0); }
  double length() const { return length_; }
  /// γ_τ at x (0 without `bond_shear_stiffness`), and whether the law has a tangential bond at all.
  double shear_stiffness(const Point& x) const { return shear_ ? shear_(x, 0.0) : 0.0; }
  bool shears() const { return static_cast<bool>(shear_); }
  /// α_n from α_{n−1}, s_{n−1} and the tangential stretch's length |v_{n−1}| over a step of size k (the
  /// exact solution with both frozen: c = γ_ν R(s)² + γ_τ R(|v|)²).
  double carried(double alpha, double separation, const Point& x, double k, double stretch = 0) const;

  std::vector<SurfaceVariable> surface_state() const override;
  SurfaceUpdate update_surface(const SurfaceNode& node, std::span<double* const> values) const override;
  LawText check_at(const Point& x) const override;
  LawText initial_at(const Point& x, double gap, std::span<double* const> values) const override;
  double bond(std::span<const double* const> values, const Point& x, double k) const override;
  double bond_length() const override { return length_; }
  double shear_bond(std::span<const double* const> values, const Point& x, double k) const override;
  void bond_stretch(std::span<const double* const> values, std::span<double> stretch) const override;

 private:
  /// ∫_0^s R = s²/2 below L, L s − L²/2 beyond: the bond's stored energy per unit of γ_ν α².
  double energy_shape(double s) const;
  std::string text_, bonding_text_, shear_text_;  // before the fields: their readers set them
  LawField gamma_, alpha0_, shear_;  // shear_: γ_τ, empty without `bond_shear_stiffness`
  /// |v| of the tangential stretch in the values (0 without a tangential bond).
  double stretch_of(std::span<const double* const> values) const;
  double length_ = 0, viscosity_ = 0, energy_ = 0;
};

/// The adhesion keys, for the messages of a key without `adhesion` in its table.
std::vector<std::string> adhesion_keys();
/// The keys the adhesion `name` reads (adhesion_keys() for "fremond", none for "none"): what
/// `--set contact.adhesion=none` drops.
std::vector<std::string> adhesion_law_keys(const std::string& name);
/// `adhesion` = "none" (nullptr) or "fremond" with its keys; a located error for a key of the law
/// given with "none".
std::shared_ptr<const FremondAdhesion> make_adhesion_law(const std::string& name, FrictionKeys& keys);

}  // namespace vpc
