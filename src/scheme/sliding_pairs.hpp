#pragma once
// Large sliding between bodies (SPEC §8): a `sliding = "large"` pair's rows rebuilt at the start
// of every step by dual mortar between its surfaces moved by the displacement the step starts
// from, x + u_{n−1}: masters, weights, normals, measures and gaps of that configuration. The step's
// constraint is the gap's linearization about it, N_n (u_n − u_{n−1}) ≤ g(x + u_{n−1}), written on
// u_n as N_n u_n ≤ g(x + u_{n−1}) + N_n u_{n−1} (a master's prescribed components move the bound
// by their motion over the step, step_data.cpp); friction's slip is T_n (u_n − u_{n−1}).
#include "scheme/discrete_system.hpp"
#include "scheme/state.hpp"

namespace vpc {

/// Whether some pair of p slides (ContactPair::large_sliding).
bool slides(const Problem& p);

/// The large-sliding pairs' rows of sys.part.contact in the configuration x + u (u: a state's
/// displacement over the part's dofs, prescribed components included), then sys's N and friction
/// frame (ContactSet::set_rows). The rows, and λ with them, are the slave nodes that had
/// one at t = 0 (the pair's `search` must reach every slave node that may touch): one that no
/// master facet covers within reach now gets no masters and the gap sys.contact.miss_gap (it cannot touch
/// this step); a node without a row at t = 0 gets none. Under MPI rank 0 owns every node of a
/// sliding pair's parts and holds the whole mesh; other ranks only renew N and T.
void slide_pairs(DiscreteSystem& sys, const Vector& u);

/// How far a small-sliding pair's slave nodes have slid from the masters they were coupled to at t = 0.
struct PairSlide {
  double ratio = 0;  // the largest over its slave nodes of slide / facet (0: none, or large sliding)
  double slide = 0;  // at the node of that ratio: |(I − ν_j ν_jᵀ)(u_j − Σ_k w_k u_k)|
  double facet = 0;  // there, a master facet's size: the largest distance from one of its masters to the nearest other
  int node = -1;     // that slave node, numbered as in the mesh read (−1: none)
  Point x{0, 0, 0};  // its reference position
};

/// With `sliding = "small"` a slave node keeps the masters it faced at t = 0; the run warns when a
/// slave node slides past this fraction of a master facet (docs/cases.md, "Large sliding").
inline constexpr double kSmallSlideLimit = 0.5;

/// Per pair of p (ContactSpec::pairs order; ratio 0 for a large-sliding pair, whose rows follow the
/// motion): the largest over its slave nodes j in contact (λ_ν,j > 0: an open node's masters give only
/// its distance, and it is measured again once it touches) of the slide across ν_j relative to the masters' mortar
/// mean, |(I − ν_j ν_jᵀ)(u_j − Σ_k w_k u_k)|, over the size of a master facet at j (PairSlide::facet),
/// from the rows alone (the same on every engine; under MPI the whole mesh is gone), in state s
/// (its u over the part's dofs, as slide_pairs', and its replicated λ); empty where no pair
/// slides small (none, or all large). Collective.
std::vector<PairSlide> small_slides(const Problem& p, const MeshPart& part, const State& s);

}  // namespace vpc
