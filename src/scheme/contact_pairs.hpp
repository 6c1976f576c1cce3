#pragma once
// The rows of N for contact pairs between bodies (SPEC §8): dual mortar (mortar/) in the
// reference configuration. Each slave node j that the master covers gives the row of the
// constraint D_jj ν_j·u_j − Σ_k M_jk ν_j·u_k ≤ g̃_j divided by D_jj, so that the row is a
// gap and λ_j a nodal force on the slave (D_jj = ∫ N_j over the covered slave: its tributary
// measure), as a row of Γ3 is; the master takes −Σ_j w_jk λ_j ν_j.
#include "mortar/surface.hpp"
#include "scheme/contact_rows.hpp"

#include <string>
#include <vector>

namespace vpc {

/// The mortar surface of a boundary part: its facets (ordered so that their normals point out
/// of the body, from the cells they bound) and their nodes, whose ids are the mesh's node numbers.
mortar::Surface part_surface(const Mesh& mesh, const std::string& part);

/// The rows of every pair of p.contact.pairs, in increasing slave node order within a pair, each
/// with its pair's law lumped over D_jj. A slave node with every component prescribed has no row;
/// a component prescribed at a slave node drops out of the row where it is zero (a clamped part, a
/// symmetry plane) and is refused where it moves; a master node's prescribed components leave N
/// and, where they move, move the row's bound (step_data.cpp). Throws vpc::Error naming the pair
/// for a master part that covers no slave node, or a slave node inside the master at t = 0.
/// `moved`: p.mesh displaced (x + u): the rows of the large-sliding pairs alone, in that
/// configuration (scheme/sliding_pairs.hpp; no overlap check: the last step's answer may
/// penetrate the moved surfaces by its linearization's error, and no coverage check: a slave slid
/// off its master has no rows then).
std::vector<ContactRow> pair_rows(const Problem& p, const std::vector<int>& condition, const Mesh* moved = nullptr);

}  // namespace vpc
