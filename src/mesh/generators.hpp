#pragma once
// Structured simplicial meshes. Boundary facets are tagged by side:
// "left"/"right" (x = x0, x1); in 2D "bottom"/"top" (y); in 3D "front"/"back" (y)
// and "bottom"/"top" (z);
// cases re-tag subsets (e.g. the contact zone) with Mesh::tag_facets.
#include "mesh/mesh.hpp"

#include <array>
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

/// The generator of dimension `dim` (interval, rectangle, box) on [lo, hi] with n[a] cells along
/// axis a (the first `dim`): the case file's [mesh] generator.
Mesh generate(int dim, const Point& lo, const Point& hi, const std::array<int, 3>& n, Diagonal diagonal);

/// A block of a generated mesh's grid of segments (squares, cubes): along each axis a
/// of the mesh's dimension, the cells lo[a] ≤ i < hi[a] (lo = hi = 0 on the other axes).
struct GridBlock {
  std::array<int, 3> lo{0, 0, 0}, hi{0, 0, 0};
  long long cells() const;  // segments, squares or cubes
  bool operator==(const GridBlock&) const = default;
};

/// The whole grid of n[a] cells along each of the first `dim` axes.
GridBlock whole_grid(const std::array<int, 3>& n, int dim);

/// Splits `grid` into `parts` blocks by recursive bisection: the longest axis (in cells; the
/// first of equals) is cut in proportion to the parts on either side, which gives blocks of
/// nearly equal size and small faces, a structured domain decomposition. Blocks are in the
/// order of the bisection tree, so consecutive ones are neighbours. Throws vpc::Error where
/// a block would be empty (fewer cells than parts along the way).
std::vector<GridBlock> split_grid(const GridBlock& grid, int dim, int parts);

/// The part of a generated mesh in a block of its grid, built without the rest: the
/// cells the whole generator makes in the block's segments (squares, cubes), in its order
/// and with its nodes in its order (the node coordinates bit for bit), and the boundary
/// facets of the whole mesh on them, tagged by side as it tags them (not the faces where the
/// block is cut). `node_id` and `cell_id` number its nodes and cells in the whole mesh.
struct BlockMesh {
  Mesh mesh;
  std::vector<int> node_id, cell_id;
  long long whole_nodes = 0, whole_cells = 0;  // the whole mesh's
};

/// `generate` on a block of the grid.
BlockMesh generate_block(int dim, const Point& lo, const Point& hi, const std::array<int, 3>& n, Diagonal diagonal,
                         const GridBlock& block);

/// The generators above on a block of the grid (of n, nx × ny, nx × ny × nz cells).
/// The size check (check_mesh_size) applies to the block; the whole mesh's numbers must fit in int.
BlockMesh make_interval_block(double x0, double x1, int n, const GridBlock& block);
BlockMesh make_rectangle_block(Point lo, Point hi, int nx, int ny, Diagonal diagonal, const GridBlock& block);
BlockMesh make_box_block(Point lo, Point hi, int nx, int ny, int nz, Diagonal diagonal, const GridBlock& block);

}  // namespace vpc
