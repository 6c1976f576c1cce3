#pragma once
#include "material/damage_source.hpp"

#include <fmt/format.h>

namespace vpc {

/// φ = 0: damage only diffuses.
class ZeroSource final : public DamageSource {
 public:
  explicit ZeroSource(const Parameters&) {}
  double rate(const PointState&) const override { return 0; }
  std::string describe() const override { return "zero"; }
  bool vanishes() const override { return true; }
};

/// φ = −c tr ε(u); in 1D the paper's −2ε (4.4) with c = 2.
class StrainSource final : public DamageSource {
 public:
  explicit StrainSource(const Parameters& p) : c_(p.get("c", 2.0)) {}
  double rate(const PointState& s) const override { return -c_ * s.eps.trace(); }
  std::string describe() const override { return fmt::format("strain (phi = -{} tr eps)", c_); }

 private:
  double c_;
};

/// φ = −c |σ|_VM; the paper's (4.9) with c = 1/100.
class VonMisesSource final : public DamageSource {
 public:
  explicit VonMisesSource(const Parameters& p) : c_(p.get("c", 0.01)) {}
  double rate(const PointState& s) const override { return -c_ * s.sigma.von_mises(); }
  std::string describe() const override { return fmt::format("von-mises (phi = -{} |sigma|_VM)", c_); }

 private:
  double c_;
};

}  // namespace vpc
