#pragma once
// Uniform refinement of a simplicial mesh (`[mesh] refine = k`, issue 30; the verification's mesh
// hierarchies, verification/refine.hpp): every segment cut in 2, triangle in 4, tetrahedron in 8
// (Bey's red refinement, its inner octahedron cut along its shortest diagonal, the first of
// equals), k times. Boundary facets are refined alike
// and keep their part, cells keep their region, so a refined Gmsh mesh has the coarse mesh's
// physical groups.
//
// The refined mesh is numbered from the coarse mesh alone, which every rank holds (as p4est and
// deal.II hold their coarse mesh): coarse cell after coarse cell, the nodes a cell adds (its
// vertices, then the points inside its edges, faces and itself, each entity's in a fixed order of
// its lattice points, where no earlier cell has numbered them); the children of coarse cell c are
// cells c·2^(dk) onwards. So a rank refines only its
// coarse cells and a layer around them (refine_block), with the numbers, coordinates (bit for
// bit) and cells of the whole refinement (refine_mesh), and no rank builds the whole fine mesh.
#include "mesh/generators.hpp"
#include "mesh/mesh.hpp"

#include <array>
#include <vector>

namespace vpc {

class MeshRefinement {
 public:
  /// Numbers the coarse mesh's edges (and faces in 3D). Throws vpc::Error where the refined mesh
  /// would not fit a mesh's numbers (2^31 cells or nodes).
  MeshRefinement(const Mesh& coarse, int levels);

  int levels() const { return levels_; }
  long long whole_nodes() const { return whole_nodes_; }
  long long whole_cells() const { return static_cast<long long>(coarse_.n_cells()) * children_; }

  /// The children of the coarse cells `cells` (increasing) and, of the coarse cells `layer`
  /// (increasing, none of `cells`), the children that share a node with those (one layer of fine
  /// cells around them, as a generated block has), with the children of the coarse boundary
  /// facets on them: nodes in increasing whole-mesh number, cells and facets in the whole
  /// refinement's order, parts and regions named in the coarse mesh's order (even those absent
  /// here). Checks the size (kMaxGeneratedCells on the children of `cells`) before allocating.
  BlockMesh refine(const std::vector<int>& cells, const std::vector<int>& layer = {}) const;
  /// The whole refinement (refine on every coarse cell, with every coarse facet).
  BlockMesh refine_all() const;

  /// With one level, for every node of the whole refinement: the two coarse nodes whose midpoint
  /// it is ({v, v} for coarse node v).
  std::vector<std::array<int, 2>> midpoints() const;

 private:
  using Lattice = std::array<int, 4>;  // barycentric coordinates times 2^levels on a coarse simplex
  /// The whole-mesh number of the point `lambda` of the simplex of n coarse `vertices` (the coarse
  /// cell `cell` when n = d + 1; −1 for a facet).
  long long node_id(const int* vertices, int n, const Lattice& lambda, int cell) const;
  Point node_x(const int* vertices, int n, const Lattice& lambda) const;
  /// Calls emit(child) for each of the 2^(levels·(n−1)) children (n lattice points each) of the
  /// simplex of n coarse `vertices`, in the refinement's order.
  template <class Emit>
  void children(const int* vertices, int n, Emit emit) const;
  BlockMesh refine(const std::vector<int>& cells, const std::vector<int>& layer, bool every_facet) const;

  /// The index in entities_[j] of the j-face with these sorted vertices.
  long long entity(int j, const std::array<int, 3>& sorted) const;

  const Mesh& coarse_;
  int levels_ = 0, m_ = 1;    // m = 2^levels lattice steps along each coarse edge
  long long children_ = 1;    // cells per coarse cell: 2^(d·levels)
  std::vector<std::array<int, 3>> entities_[3];  // [j]: sorted vertices of the coarse j-faces, j = 1, 2
  std::vector<int> base_[4];  // [j]: the first number of the nodes inside each j-face (j = 0: the
                              // coarse nodes; j = d: the cells)
  long long whole_nodes_ = 0;
};

/// The whole mesh refined `levels` times.
Mesh refine_mesh(const Mesh& coarse, int levels);

/// Each coarse cell's rank: recursive coordinate bisection of the cells' centroids (the longest
/// extent cut in proportion to the ranks on either side), the same on every rank; the cells of a
/// rank are then nearly 1/ranks of them. Throws vpc::Error where a rank would get no cell.
std::vector<int> split_cells(const Mesh& coarse, int ranks);

/// The coarse cells of other ranks than `rank` that share a node with one of its cells (the
/// coarse cells whose children may touch its children), increasing.
std::vector<int> layer_cells(const Mesh& coarse, const std::vector<int>& cell_rank, int rank);

}  // namespace vpc
