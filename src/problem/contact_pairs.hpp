#pragma once
// The rows of N for contact pairs between bodies (SPEC §8): dual mortar (mortar/) in the
// reference configuration. Each slave node j that the master covers gives the row of the
// constraint D_jj ν_j·u_j − Σ_k M_jk ν_j·u_k ≤ g̃_j divided by D_jj, so that the row is a
// gap and λ_j a nodal force on the slave (D_jj = ∫ N_j over the covered slave: its tributary
// measure), as a row of Γ3 is; the master takes −Σ_j w_jk λ_j ν_j.
#include "contact/sliding_surface.hpp"
#include "mortar/surface.hpp"
#include "problem/contact_rows.hpp"

#include <functional>
#include <string>
#include <vector>

namespace vpc {

/// A boundary part's facets as a mortar surface takes them, before its nodes' positions: its nodes
/// (ids: the mesh's numbers, in order of first appearance), each facet's d nodes (indices into ids,
/// in the mesh's order) and the cell behind each facet (its inside, for the orientation).
struct SurfaceFacets {
  std::vector<int> ids, facets, cells;
};
SurfaceFacets surface_facets(const Mesh& mesh, const std::string& part);

/// The surface of nodes `ids` (at x, one per id) and facets `facets` (d indices into ids each), each
/// facet ordered so that its normal points away from inside[f] (a point of the body behind facet f:
/// its cell's centroid).
mortar::Surface oriented_surface(int d, const std::vector<int>& ids, std::vector<int> facets, std::vector<Point> x,
                                 const std::vector<Point>& inside);

/// A large-sliding pair's side (MeshPart::sliding) with the part's node l at x(l): a mortar surface
/// whose ids are the part's nodes, oriented away from its cells moved alike.
mortar::Surface sliding_surface(int d, int nodes_per_cell, const SlidingSurface& s, const std::function<Point(int)>& x);

/// The mortar surface of a boundary part in the mesh's configuration: its facets (ordered so that
/// their normals point out of the body, from the cells they bound) and their nodes, whose ids are
/// the mesh's node numbers.
mortar::Surface part_surface(const Mesh& mesh, const std::string& part);

/// The prescribed-dof condition of a node (d entries, DirichletDofs::condition's: < 0 free).
using FixedAt = std::function<const int*(int node)>;

/// Appends the rows of pair q of p.contact.pairs between its surfaces `slave` and `master`, in the
/// coupling's slave node order, each with the pair's law lumped over D_jj. A slave node with every
/// component prescribed has no row; a component prescribed at a slave node drops out of the row
/// where it is zero (a clamped part, a symmetry plane) and is refused where it moves; a master
/// node's prescribed components leave N and, where they move, move the row's bound (step_data.cpp).
/// `reference`: the mesh, at t = 0, whose surfaces these are; there a master part that covers no
/// slave node, or a slave node inside the master, is an error naming the pair. Null: surfaces
/// moved by a large-sliding pair's displacement (scheme/pair_slider.hpp), where neither is checked:
/// the last step's answer may penetrate the moved surfaces by its linearization's error, and a
/// slave slid off its master has no rows then.
/// `search`: the distance within which a master facet covers a slave node (search_margin).
void add_pair_rows(const Problem& p, std::size_t q, const mortar::Surface& slave, const mortar::Surface& master,
                   const FixedAt& fixed_at, const Mesh* reference, double search, std::vector<ContactRow>& rows);

/// The pair's search distance: its `search`, or else the longest edge of its slave surface (a
/// large-sliding pair's over every process's piece of it: PairSlider).
double search_margin(const ContactPair& pair, double slave_longest_edge);

/// Rows in increasing node order.
void sort_rows_by_node(std::vector<ContactRow>& rows);

/// The rows of every pair of p.contact.pairs in the reference configuration (add_pair_rows),
/// sorted by node. `condition`: dirichlet_dofs(p).condition.
std::vector<ContactRow> pair_rows(const Problem& p, const std::vector<int>& condition);

}  // namespace vpc
