#pragma once
// Conforming newest-vertex bisection of a triangle or tetrahedron mesh (issue 51: local refinement and
// coarsening for the adaptive run).
//
// 2D. Each triangle (v0, v1, v2) is bisected across its
// refinement edge v0–v1 at its midpoint m into (v2, v0, m) and (v1, v2, m): the new vertex m is each
// child's peak, and each child's refinement edge is one of the parent's other edges. A triangle whose
// refinement-edge neighbour has another refinement edge bisects that neighbour first (its child across the
// edge then has it as its own), so the leaves stay conforming: no hanging node (Mitchell 1991; Binev, Dahmen,
// DeVore 2004). The coarse mesh's labelling takes each triangle's longest edge as its refinement edge, ties
// broken by the least (smaller, larger) pair of coarse node numbers: the same on every rank, and it makes
// the closure terminate. A triangle's descendants fall into finitely many similarity classes (at most 4 per
// coarse triangle), so their angles stay bounded below by the coarse mesh's (tested 30 levels deep).
//
// 3D. Maubach's bisection of tagged simplices (Maubach 1995; Kossaczký's form, as ALBERTA's): a tetrahedron
// (x0, x1, x2, x3) of generation g is bisected at the midpoint z of its refinement edge x0–x3 into
// (x0, z, x1, x2) and (x3, z, x2, x1) when g ≡ 0 (mod 3), (x3, z, x1, x2) otherwise; each child is of
// generation g + 1, z its newest vertex. The descendants of one tetrahedron fall into finitely many
// similarity classes (Arnold, Mukherjee & Pouly 2000: at most 36), so the dihedral angles stay bounded below
// by a bound set by the coarse mesh (tested 30 generations deep). The initial labelling works on any
// conforming mesh and depends on the global node numbers only (not on a partition): each coarse
// tetrahedron's vertices in increasing node number, generation 0 — the labelling of Alkämper, Gaspoz &
// Klöfkorn (SIAM J. Sci. Comput. 40, 2018), which satisfies their weak compatibility condition, under which
// the closure below terminates. The closure bisects every leaf around the refinement edge at that edge,
// bisecting first (recursively) those whose own refinement edge is another; a closure deeper than any
// such labelling needs is reported as an error, never a hang.
//
// The refinement is kept as a forest over the coarse cells (each cell's parent, children and level), so that
// the leaves' data can be carried from parents to children (and back, by coarsening, later), and a leaf mesh
// (BisectionForest::leaf_mesh) keeps the coarse mesh's boundary parts (a bisected boundary facet's halves
// keep its part), regions and bodies.
#include "mesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

namespace vpc {

class BisectionForest {
 public:
  /// The forest of `coarse` (triangles or tetrahedra): every coarse cell a root, labelled (see above).
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
  /// Cell c's measure (area in 2D, volume in 3D).
  double area(int c) const;
  /// Whether node i is a vertex of the leaves (a node removed by coarsening keeps its number, unused).
  bool node_alive(int i) const { return alive_[static_cast<std::size_t>(i)] != 0; }
  /// The leaf mesh's number of each node (−1 where it is not alive).
  std::vector<int> mesh_numbers() const;

  int n_cells() const { return static_cast<int>(cells_.size()); }
  int n_nodes() const { return static_cast<int>(x_.size()); }
  const Point& node(int i) const { return x_[static_cast<std::size_t>(i)]; }
  /// Cell c's vertices: 2D (v0, v1, v2), the refinement edge v0–v1, the peak (newest vertex) v2,
  /// counterclockwise; 3D (x0, x1, x2, x3) in Maubach's order, the refinement edge x0–x3, the newest vertex x1.
  std::span<const int> vertices(int c) const {
    return {cells_[static_cast<std::size_t>(c)].v.data(), static_cast<std::size_t>(dim_ + 1)};
  }
  /// The ends of cell c's refinement edge.
  std::array<int, 2> refinement_edge(int c) const;
  /// Cell c's newest vertex (the midpoint its parent's bisection made, for a cell that has a parent).
  int newest_vertex(int c) const { return vertices(c)[dim_ == 2 ? 2 : 1]; }
  int dim() const { return dim_; }
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

  /// The smallest interior angle (2D) or dihedral angle (3D) over the leaves (radians).
  double min_angle() const;
  /// 3D: cell c's dihedral angle at its edge (vertices(c)[i], vertices(c)[j]) (radians).
  double dihedral_angle(int c, int i, int j) const;

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
    std::array<int, 4> v{-1, -1, -1, -1};
    /// 3D: the coarse boundary facet each face (opposite v[k]) lies in, −1 inside the domain.
    std::array<int, 4> facet{-1, -1, -1, -1};
    int parent = -1, root = 0, level = 0;
    /// Its children, kept when coarsening makes it a leaf again (inherit reads them; a new bisection
    /// of it makes new ones).
    std::array<int, 2> child{-1, -1};
    bool is_leaf = true;
  };
  static std::uint64_t key(int a, int b);
  /// Bisects leaf c with the closure (depth: the closure's recursion, bounded); counts into `bisected`.
  void bisect(int c, int& bisected, int depth);
  /// Splits leaf c at the midpoint of its refinement edge (made if new).
  void split(int c);
  void add_edges(int c);
  void remove_edges(int c);

  /// 3D: the faces of a child (its vertices `cv`) in the coarse boundary facets, from its parent's.
  std::array<int, 4> child_facets(const Cell& parent, const std::array<int, 4>& cv, int m) const;
  void add_facets_3d(Mesh& mesh, const std::vector<int>& cells, const std::vector<int>& number) const;

  const Mesh& coarse_;
  int dim_ = 2;
  std::vector<Point> x_;
  std::vector<Cell> cells_;
  std::unordered_map<std::uint64_t, std::vector<int>> edge_cells_;   // the leaves at each edge
  std::unordered_map<std::uint64_t, int> midpoint_;                    // an edge's midpoint node, once made
  std::vector<std::array<int, 2>> made_at_;                            // per node made: its edge's ends
  std::vector<char> alive_;                                            // per node: a leaf's vertex
  /// Makes cell c a leaf again (its two children leaves: removed).
  void unsplit(int c);
};

}  // namespace vpc
