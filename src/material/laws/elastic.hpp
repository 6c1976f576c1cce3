#pragma once
#include "material/viscoplastic_law.hpp"

namespace vpc {

/// G = 0: the body is linearly elastic (β then has no mechanical effect).
class ElasticLaw final : public ViscoplasticLaw {
 public:
  explicit ElasticLaw(const Parameters&) {}
  SymTensor rate(const PointState&) const override { return {}; }
  std::string describe() const override { return "elastic (G = 0)"; }
  Lipschitz lipschitz(double) const override { return {}; }
};

}  // namespace vpc
