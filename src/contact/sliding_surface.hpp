#pragma once
// The surfaces of a `sliding = "large"` contact pair as a part holds them (MeshPart::sliding, cut with
// the part by part/part_cut.hpp): plain numbers over the part's nodes, from which the slider
// (scheme/pair_slider.hpp) makes the moved mortar surfaces (problem/contact_pairs.hpp).
#include <vector>

namespace vpc {

/// One side of a `sliding = "large"` contact pair as a part holds it for its slider
/// (scheme/pair_slider.hpp), over the part's nodes in the reference configuration.
struct SlidingSurface {
  std::vector<int> nodes;       // the side's nodes (the part's), in order of first appearance
  std::vector<int> facets;      // d per facet: indices into nodes, in the mesh's order
  std::vector<int> cell_nodes;  // per facet, the nodes (the part's) of the cell behind it: its inside
};

/// A large-sliding pair's surfaces on a part that owns some of its slave nodes: the slave facets at
/// those nodes (a row needs the facets at its node alone) and the whole master side (a slave node
/// may slide to any of it).
struct SlidingPairPiece {
  int pair = 0;  // in ContactSpec::pairs
  SlidingSurface slave, master;
};

}  // namespace vpc
