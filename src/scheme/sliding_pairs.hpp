#pragma once
// Large sliding between bodies (SPEC §8): a `sliding = "large"` pair's rows rebuilt at the start
// of every step by dual mortar between its surfaces moved by the displacement the step starts
// from, x + u_{n−1}: masters, weights, normals, measures and gaps of that configuration. The step's
// constraint is the gap's linearization about it, N_n (u_n − u_{n−1}) ≤ g(x + u_{n−1}), written on
// u_n as N_n u_n ≤ g(x + u_{n−1}) + N_n u_{n−1} (a master's prescribed components move the bound
// by their motion over the step, step_data.cpp); friction's slip is T_n (u_n − u_{n−1}).
#include "scheme/discrete_system.hpp"

namespace vpc {

/// Whether some pair of p slides (ContactPair::large_sliding).
bool slides(const Problem& p);

/// The large-sliding pairs' rows of sys.part.contact in the configuration x + u (u: a state's
/// displacement over the part's dofs, prescribed components included), then sys's N and friction
/// frame (DiscreteSystem::set_contact_rows). The rows, and λ with them, are the slave nodes that had
/// one at t = 0 (the pair's `search` must reach every slave node that may touch): one that no
/// master facet covers within reach now gets no masters and the gap sys.miss_gap (it cannot touch
/// this step); a node without a row at t = 0 gets none. Under MPI rank 0 owns every node of a
/// sliding pair's parts and holds the whole mesh; other ranks only renew N and T.
void slide_pairs(DiscreteSystem& sys, const Vector& u);

}  // namespace vpc
