#pragma once
// A facet as a key: its node indices sorted, so that a face of a cell and a boundary
// element of a Gmsh group with the same nodes in another order meet in one map entry
// (Mesh::build_boundary, the facets' cells, the Gmsh reader's parts).
#include <array>
#include <cstddef>
#include <utility>

namespace vpc {

/// Sorted node indices of a facet (at most 3 nodes; unused entries −1).
using FacetKey = std::array<int, 3>;

/// The key of the facet with the `n` nodes `nodes`.
inline FacetKey facet_key(const int* nodes, int n) {
  FacetKey k{-1, -1, -1};
  for (int i = 0; i < n; ++i) k[i] = nodes[i];
  // Insertion sort (std::sort on three entries trips g++ 12's -Warray-bounds).
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && k[j - 1] > k[j]; --j) std::swap(k[j - 1], k[j]);
  return k;
}

/// FNV-1a over the three entries, for unordered maps of facets.
struct FacetKeyHash {
  std::size_t operator()(const FacetKey& k) const {
    std::size_t h = 1469598103934665603ull;
    for (int v : k) h = (h ^ static_cast<std::size_t>(v + 1)) * 1099511628211ull;
    return h;
  }
};

/// The nodes of facet i of a simplex with `n_per_cell` nodes: all but local vertex i.
inline void cell_facet(const int* cell, int n_per_cell, int i, int* out) {
  int m = 0;
  for (int j = 0; j < n_per_cell; ++j)
    if (j != i) out[m++] = cell[j];
}

}  // namespace vpc
