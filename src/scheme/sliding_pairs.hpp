#pragma once
// How far a small-sliding pair's slave nodes slide (SPEC §8): with `sliding = "small"` a slave node
// keeps the masters it faced at t = 0, which holds while it slides a fraction of a master facet;
// the run warns past kSmallSlideLimit. Large sliding follows the motion instead (scheme/pair_slider.hpp).
#include "part/mesh_part.hpp"
#include "problem/problem.hpp"
#include "scheme/state.hpp"

#include <span>
#include <vector>

namespace vpc {

/// How far a small-sliding pair's slave nodes have slid from the masters they were coupled to at t = 0.
struct PairSlide {
  std::size_t pair = 0;  // its index in ContactSpec::pairs
  double ratio = 0;  // the largest over its slave nodes of slide / facet (0: none)
  double slide = 0;  // at the node of that ratio: |(I − ν_j ν_jᵀ)(u_j − Σ_k w_k u_k)|
  double facet = 0;  // there, a master facet's size: the largest distance from one of its masters to the nearest other
  int node = -1;     // that slave node, numbered as in the mesh read (−1: none)
  Point x{0, 0, 0};  // its reference position
};

/// With `sliding = "small"` a slave node keeps the masters it faced at t = 0; the run warns when a
/// slave node slides past this fraction of a master facet (docs/cases.md, "Large sliding").
inline constexpr double kSmallSlideLimit = 0.5;

/// Per small-sliding pair of p (ContactSpec::pairs order; large-sliding pairs' rows follow the motion
/// and have none): the largest over its slave nodes j in contact (λ_ν,j > 0: an open node's masters
/// give only its distance, and it is measured again once it touches) of the slide across ν_j
/// relative to the masters' mortar mean, |(I − ν_j ν_jᵀ)(u_j − Σ_k w_k u_k)|, over the size of a
/// master facet at j (PairSlide::facet), from the rows alone (the same on every engine; under MPI
/// the whole mesh is gone), in state s (its u over the part's dofs and its replicated λ), from the
/// part's contact nodes `nodes` (ContactSet::nodes). Collective.
std::vector<PairSlide> small_slides(const Problem& p, const MeshPart& part, std::span<const PartContactNode> nodes,
                                    const State& s);

}  // namespace vpc
