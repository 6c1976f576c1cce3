#pragma once
// Geometry of a P1 simplex: its measure and the (constant) gradients of the
// barycentric coordinates λ_a, which are the P1 shape functions.
#include "mesh/mesh.hpp"

#include <array>
#include <vector>

namespace vpc {

struct CellGeometry {
  double volume = 0;                               // length / area / volume
  std::array<std::array<double, 3>, 4> grad{};     // ∇λ_a, a = 0..d
};

/// Geometry of every cell; throws vpc::Error for a degenerate cell.
std::vector<CellGeometry> compute_geometry(const Mesh& mesh);

/// Geometry of one cell from its vertex coordinates (d + 1 of them).
CellGeometry cell_geometry(int dim, const Point* x);

}  // namespace vpc
