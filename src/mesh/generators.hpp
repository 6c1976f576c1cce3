#pragma once
// Structured simplicial meshes. Boundary facets are tagged by side:
// "left"/"right" (x = x0, x1); in 2D "bottom"/"top" (y); in 3D "front"/"back" (y)
// and "bottom"/"top" (z);
// cases re-tag subsets (e.g. the contact zone) with Mesh::tag_facets.
#include "mesh/mesh.hpp"

namespace vpc {

/// The largest generated mesh (simplices): far beyond what a run can solve, and
/// small enough to fail at once rather than exhaust memory or overflow int indices.
inline constexpr int kMaxGeneratedCells = 10'000'000;

/// Throws vpc::Error if a generated mesh of `n_cells` simplices exceeds
/// kMaxGeneratedCells. Every generator calls it before allocating anything.
void check_mesh_size(double n_cells);

/// Interval (x0, x1) with n segments; boundary points "left" and "right".
Mesh make_interval(double x0, double x1, int n);

/// Rectangle (x0, x1) × (y0, y1) of nx × ny squares, each split into two triangles.
Mesh make_rectangle(Point lo, Point hi, int nx, int ny);

/// Box of nx × ny × nz cubes, each split into six tetrahedra (Kuhn subdivision,
/// conforming across cubes).
Mesh make_box(Point lo, Point hi, int nx, int ny, int nz);

}  // namespace vpc
