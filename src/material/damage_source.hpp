#pragma once
// The damage source φ(σ, ε(u), β) of (2.2).
#include "material/parameters.hpp"
#include "material/point_state.hpp"

#include <memory>
#include <string>
#include <vector>

namespace vpc {

class DamageSource {
 public:
  virtual ~DamageSource() = default;
  virtual double rate(const PointState& s) const = 0;
  virtual std::string describe() const = 0;
  /// φ ≡ 0 whatever the state: a body of such cells with a uniform β0 keeps β = β0 exactly
  /// (constant_damage_nodes, scheme/discrete_system.hpp).
  virtual bool vanishes() const { return false; }
};

/// Builds a source by name ("zero", "strain", "von-mises"); throws vpc::Error for
/// an unknown name or parameter.
std::unique_ptr<DamageSource> make_damage_source(const std::string& name, const Parameters& p);
std::vector<std::string> damage_source_names();
/// The parameter names of a source (empty for an unknown name).
std::vector<std::string> damage_source_parameters(const std::string& name);

}  // namespace vpc
