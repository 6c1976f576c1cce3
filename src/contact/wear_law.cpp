#include "contact/wear_law.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vpc {

namespace {

/// A number of the wear law in (0, high], or its default.
double wear_number(FrictionKeys& keys, const std::string& key, double fallback, double high, const std::string& what) {
  const double v = keys.number(key, fallback);
  if (!(v > 0 && v <= high)) fail("{}: expected {}, got {}", keys.where(key), what, v);
  return v;
}

}  // namespace

std::vector<std::string> wear_keys() { return {"wear_coefficient", "wear_cap", "wear_warning"}; }

std::vector<std::string> wear_law_keys(const std::string& name) {
  return name == "archard" ? wear_keys() : std::vector<std::string>{};
}

ArchardWear::ArchardWear(FrictionKeys& keys)
    : k_w_(nonnegative_field(keys, "wear_coefficient", false, "a wear coefficient k_w (1/Pa: m^2/N)", text_)),
      cap_(wear_number(keys, "wear_cap", 0.5, 1.0,
                       "a share 0 < wear_cap <= 1 of a node's elastic approach (the largest wear increment of a step)")),
      warning_(wear_number(keys, "wear_warning", 0.1, INFINITY,
                           "a share wear_warning > 0 of the element size (a worn depth to warn at)")) {}

ArchardWear::ArchardWear(double coefficient, double cap, double warning)
    : text_(fmt::format("{}", coefficient)), k_w_([coefficient](const Point&, double) { return coefficient; }),
      cap_(cap), warning_(warning) {
  require(coefficient >= 0 && std::isfinite(coefficient) && cap > 0 && cap <= 1 && warning > 0,
          "Archard wear: k_w >= 0, 0 < cap <= 1 and warning > 0, got {}, {} and {}", coefficient, cap, warning);
}

std::string ArchardWear::describe() const { return "Archard wear k_w = " + text_; }

std::vector<SurfaceVariable> ArchardWear::surface_state() const {
  return {{"wear", 1, 0.0, "Archard's worn depth ω (a length; it opens the gap: u_ν <= g + ω)", "worn_volume"}};
}

SurfaceUpdate ArchardWear::update_surface(const SurfaceNode& node, std::span<double* const> values) const {
  const double slip = node.slip;
  const double pressing = std::max(node.lambda_nu, 0.0);
  double& omega = *values[0];
  omega += coefficient(node.x) * pressing / node.measure * slip;
  SurfaceUpdate out;
  // increment / (cap · λ_ν / k_ν) = k_w |Δ| k_ν / (|Γ3|_i cap): the step's share of its cap, 0 where
  // the node does not press (no increment, whatever its approach).
  if (pressing > 0) out.step_share = coefficient(node.x) * slip * node.normal_stiffness / (node.measure * cap_);
  if (node.size > 0) out.warn_share = omega / (warning_ * node.size);
  return out;
}

LawText ArchardWear::check_at(const Point& x) const {
  const double k = coefficient(x);
  if (std::isfinite(k) && k >= 0) return {};
  return {"wear_coefficient", fmt::format("the wear coefficient k_w is {} at contact node ({}, {}, {}); expected a number >= 0", k, x[0], x[1],
                     x[2])};
}

LawText ArchardWear::step_limit() const {
  return {"wear_cap", fmt::format(
      "the Archard wear increment k_w (λ_ν/|Γ3|) |Δu_τ| of the step passed wear_cap = {} of the node's elastic approach "
      "λ_ν/k_ν (k_ν: the node's normal stiffness): the lagged wear overshoots above it. Shorter steps lower it "
      "(--retry-halvings, or [time] tolerance for error-controlled steps), as does a smaller k_w",
      cap_)};
}

LawText ArchardWear::warning() const {
  return {"wear_warning", fmt::format(
      "the Archard worn depth ω passed wear_warning = {} of the element size at the node: the wear enters as a shift "
      "of the gap on the reference mesh, which stops representing the worn shape as ω grows against the elements",
      warning_)};
}

std::shared_ptr<const ArchardWear> make_wear_law(const std::string& name, FrictionKeys& keys) {
  if (name == "none") {
    for (const std::string& k : wear_keys())
      if (keys.has(k)) fail("{}: {} does not belong to wear = \"none\"", keys.where(k), k);
    return nullptr;
  }
  require(name == "archard", "make_wear_law: unknown wear law '{}'", name);
  return std::make_shared<const ArchardWear>(keys);
}

}  // namespace vpc
