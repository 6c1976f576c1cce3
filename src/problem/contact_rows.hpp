#pragma once
// The contact rows of (3.9), from the problem: per node of Γ3 its direction, gap and law.
#include "contact/contact_node.hpp"
#include "problem/problem.hpp"

#include <vector>

namespace vpc {

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
