#pragma once
// Quadrature on the reference simplex in barycentric coordinates, exact for
// polynomials of degree 2: enough to integrate f·λ_a exactly for loads f that are
// linear in x (the paper's loads are constant or linear).
#include <array>
#include <vector>

namespace vpc {

struct QuadraturePoint {
  std::array<double, 4> lambda{};  // barycentric coordinates
  double weight = 0;               // weights sum to 1 (multiply by the measure)
};

/// Degree-2 rule on a d-simplex, d = 0 (a point), 1, 2, 3.
const std::vector<QuadraturePoint>& simplex_rule(int d);

}  // namespace vpc
