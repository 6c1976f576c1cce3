#pragma once
// Conforming newest-vertex bisection of a triangle mesh (issue 51's first piece: local refinement; the
// adaptive run, 3D and coarsening build on it). Each triangle (v0, v1, v2) is bisected across its
// refinement edge v0–v1 at its midpoint m into (v2, v0, m) and (v1, v2, m): the new vertex m is each
// child's peak, and each child's refinement edge is one of the parent's other edges. A triangle whose
// refinement-edge neighbour has another refinement edge bisects that neighbour first (its child across the
// edge then has it as its own), so the leaves stay conforming: no hanging node (Mitchell 1991; Binev, Dahmen,
// DeVore 2004). The coarse mesh's labelling takes each triangle's longest edge as its refinement edge, ties
// broken by the least (smaller, larger) pair of coarse node numbers: the same on every rank, and it makes
// the closure terminate. A triangle's descendants fall into finitely many similarity classes (at most 4 per
// coarse triangle), so their angles stay bounded below by the coarse mesh's (tested 30 levels deep).
//
// The refinement is kept as a forest over the coarse cells (each cell's parent, children and level), so that
// the leaves' data can be carried from parents to children (and back, by coarsening, later), and a leaf mesh
// (BisectionForest::leaf_mesh) keeps the coarse mesh's boundary parts (a bisected boundary facet's halves
// keep its part), regions and bodies.
#include "mesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace vpc {

class BisectionForest {
 public:
  /// The forest of `coarse` (2D, triangles): every coarse cell a root, labelled (see above).
  explicit BisectionForest(const Mesh& coarse);

  /// Bisects each leaf of `leaves` (BisectionForest cell numbers, leaves) once, and what conformity needs.
  /// Returns how many cells were bisected in all.
  int refine(const std::vector<int>& leaves);
  /// Undoes the bisections that made a node wherever every leaf around the node is in `leaves` and those
  /// leaves are exactly the children of the bisection(s) that made it (the node's patch: 2 children on the
  /// boundary, 4 inside): their parents become leaves again, and the node goes (node_alive). Conforming
  /// before, conforming after. Returns how many nodes went.
  int coarsen(const std::vector<int>& leaves);
  /// A node that coarsening can remove, and the parents whose children make up its patch.
  struct Patch {
    int node = -1;
    std::vector<int> parents;
  };
  /// The nodes coarsen(leaves) would remove, in increasing number, each with its patch (a leaf is in one
  /// patch at most: the patch of its peak).
  std::vector<Patch> coarsenable(const std::vector<int>& leaves) const;
  /// Removes the nodes of `patches` (coarsenable's, on this forest as it was then). Returns how many.
  int coarsen_patches(const std::vector<Patch>& patches);
  /// The children of cell c (−1 for a cell never split).
  const std::array<int, 2>& children(int c) const { return cells_[static_cast<std::size_t>(c)].child; }
  /// Cell c's area.
  double area(int c) const;
  /// Whether node i is a vertex of the leaves (a node removed by coarsening keeps its number, unused).
  bool node_alive(int i) const { return alive_[static_cast<std::size_t>(i)] != 0; }
  /// The leaf mesh's number of each node (−1 where it is not alive).
  std::vector<int> mesh_numbers() const;

  int n_cells() const { return static_cast<int>(cells_.size()); }
  int n_nodes() const { return static_cast<int>(x_.size()); }
  const Point& node(int i) const { return x_[static_cast<std::size_t>(i)]; }
  /// Cell c's vertices (v0, v1, v2: the refinement edge v0–v1, the peak v2), counterclockwise.
  const std::array<int, 3>& vertices(int c) const { return cells_[static_cast<std::size_t>(c)].v; }
  bool leaf(int c) const { return cells_[static_cast<std::size_t>(c)].is_leaf; }
  int parent(int c) const { return cells_[static_cast<std::size_t>(c)].parent; }
  int level(int c) const { return cells_[static_cast<std::size_t>(c)].level; }
  /// The coarse cell c descends from.
  int root(int c) const { return cells_[static_cast<std::size_t>(c)].root; }
  /// The leaves, in forest order (coarse cell after coarse cell, each subtree depth first).
  std::vector<int> leaves() const;

  /// The mesh of the leaves (in leaves() order; the alive nodes in increasing number: mesh_numbers):
  /// boundary facets as the coarse mesh's, bisected, in their parts; cells in their coarse cell's region.
  Mesh leaf_mesh() const;

  /// The smallest interior angle over the leaves (radians).
  double min_angle() const;

  // The history carried over a refinement (issue 51: "on refinement, exactly"):
  /// A nodal field of `width` numbers a node, given on the nodes before a refinement (its size: those
  /// nodes × width), extended to every node: a new node takes the mean of its edge's ends, in the order
  /// the nodes were made (a midpoint of midpoints after them): P1 fields are carried exactly.
  void interpolate(std::vector<double>& values, int width) const;
  /// A cell field of `width` numbers a cell, given on the leaves `before` (leaves() before a refinement
  /// or coarsening, in that order), on today's leaves (leaves() order): a leaf that was one keeps its
  /// values, a child takes its ancestor's (P0 fields inherited exactly), a parent made a leaf again the
  /// area-weighted mean of its descendants among `before` (the integral kept: z by volume average).
  std::vector<double> inherit(const std::vector<int>& before, const std::vector<double>& values, int width) const;
  /// The ends of the edge node i was made at (−1, −1 for a coarse node).
  std::array<int, 2> made_at(int i) const;

 private:
  struct Cell {
    std::array<int, 3> v{};
    int parent = -1, root = 0, level = 0;
    /// Its children, kept when coarsening makes it a leaf again (inherit reads them; a new bisection
    /// of it makes new ones).
    std::array<int, 2> child{-1, -1};
    bool is_leaf = true;
  };
  static std::uint64_t key(int a, int b);
  /// The leaf across edge (a, b) from leaf c, −1 on the boundary.
  int neighbour(int c, int a, int b) const;
  /// Bisects leaf c with the closure; counts into `bisected`.
  void bisect(int c, int& bisected);
  /// Splits leaf c at the midpoint of its refinement edge (made if new).
  void split(int c);
  void add_edges(int c);
  void remove_edges(int c);

  const Mesh& coarse_;
  std::vector<Point> x_;
  std::vector<Cell> cells_;
  std::unordered_map<std::uint64_t, std::array<int, 2>> edge_cells_;  // leaf cells on each edge (−1: none)
  std::unordered_map<std::uint64_t, int> midpoint_;                    // an edge's midpoint node, once made
  std::vector<std::array<int, 2>> made_at_;                            // per node made: its edge's ends
  std::vector<char> alive_;                                            // per node: a leaf's vertex
  /// Makes cell c a leaf again (its two children leaves: removed).
  void unsplit(int c);
};

}  // namespace vpc
