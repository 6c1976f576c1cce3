#pragma once
// The viscoplastic function G(σ, ε(u), β) of (2.1). Laws hold parameters, never
// state; the scheme evaluates them per element on the lagged state.
#include "material/parameters.hpp"
#include "material/point_state.hpp"

#include <memory>
#include <string>
#include <vector>

namespace vpc {

class ViscoplasticLaw {
 public:
  virtual ~ViscoplasticLaw() = default;
  virtual SymTensor rate(const PointState& s) const = 0;
  virtual std::string describe() const = 0;
};

/// Builds a law by name ("elastic", "perzyna", "perzyna-von-mises", "maxwell-damage");
/// throws vpc::Error for an unknown name or parameter.
std::unique_ptr<ViscoplasticLaw> make_viscoplastic_law(const std::string& name, const Parameters& p);
std::vector<std::string> viscoplastic_law_names();
/// The parameter names of a law (empty for an unknown name).
std::vector<std::string> viscoplastic_law_parameters(const std::string& name);

}  // namespace vpc
