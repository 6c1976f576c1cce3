#pragma once
// The contact rows of (3.9), from the problem: per node of Γ3 its direction, gap and law.
#include "scheme/problem.hpp"

#include <vector>

namespace vpc {

/// A row of the contact matrix N of (3.9): a node of Γ3 that is not clamped, its
/// unit direction ν (the given one, or the measure-weighted mean of the outward
/// normals of its Γ3 facets), its gap g, its contact law and its obstacles.
struct ContactRow {
  int node = 0;
  Point direction{0, 0, 0};
  double gap = 0;
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
  int pair = -1;       // its index in ContactSpec::pairs (−1: Γ3)
  double measure = 0;  // a pair's row: D_jj, its tributary measure on the covered slave (Γ3's: tributary_measures)
};

/// The contact rows in increasing node order, for the nodes of Γ3 with a free
/// component (`condition`: DirichletDofs::condition). At a node on a symmetry plane
/// the outward normal loses its component across the plane (the mirrored half's
/// facets would cancel it); any other direction with a component along a prescribed
/// one is refused. Throws vpc::Error for that, for a fixed direction at 90° or more
/// from the outward normal at some node (it would point into the body), for a gap
/// below 0 at t = 0, for a node where parts of laws that cannot share it meet
/// (ContactLaw::conflict: e.g. compliance laws of different exponents) and when no free
/// node is left on Γ3.
std::vector<ContactRow> contact_rows(const Problem& p, const std::vector<int>& condition);

/// How many times contact_rows has run in this process: a set-up runs it once (tests count it).
long long contact_rows_builds();

/// The rows a set-up hands over (`built`: Problem::validate's, Case::contact_rows), or where it
/// hands none (null), p's built here for `condition` (contact_rows).
ContactRows contact_rows_of(const Problem& p, const std::vector<int>& condition, const ContactRows& built);

/// contact_rows' error where Γ3 has no free node: every component of each of its nodes (of p.mesh)
/// prescribed, naming the keys that prescribe them.
[[noreturn]] void fail_no_free_contact_node(const Problem& p, const std::vector<int>& condition);

/// The tributary measure of each node on the facets of `parts` (Γ3): the sum over
/// those facets containing the node of facet measure / vertices per facet (a
/// length in 2D, an area in 3D, 1 in 1D); 0 at the other nodes. A uniform
/// pressure p on Γ3 has the P1 nodal forces p × this measure, so a nodal force
/// divided by it is the contact pressure (VTU field contact_pressure).
std::vector<double> tributary_measures(const Mesh& mesh, const std::vector<std::string>& parts);

}  // namespace vpc
