#pragma once
#include "core/expression.hpp"
#include "material/damage_source.hpp"

#include <memory>

namespace vpc {

/// φ given as a formula of x, y, z, t, vm, tr_sigma, tr_eps, eps_eq, beta
/// (see core/expression.hpp), evaluated at the element centroid at t_{n−1}.
class ExpressionSource final : public DamageSource {
 public:
  explicit ExpressionSource(std::shared_ptr<const Expression> phi) : phi_(std::move(phi)) {}
  double rate(const PointState& s) const override { return (*phi_)(s.x, s.t, s.sigma, s.eps, s.beta); }
  std::string describe() const override { return "expression (phi = " + phi_->text() + ")"; }

 private:
  std::shared_ptr<const Expression> phi_;
};

}  // namespace vpc
