// Contact pairs between bodies (SPEC §8): the rows of N by dual mortar.
#include "problem/contact_pairs.hpp"

#include "core/error.hpp"
#include "mortar/mortar_coupling.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace vpc {

SurfaceFacets surface_facets(const Mesh& mesh, const std::string& part) {
  const int d = mesh.dim();
  require(d == 2 || d == 3, "contact pairs need a mesh of dimension 2 or 3 (part '{}')", part);
  std::map<int, int> local;  // mesh node -> surface node
  SurfaceFacets s;
  for (int f : mesh.facets_of_parts({part})) {
    for (int a = 0; a < d; ++a) {
      const auto [it, fresh] = local.emplace(mesh.facet(f)[a], static_cast<int>(s.ids.size()));
      if (fresh) s.ids.push_back(mesh.facet(f)[a]);
      s.facets.push_back(it->second);
    }
    s.cells.push_back(mesh.facet_cell(f));
  }
  return s;
}

mortar::Surface oriented_surface(int d, const std::vector<int>& ids, std::vector<int> facets, std::vector<Point> x,
                                 const std::vector<Point>& inside) {
  mortar::orient_away_from(d, x, facets, inside);
  return mortar::Surface(d, std::move(x), ids, std::move(facets), mortar::FacetOrder::Outward);
}

mortar::Surface sliding_surface(int d, int nodes_per_cell, const SlidingSurface& s, const std::function<Point(int)>& x) {
  std::vector<Point> nodes, inside;
  for (int l : s.nodes) nodes.push_back(x(l));
  const auto npc = static_cast<std::size_t>(nodes_per_cell);
  std::vector<Point> cell(npc);
  std::vector<int> order(npc);
  std::iota(order.begin(), order.end(), 0);
  for (std::size_t f = 0; f < s.cell_nodes.size() / npc; ++f) {
    for (std::size_t a = 0; a < npc; ++a) cell[a] = x(s.cell_nodes[f * npc + a]);
    inside.push_back(centroid(cell, order.data(), nodes_per_cell));
  }
  return oriented_surface(d, s.nodes, s.facets, std::move(nodes), inside);
}

mortar::Surface part_surface(const Mesh& mesh, const std::string& part) {
  const SurfaceFacets s = surface_facets(mesh, part);
  std::vector<Point> x, inside;
  for (int node : s.ids) x.push_back(mesh.node(node));
  for (int c : s.cells) inside.push_back(mesh.cell_centroid(c));
  return oriented_surface(mesh.dim(), s.ids, s.facets, std::move(x), inside);
}

namespace {

/// A component prescribed at a slave node by a [[boundary.displacement]] (condition k > 0: the
/// k-th; taken as moving) is right only where the pair's constraints do not see it: the
/// normal row ν_j·u_j − Σ_k w_k ν_j·u_k ≤ g holds u_j's components along ν_j alone, so a motion
/// across ν_j (a slave face slid along itself) leaves the row as it is and only moves the body. Refused
/// where ν_j has a component along it (the row would need the motion in its bound), under friction
/// (the slip t_j·(Δu_j − Σ_k w_k Δu_k) along it would miss the motion: the frame keeps free components
/// only) and under large sliding (the normal of a later step may turn towards it).
void check_slave_motion(const Problem& p, std::size_t q, int node, const Point& normal, const int* fixed) {
  const ContactPair& pair = p.contact.pairs[q];
  const bool frictional = p.contact.frictions()[static_cast<std::size_t>(p.contact.pair_law_index(q))] != nullptr;
  for (int i = 0; i < p.mesh.dim(); ++i) {
    if (fixed[i] <= 0) continue;  // free, or prescribed zero (clamped, a symmetry plane)
    const char* why = normal[i] != 0 ? "its normal ({:.6g}, {:.6g}, {:.6g}) has a component along it"
                      : frictional   ? "the pair has friction, whose slip along it would not see the motion"
                      : pair.large_sliding ? "the pair slides large, whose normal may turn towards it"
                                           : nullptr;
    if (why == nullptr) continue;
    const Point& x = p.mesh.node(node);
    fail("{}: u{} of slave node {} ({}, {}, {}) of '{}' is prescribed by this displacement, but {}; a contact "
         "pair's slave nodes may be clamped ([boundary] clamped), on a symmetry plane, or moved by a "
         "[[boundary.displacement]] across their normal in a frictionless pair with sliding = \"small\" ({}: make the moved part the master, or drive the body through another part)",
         p.where(fmt::format("boundary.displacement[{}]", fixed[i] - 1)), "xyz"[i], p.node_number(node), x[0], x[1],
         x[2], pair.slave, fmt::format(fmt::runtime(why), normal[0], normal[1], normal[2]),
         p.where(fmt::format("contact.pair[{}]", q)));
  }
}

}  // namespace

void add_pair_rows(const Problem& p, std::size_t q, const mortar::Surface& slave, const mortar::Surface& master,
                   const FixedAt& fixed_at, const Mesh* reference, double search, std::vector<ContactRow>& rows) {
  const bool moved = reference == nullptr;
  const int d = slave.dim();
  const ContactPair& pair = p.contact.pairs[q];
  const std::string where = p.where(fmt::format("contact.pair[{}]", q));
  mortar::MortarOptions options;
  options.search_margin = search;
  const mortar::MortarCoupling c = located(where, [&] { return mortar::mortar_coupling(slave, master, options); });
  const ContactLaw& law = *p.contact.laws()[static_cast<std::size_t>(p.contact.pair_law_index(q))];
  std::map<int, std::vector<std::pair<int, double>>> masters;  // slave node -> (master node, M_jk)
  for (const auto& t : c.m) masters[t.row()].emplace_back(t.col(), t.value());
  std::size_t covered = 0;
  const std::size_t first = rows.size();
  for (const mortar::SlaveNodeCoupling& s : c.nodes) {
    if (!(s.d > 0)) continue;  // no master facet covers it: no constraint
    ++covered;
    const int* fixed = fixed_at(s.id);
    if (std::all_of(fixed, fixed + d, [](int k) { return k >= 0; })) continue;  // u prescribed there
    ContactRow row;
    row.node = s.id;
    row.direction = s.normal;
    if (!moved) check_slave_motion(p, q, s.id, s.normal, fixed);
    // A component prescribed zero at the slave node (a symmetry plane) leaves the normal, as on Γ3.
    for (int i = 0; i < d; ++i)
      if (fixed[i] >= 0) row.direction[i] = 0;
    const double l = std::hypot(row.direction[0], row.direction[1], row.direction[2]);
    require(l > 0, "{}: slave node {} has every component of its normal prescribed", where, s.id);
    for (double& v : row.direction) v /= l;
    row.gap = s.gap / s.d;
    row.measure = s.d;
    // At t = 0 the bodies must not overlap, as a body and an obstacle must not (docs/cases.md): the
    // solver would push them apart by the overlap, a force nothing asked for. A gap above −1 % of
    // the node's mesh size (D_jj^(1/(d−1))) is the round-off of curved surfaces meshed apart.
    if (!moved && row.gap < -1e-2 * std::pow(s.d, 1.0 / (d - 1))) {
      const Point& x = reference->node(s.id);
      fail("{}: slave node {} ({}, {}, {}) of '{}' lies {:.6g} inside the master part '{}' at t = 0 (its weighted "
           "gap); at t = 0 the bodies of a pair must not overlap: move one of them apart",
           where, s.id, x[0], x[1], x[2], pair.slave, -row.gap, pair.master);
    }
    row.pair = static_cast<int>(q);
    // The pair's law, its datum lumped at the node over its covered measure D_jj (k_j = c D_jj for a compliance).
    row.law = p.contact.pair_law_index(q);
    row.datum = law.lumped(s.d, 1);
    row.obstacles = 0;
    // A master node's prescribed components leave N (its free dofs alone) and, where they move,
    // move the bound instead (step_data.cpp: add_master_motion).
    for (const auto& [k, m] : masters[s.id]) row.masters.emplace_back(k, m / s.d);
    rows.push_back(std::move(row));
  }
  // At t = 0 a pair whose master covers nothing is a mistake; in a large-sliding step the slave may
  // have slid off its master, and then its nodes are simply inactive (PairSlider).
  require(covered > 0 || moved, "{}: master part '{}' covers no node of slave part '{}' (their facets must face "
          "each other within the search distance {:.6g}: [[contact.pair]] search)", where, pair.master, pair.slave,
          options.search_margin);
  require(rows.size() > first || moved, "{}: every node of slave part '{}' that the master part '{}' covers has "
          "every component prescribed ([boundary]): the pair would constrain nothing", where, pair.slave, pair.master);
}

double search_margin(const ContactPair& pair, double slave_longest_edge) {
  return pair.search > 0 ? pair.search : slave_longest_edge;
}

void sort_rows_by_node(std::vector<ContactRow>& rows) {
  std::sort(rows.begin(), rows.end(), [](const ContactRow& a, const ContactRow& b) { return a.node < b.node; });
}

std::vector<ContactRow> pair_rows(const Problem& p, const std::vector<int>& condition) {
  const int d = p.mesh.dim();
  const FixedAt fixed_at = [&](int node) { return condition.data() + static_cast<std::size_t>(node) * d; };
  std::vector<ContactRow> rows;
  for (std::size_t q = 0; q < p.contact.pairs.size(); ++q) {
    const ContactPair& pair = p.contact.pairs[q];
    const std::string where = p.where(fmt::format("contact.pair[{}]", q));
    const mortar::Surface slave = located(where, [&] { return part_surface(p.mesh, pair.slave); });
    const mortar::Surface master = located(where, [&] { return part_surface(p.mesh, pair.master); });
    add_pair_rows(p, q, slave, master, fixed_at, &p.mesh, search_margin(pair, slave.longest_edge()), rows);
  }
  sort_rows_by_node(rows);
  return rows;
}

}  // namespace vpc
