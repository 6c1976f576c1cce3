#pragma once
// Uniform red refinement of simplicial meshes (d = 1, 2, 3) and the exact transfers
// between the nested meshes it produces.
//
// Every edge is halved. A segment gives 2 children, a triangle 4 (three corner
// triangles and the middle one), a tetrahedron 8 (Bey's red refinement: four corner
// tetrahedra and the inner octahedron split along its shortest diagonal). The fine
// mesh is therefore nested in the coarse one for any simplicial mesh, so that
//   - P1 functions prolong exactly: a fine node is a coarse node (same value) or the
//     midpoint of a coarse edge (mean of the two end values), and
//   - P0 functions prolong exactly: a fine cell lies in one coarse cell (its parent).
// Boundary facets split like cells of one dimension less and keep their part, so Γ1,
// Γ2, Γ3 of a case are the same sets on every level; cells keep their region (material).
#include "fem/assembly.hpp"
#include "mesh/mesh.hpp"

#include <array>
#include <vector>

namespace vpc {

/// One refinement step: the fine mesh and how it sits in the coarse one.
struct Refinement {
  Mesh fine;
  /// Coarse cell that contains each fine cell.
  std::vector<int> parent_cell;
  /// For each fine node, the two coarse nodes whose mean it is (a, a) for a node
  /// that is already a coarse node. Coarse nodes keep their numbers: fine node i is
  /// coarse node i for i < coarse.n_nodes().
  std::vector<std::array<int, 2>> node_parents;
  /// Coarse facet of each fine boundary facet.
  std::vector<int> parent_facet;
};

/// Red refinement of `coarse` (see the file comment).
Refinement refine_uniform(const Mesh& coarse);

/// Prolongs a P1 field with `components` values per node (node-major: node * c + i)
/// from the coarse to the fine mesh of `r`. Exact for P1 functions.
Vector prolong_p1(const Refinement& r, const Vector& coarse, int components = 1);

/// Prolongs P0 (per-cell) values: fine cell c takes the value of its parent.
template <typename T>
std::vector<T> prolong_p0(const Refinement& r, const std::vector<T>& coarse) {
  std::vector<T> fine(r.parent_cell.size());
  for (size_t c = 0; c < fine.size(); ++c) fine[c] = coarse[r.parent_cell[c]];
  return fine;
}

/// A sequence of meshes, each the red refinement of the previous one.
class MeshHierarchy {
 public:
  /// `n_refinements` red refinements of `base`: levels 0 .. n_refinements.
  MeshHierarchy(const Mesh& base, int n_refinements);

  int n_levels() const { return static_cast<int>(meshes_.size()); }
  const Mesh& mesh(int level) const { return meshes_[level]; }
  /// The refinement from level l to level l + 1.
  const Refinement& refinement(int level) const { return refinements_[level]; }

  /// P1 field on level `from` prolonged to level `to` >= from.
  Vector prolong_p1(const Vector& v, int from, int to, int components = 1) const;
  /// For every cell of level `to`, its ancestor cell on level `from` <= to.
  const std::vector<int>& ancestors(int from, int to) const;
  /// P0 values on level `from` prolonged to level `to` >= from.
  template <typename T>
  std::vector<T> prolong_p0(const std::vector<T>& v, int from, int to) const {
    const std::vector<int>& a = ancestors(from, to);
    std::vector<T> out(a.size());
    for (size_t c = 0; c < a.size(); ++c) out[c] = v[a[c]];
    return out;
  }

 private:
  std::vector<Mesh> meshes_;
  std::vector<Refinement> refinements_;
  mutable std::vector<std::vector<std::vector<int>>> ancestors_;  // [from][to], computed lazily
};

}  // namespace vpc
