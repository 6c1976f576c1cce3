#pragma once
// The viscoplastic function G(σ, ε(u), β) of (2.1). Laws hold parameters, never
// state; the scheme evaluates them per element on the lagged state.
#include "material/parameters.hpp"
#include "material/point_state.hpp"

#include <memory>
#include <string>
#include <vector>

namespace vpc {

/// A law's Lipschitz constant L and its formula in the law's parameters (for messages).
struct Lipschitz {
  double value = 0;
  std::string formula;  // "E/(2 lambda)"; empty for L = 0
};

class ViscoplasticLaw {
 public:
  virtual ~ViscoplasticLaw() = default;
  virtual SymTensor rate(const PointState& s) const = 0;
  virtual std::string describe() const = 0;
  /// L(β), the Lipschitz constant of σ ↦ G(σ, ε, β) at a fixed β (Frobenius norm): the
  /// fastest rate at which G relaxes σ. Non-increasing in β (β = 0, the most damaged state,
  /// is the worst). The lagged step z_n = z_{n−1} + k G_{n−1} of (3.6) is explicit and stable
  /// only for k L ≤ 2 (problem/stability.hpp; docs/scheme.md, "Stability of the lagged step").
  virtual Lipschitz lipschitz(double beta) const = 0;
};

/// Builds a law by name ("elastic", "perzyna", "perzyna-von-mises", "maxwell-damage");
/// throws vpc::Error for an unknown name or parameter.
std::unique_ptr<ViscoplasticLaw> make_viscoplastic_law(const std::string& name, const Parameters& p);
std::vector<std::string> viscoplastic_law_names();
/// The parameter names of a law (empty for an unknown name).
std::vector<std::string> viscoplastic_law_parameters(const std::string& name);

}  // namespace vpc
