#pragma once
// Structured simplicial meshes. Boundary facets are tagged by side:
// "left"/"right" (x = x0, x1); in 2D "bottom"/"top" (y); in 3D "front"/"back" (y)
// and "bottom"/"top" (z);
// cases re-tag subsets (e.g. the contact zone) with Mesh::tag_facets.
#include "mesh/mesh.hpp"

#include <string>
#include <vector>

namespace vpc {

/// The largest generated mesh (simplices): beyond what a run can solve on a workstation (the
/// memory plan, run/solver_plan.hpp, refuses what does not fit; foundation-3d n = 120, 1.04e7
/// cells, runs in 24 GB on 2 ranks), and small enough to fail at once rather than exhaust memory
/// or overflow int indices (a box's K on one rank: about 7e8 nonzeros, below 2³¹).
inline constexpr int kMaxGeneratedCells = 30'000'000;

/// Throws vpc::Error if a generated mesh of `n_cells` simplices exceeds
/// kMaxGeneratedCells. Every generator calls it before allocating anything.
void check_mesh_size(double n_cells);

/// Interval (x0, x1) with n segments; boundary points "left" and "right".
Mesh make_interval(double x0, double x1, int n);

/// How squares (cubes) are cut into simplices. Rectangle: "right" along the
/// diagonal (x0, y0)–(x1, y1) of every square, "left" along the other one,
/// "alternate" right and left in a checkerboard (mirror-symmetric about the
/// mid-lines when the number of cells is even), "crossed" 4 triangles about a
/// centre node (symmetric for any number of cells). Box: "right" the Kuhn
/// subdivision (6 tetrahedra), "left" it mirrored in x, "alternate" mirrored along
/// each axis where the cube's index is odd, "crossed" 24 tetrahedra about the
/// centres of the cube and of its faces. "right" is the default.
enum class Diagonal { right, left, alternate, crossed };
/// "right", "left", "alternate", "crossed" (the order of Diagonal).
const std::vector<std::string>& diagonal_names();
/// Throws vpc::Error listing the names for an unknown one.
Diagonal diagonal_from_name(const std::string& name);

/// Rectangle (x0, x1) × (y0, y1) of nx × ny squares, each split into two
/// triangles (four with Diagonal::crossed).
Mesh make_rectangle(Point lo, Point hi, int nx, int ny, Diagonal diagonal = Diagonal::right);

/// Box of nx × ny × nz cubes, each split into six tetrahedra (Kuhn subdivision,
/// conforming across cubes; 24 with Diagonal::crossed).
Mesh make_box(Point lo, Point hi, int nx, int ny, int nz, Diagonal diagonal = Diagonal::right);

}  // namespace vpc
