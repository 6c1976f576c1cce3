#pragma once
// Archard's wear (SPEC §9; Shillor–Sofonea–Telega 2004): a surface sliding under pressure loses
// material at the rate ω̇ = k_w p |u̇_τ − v*_τ|, p = λ_ν / |Γ3|_i the compressive pressure, v*_τ the
// partner's tangential velocity (a moving obstacle's, or the master side's mortar mean), k_w ≥ 0 a
// wear coefficient (1/Pa = m²/N). The worn depth ω per contact node opens the gap: u_ν ≤ g + ω.
//
// Lagged as the scheme lags the damage source (SPEC §2): step n solves with the gap g(t_n) + ω_{n−1}
// (gap_shift), and once it is accepted ω_n = ω_{n−1} + k_w (λ_ν,n / |Γ3|_i) |Δu_τ,n| (rate-independent:
// the step's size cancels, as for friction). The lagged update is conditionally stable: ω's change
// moves the pressure back by the node's stiffness, so an increment above the node's elastic approach
// λ_ν / k_ν overshoots (a bar: the factor 1 − k_w E Δs / H of SPEC §9). A step whose increment passes
// wear_cap times that approach is rejected and redone smaller. On a pair the worn depth is the slave
// side's: its rows are the slave nodes' (dual mortar), and all material a pair loses is taken from the
// slave surface (make the softer body the slave).
//
// Keys of [contact], a [[contact.part]] or a [[contact.pair]] (a table without `wear` takes [contact]'s):
//   wear = "archard" | "none", wear_coefficient = k_w (a number or a formula in x, y, z; >= 0),
//   wear_cap (0 < cap <= 1, default 0.5), wear_warning (> 0, default 0.1: warn once when ω passes
//   that fraction of the element size at a node, where the gap shift stops representing the worn shape).
#include "contact/friction_law.hpp"

#include <memory>
#include <string>
#include <vector>

namespace vpc {

class ArchardWear final : public SurfaceHistory {
 public:
  explicit ArchardWear(FrictionKeys& keys);
  ArchardWear(double coefficient, double cap = 0.5, double warning = 0.1);
  std::string describe() const;
  double coefficient(const Point& x) const { return k_w_(x, 0.0); }

  std::vector<SurfaceVariable> surface_state() const override;
  SurfaceUpdate update_surface(const SurfaceNode& node, std::span<double* const> values) const override;
  double gap_shift(std::span<const double* const> values) const override { return *values[0]; }
  LawText check_at(const Point& x) const override;
  LawText step_limit() const override;
  LawText warning() const override;

 private:
  std::string text_;  // before k_w_: its reader sets it
  LawField k_w_;
  double cap_ = 0.5, warning_ = 0.1;
};

/// The wear keys, for the messages of a key without `wear` in its table.
std::vector<std::string> wear_keys();
/// The keys the wear `name` reads (wear_keys() for "archard", none for "none"): what
/// `--set contact.wear=none` drops.
std::vector<std::string> wear_law_keys(const std::string& name);
/// `wear` = "none" (nullptr) or "archard" with its keys; a located error for another name or a key
/// of the wear law given without it.
std::shared_ptr<const ArchardWear> make_wear_law(const std::string& name, FrictionKeys& keys);

}  // namespace vpc
