#include "contact/normal_compliance.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

NormalComplianceLaw::NormalComplianceLaw(LawKeys& keys) {
  c_ = keys.number("stiffness");
  if (!(c_ > 0)) fail("{}: expected a stiffness > 0, got {}", keys.where("stiffness"), c_);
  e_ = keys.number("exponent", 1.0);
  if (!(e_ >= 1)) fail("{}: expected an exponent >= 1, got {}", keys.where("exponent"), e_);
}

std::string NormalComplianceLaw::describe() const {
  return e_ == 1 ? fmt::format("normal compliance c = {}", c_) : fmt::format("normal compliance c = {}, e = {}", c_, e_);
}

std::string NormalComplianceLaw::conflict(const ContactLaw& other) const {
  const auto* o = dynamic_cast<const NormalComplianceLaw*>(&other);
  if (!o) return fmt::format("laws are a {} and a {}; parts with different laws cannot share a node", kind(), other.kind());
  if (o->e_ == e_) return {};
  return fmt::format("compliance laws have the exponents {} and {}; parts with different exponents cannot share a node",
                     e_, o->e_);
}

// s0 + λ/k, and (λ/k)^{1/e} in place of λ/k where e ≠ 1 (in this order: the residuals of a
// linear row are those of the box QP's S + diag(1/k)).
double NormalComplianceLaw::gap_left(double s0, double lambda, double compliance) const {
  double s = s0 + compliance * lambda;
  if (e_ != 1) s += std::pow(std::max(compliance * lambda, 0.0), 1 / e_) - compliance * lambda;
  return s;
}

double NormalComplianceLaw::force(double d, double compliance) const {
  const double k = 1 / compliance, pen = std::max(d, 0.0);
  return k * std::pow(pen, e_);
}

double NormalComplianceLaw::force_slope(double d, double compliance) const {
  const double k = 1 / compliance, pen = std::max(d, 0.0);
  return pen > 0 ? k * e_ * std::pow(pen, e_ - 1) : 0.0;
}

}  // namespace vpc
