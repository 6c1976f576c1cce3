#pragma once
// A contact node's block: what the contact rows of the whole mesh (problem/contact_rows.hpp) and
// a part's contact nodes (part/mesh_part.hpp) carry, each in its own numbering.
#include "contact/obstacle.hpp"
#include "mesh/mesh.hpp"

#include <utility>
#include <vector>

namespace vpc {

/// One contact node's block (SPEC (3.9)), whatever numbering it is in: its unit direction ν (the
/// given one, or the measure-weighted mean of the outward normals of its Γ3 facets), its gap g,
/// its measure, its law and the law's datum, its obstacles and, on a pair, its masters. The whole
/// mesh's rows (ContactRow) and a part's nodes (PartContactNode, part/mesh_part.hpp) are this
/// block with their own numbering.
struct ContactNode {
  Point direction{0, 0, 0};
  double gap = 0;
  /// Its tributary measure: on Γ3 tributary_measures' (the contact pressure is λ over it), on a
  /// pair D_jj, the covered slave measure.
  double measure = 0;
  /// The law at the node (its index in ContactSpec::laws(): a rigid one where any of its Γ3
  /// facets has one) and its per-node datum, Σ ContactLaw::lumped over the node's Γ3 facets of
  /// that kind (rigid or compliant), whose meaning the law defines (k_i = c |Γ3|_i for normal
  /// compliance, 0 for Signorini).
  int law = 0;
  double datum = 0;
  ObstacleMask obstacles = kAllObstacles;  // the obstacles acting on the node's parts
  /// A contact pair's row (SPEC §8): its master nodes k and weights w_k = M_jk / D_jj, the row
  /// ν·u_j − Σ_k w_k ν·u_k ≤ g (g = g̃_j / D_jj: a gap, λ a nodal force as on Γ3). Empty on Γ3.
  std::vector<std::pair<int, double>> masters;
  int pair = -1;  // its index in ContactSpec::pairs (−1: Γ3)
};

/// A row of the contact matrix N of (3.9) on the whole mesh (problem/contact_rows.hpp builds them):
/// a node of Γ3 that is not clamped, or a pair's covered slave node, with its block; masters are
/// numbered as the mesh's nodes.
struct ContactRow : ContactNode {
  int node = 0;
};

}  // namespace vpc
