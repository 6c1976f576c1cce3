#pragma once
#include "material/viscoplastic_law.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vpc {

/// Maxwell-type law with damage (4.8): G = r (β − 1) σ; r = 1 in the paper.
class MaxwellDamageLaw final : public ViscoplasticLaw {
 public:
  explicit MaxwellDamageLaw(const Parameters& p) : r_(p.get("rate", 1.0)) {}
  SymTensor rate(const PointState& s) const override { return (r_ * (s.beta - 1)) * s.sigma; }
  std::string describe() const override { return fmt::format("maxwell-damage (rate = {})", r_); }
  /// ∂G/∂σ = −r (1 − β) I.
  Lipschitz lipschitz(double beta) const override {
    return {std::abs(r_) * (1 - std::clamp(beta, 0.0, 1.0)), "|rate| (1 - beta)"};
  }

 private:
  double r_;
};

}  // namespace vpc
