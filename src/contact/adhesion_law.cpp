#include "contact/adhesion_law.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vpc {

namespace {

/// A number of the law > 0 (required) or >= 0 (with a fallback).
double positive_number(FrictionKeys& keys, const std::string& key, const std::string& what) {
  if (!keys.has(key)) fail("{}: missing key {} ({})", keys.where(key), key, what);
  const double v = keys.number(key);
  if (!(v > 0) || !std::isfinite(v)) fail("{}: expected {} > 0, got {}", keys.where(key), what, v);
  return v;
}

/// α ≤ this counts as debonded (SPEC §9's debonded fraction).
constexpr double kDebonded = 1e-6;

}  // namespace

std::vector<std::string> adhesion_keys() {
  return {"bond_stiffness", "bond_length", "bond_viscosity", "adhesion_energy", "bonding", "bond_shear_stiffness"};
}

std::vector<std::string> adhesion_law_keys(const std::string& name) {
  return name == "fremond" ? adhesion_keys() : std::vector<std::string>{};
}

FremondAdhesion::FremondAdhesion(FrictionKeys& keys)
    : gamma_(nonnegative_field(keys, "bond_stiffness", false,
                               "a bond stiffness gamma_nu (Pa/m: the bond's traction per unit of separation)", text_)),
      length_(positive_number(keys, "bond_length", "a bond length L (m: the separation beyond which the pull stays "
                                                   "gamma_nu alpha^2 L)")),
      viscosity_(positive_number(keys, "bond_viscosity", "a bond viscosity b (J s/m^2)")),
      energy_(keys.number("adhesion_energy", 0.0)) {
  if (!(energy_ >= 0) || !std::isfinite(energy_))
    fail("{}: expected an adhesion energy epsilon_a >= 0 (J/m^2), got {}", keys.where("adhesion_energy"), energy_);
  if (keys.has("bond_shear_stiffness"))
    shear_ = nonnegative_field(keys, "bond_shear_stiffness", false,
                               "a tangential bond stiffness gamma_tau (Pa/m: the bond's shear traction per unit of "
                               "tangential stretch)",
                               shear_text_);
  if (!keys.has("bonding")) {
    alpha0_ = [](const Point&, double) { return 1.0; };
    bonding_text_ = "1";
    return;
  }
  alpha0_ = keys.field("bonding", false);
  bonding_text_ = "(a formula)";
  if (!keys.is_number("bonding")) return;
  const double a = alpha0_(Point{0, 0, 0}, 0.0);
  if (!(a >= 0 && a <= 1)) fail("{}: expected an initial bonding alpha_0 in [0, 1], got {}", keys.where("bonding"), a);
  bonding_text_ = fmt::format("{}", a);
}

FremondAdhesion::FremondAdhesion(double stiffness, double length, double viscosity, double energy, double bonding)
    : text_(fmt::format("{}", stiffness)), bonding_text_(fmt::format("{}", bonding)),
      gamma_([stiffness](const Point&, double) { return stiffness; }),
      alpha0_([bonding](const Point&, double) { return bonding; }), length_(length), viscosity_(viscosity),
      energy_(energy) {
  require(stiffness >= 0 && std::isfinite(stiffness) && length > 0 && std::isfinite(length) && viscosity > 0 &&
              std::isfinite(viscosity) && energy >= 0 && std::isfinite(energy) && bonding >= 0 && bonding <= 1,
          "Frémond adhesion: gamma_nu >= 0, L > 0, b > 0, epsilon_a >= 0 and alpha_0 in [0, 1], got {}, {}, {}, {}, {}",
          stiffness, length, viscosity, energy, bonding);
}

std::string FremondAdhesion::describe() const {
  return fmt::format("adhesion gamma_nu = {}{}, L = {}, b = {}, epsilon_a = {}, alpha_0 = {}", text_,
                     shear_ ? ", gamma_tau = " + shear_text_ : std::string(), length_, viscosity_, energy_, bonding_text_);
}

double FremondAdhesion::stretch_of(std::span<const double* const> v) const {
  return shear_ ? std::hypot(v[6][0], v[6][1]) : 0.0;
}

double FremondAdhesion::energy_shape(double s) const {
  return s <= length_ ? 0.5 * s * s : length_ * (s - 0.5 * length_);
}

double FremondAdhesion::carried(double alpha, double separation, const Point& x, double k, double stretch) const {
  const double R = std::min(std::max(separation, 0.0), length_), R_tau = std::min(stretch, length_);
  const double c = stiffness(x) * R * R + shear_stiffness(x) * R_tau * R_tau;
  if (c * alpha <= energy_) return alpha;  // the bond holds: α̇ = 0 (also c = 0)
  const double rest = energy_ / c;         // the rate law's fixed point, below α
  return rest + (alpha - rest) * std::exp(-c * k / viscosity_);
}

std::vector<SurfaceVariable> FremondAdhesion::surface_state() const {
  std::vector<SurfaceVariable> vars = {{"bonding", 1, 1.0, "the bonding field α in [0, 1] (1 bonded, 0 debonded; SPEC §9)", ""},
          {"separation", 1, 0.0, "the separation s = g − u_ν ≥ 0 at t_n, which drives the next step's debonding", ""},
          {"adhesive_traction", 1, 0.0, "the bond's pull γ_ν α² min(s, L) (a traction)", "adhesive_force"},
          {"debonded", 1, 0.0, "1 where α <= 1e-6 (debonded), else 0", "debonded_fraction", true},
          {"adhesive_energy", 1, 0.0, "the energy stored in the bond, γ_ν α² ∫_0^s min(r, L) dr (per unit of Γ3)",
           "adhesive_energy"},
          {"debonding_energy", 1, 0.0,
           "the bond energy released by debonding so far, Σ γ_ν (α_{n−1}² − α_n²) ∫_0^{s_{n−1}} min(r, L) dr (per unit "
           "of Γ3)",
           "debonding_energy"}};
  if (shear_) {  // SPEC §9's tangential part
    vars.push_back({"bond_slip", 2, 0.0,
                    "the bond's tangential stretch v = u_τ − u_τ⁰ since bonding, along the node's tangents (in 2D the "
                    "second is 0)",
                    ""});
    vars.push_back({"adhesive_shear", 1, 0.0, "the bond's tangential pull γ_τ α² min(|v|, L) (a traction)", ""});
  }
  return vars;
}

SurfaceUpdate FremondAdhesion::update_surface(const SurfaceNode& node, std::span<double* const> v) const {
  const double before = *v[0], s_before = *v[1];
  const double v_before = stretch_of(std::span<const double* const>(v.data(), v.size()));
  const double alpha = carried(before, s_before, node.x, node.k, v_before);  // the α step n solved with (bond)
  const double s = std::max(node.gap_left, 0.0), gamma = stiffness(node.x), gamma_tau = shear_stiffness(node.x);
  double v_now = 0;
  if (shear_) {  // v_n = v_{n−1} + Δ: the step's slip increment relative to the partner, along the tangents
    for (std::size_t j = 0; j < node.slip_step.size() && j < 2; ++j) v[6][j] += node.slip_step[j];
    v_now = std::hypot(v[6][0], v[6][1]);
    *v[7] = gamma_tau * alpha * alpha * std::min(v_now, length_);
  }
  *v[0] = alpha;
  *v[1] = s;
  *v[2] = gamma * alpha * alpha * std::min(s, length_);
  *v[3] = alpha <= kDebonded ? 1.0 : 0.0;
  *v[4] = gamma * alpha * alpha * energy_shape(s);
  *v[5] += gamma * (before * before - alpha * alpha) * energy_shape(s_before);
  if (shear_) {  // the tangential part's (kept apart: a law without it writes the same bits as before it)
    *v[4] += gamma_tau * alpha * alpha * energy_shape(v_now);
    *v[5] += gamma_tau * (before * before - alpha * alpha) * energy_shape(v_before);
  }
  // The rate at t_n with the step's own separation against the one the step integrated (s_{n−1}):
  // the lag's local error is k/2 times it (the error estimate's, as β's).
  const auto rate = [&](double sep, double stretch) {
    const double R = std::min(sep, length_), R_tau = std::min(stretch, length_);
    return -std::max(alpha * gamma * R * R + alpha * gamma_tau * R_tau * R_tau - energy_, 0.0) / viscosity_;
  };
  SurfaceUpdate out;
  out.rate_change = std::abs(rate(s, v_now) - rate(s_before, v_before));
  return out;
}

LawText FremondAdhesion::check_at(const Point& x) const {
  if (const double g = shear_stiffness(x); !(std::isfinite(g) && g >= 0))
    return {"bond_shear_stiffness", fmt::format("the tangential bond stiffness gamma_tau is {} at contact node ({}, {}, "
                                                "{}); expected a number >= 0",
                                                g, x[0], x[1], x[2])};
  if (const double g = stiffness(x); !(std::isfinite(g) && g >= 0))
    return {"bond_stiffness", fmt::format("the bond stiffness gamma_nu is {} at contact node ({}, {}, {}); expected a "
                                          "number >= 0",
                                          g, x[0], x[1], x[2])};
  if (const double a = alpha0_(x, 0.0); !(a >= 0 && a <= 1))
    return {"bonding", fmt::format("the initial bonding alpha_0 is {} at contact node ({}, {}, {}); expected a number in "
                                   "[0, 1]",
                                   a, x[0], x[1], x[2])};
  return {};
}

LawText FremondAdhesion::initial_at(const Point& x, double gap, std::span<double* const> v) const {
  const double a = alpha0_(x, 0.0);
  // Bonding needs touching surfaces: a gap of round-off (an obstacle's distance, a pair's mortar gap) is 0.
  const double tolerance = 1e-12 * std::max({1.0, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
  if (a > 0 && gap > tolerance)
    return {"bonding", fmt::format("the initial bonding alpha_0 is {} at contact node ({}, {}, {}), where the initial "
                                   "gap is {}: a bond needs touching surfaces (gap 0); give alpha_0 = 0 where the gap "
                                   "is open (a formula in x, y, z)",
                                   a, x[0], x[1], x[2], gap)};
  *v[0] = a;
  *v[1] = std::max(gap, 0.0);
  *v[3] = a <= kDebonded ? 1.0 : 0.0;
  return {};
}

double FremondAdhesion::bond(std::span<const double* const> v, const Point& x, double k) const {
  const double alpha = carried(*v[0], *v[1], x, k, stretch_of(v));
  return stiffness(x) * alpha * alpha;
}

double FremondAdhesion::shear_bond(std::span<const double* const> v, const Point& x, double k) const {
  if (!shear_) return 0;
  const double alpha = carried(*v[0], *v[1], x, k, stretch_of(v));
  return shear_stiffness(x) * alpha * alpha;
}

void FremondAdhesion::bond_stretch(std::span<const double* const> v, std::span<double> stretch) const {
  if (!shear_) return;
  for (std::size_t j = 0; j < stretch.size() && j < 2; ++j) stretch[j] += v[6][j];
}

std::shared_ptr<const FremondAdhesion> make_adhesion_law(const std::string& name, FrictionKeys& keys) {
  if (name == "none") {
    for (const std::string& k : adhesion_keys())
      if (keys.has(k)) fail("{}: {} does not belong to adhesion = \"none\"", keys.where(k), k);
    return nullptr;
  }
  require(name == "fremond", "make_adhesion_law: unknown adhesion law '{}'", name);
  return std::make_shared<const FremondAdhesion>(keys);
}

}  // namespace vpc
