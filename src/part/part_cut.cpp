#include "part/part_cut.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <unordered_map>

namespace vpc {

// The order of the calls is the order of their checks (the first error is the one reported).
WholeMeshData::WholeMeshData(const Problem& p, ContactRows built)
    : cell_material(cell_materials(p)),
      cell_body(cell_bodies(p.mesh)),
      traction_facets(vpc::traction_facets(p)),
      pressure_facets(vpc::pressure_facets(p)),
      dirichlet(dirichlet_dofs(p)),
      shared_rows(contact_rows_of(p, dirichlet.condition, built)),
      rows(*shared_rows),
      row_of(p.mesh.n_nodes(), -1) {
  for (std::size_t k = 0; k < rows.size(); ++k) row_of[rows[k].node] = static_cast<int>(k);
  for (const std::size_t q : p.contact.sliding_pairs(true)) {
    const ContactPair& pair = p.contact.pairs[q];
    located(p.where(fmt::format("contact.pair[{}]", q)), [&] {
      sliding.push_back({static_cast<int>(q), surface_facets(p.mesh, pair.slave), surface_facets(p.mesh, pair.master)});
    });
  }
}

int free_components(const DirichletDofs& dirichlet, int node, int dim) {
  const auto begin = dirichlet.condition.begin() + static_cast<std::ptrdiff_t>(node) * dim;
  return static_cast<int>(std::count(begin, begin + dim, -1));
}

WholeNumbering::WholeNumbering(const std::vector<std::vector<int>>& owned, const DirichletDofs& dirichlet, int dim,
                               long long first_node, long long first_free) {
  const std::size_t n_nodes = dirichlet.condition.size() / static_cast<std::size_t>(dim);
  node.assign(n_nodes, -1);
  first_dof.assign(n_nodes, -1);
  long long next_node = first_node;
  n_dofs = first_free;
  for (const std::vector<int>& nodes : owned)
    for (int i : nodes) {
      node[i] = next_node++;
      if (const int k = free_components(dirichlet, i, dim); k > 0) {
        first_dof[i] = n_dofs;
        n_dofs += k;
      }
    }
}

PartContactNode part_contact_node(int k, const ContactRow& row, int local_node, bool owned) {
  PartContactNode node;
  static_cast<ContactNode&>(node) = row;
  node.masters.clear();  // numbered as the part's nodes by cut_part
  node.row = k;
  node.local_node = local_node;
  node.owned = owned;
  return node;
}

void add_loaded_facet(PartPieces& pieces, Mesh& mesh, const int* nodes, int load) {
  mesh.add_facet(nodes, load == 0 ? "traction" : fmt::format("pressure{}", load));
  (load == 0 ? pieces.traction_facets : pieces.pressure_facets[static_cast<std::size_t>(load) - 1]).push_back(mesh.n_facets() - 1);
}

namespace {

/// The facets of a large-sliding pair's side that a part takes (MeshPart::sliding): every master
/// facet, and on the slave side those that touch a facet at a node it owns (`owns`, a whole-mesh
/// node): a row's weights integrate over the facets at its node, whose normals are interpolated
/// from nodal normals averaged over the facets at their nodes. Calls f(facet).
template <typename Owns, typename F>
void piece_facets(const SurfaceFacets& side, int d, bool slave, const Owns& owns, F&& f) {
  const std::size_t n = side.cells.size();
  auto nodes = [&](std::size_t k) { return std::span(side.facets.data() + k * static_cast<std::size_t>(d), d); };
  std::vector<char> near(slave ? side.ids.size() : 0, 0);  // per side node: on a facet at an owned node
  for (std::size_t k = 0; k < n && slave; ++k)
    if (std::ranges::any_of(nodes(k), [&](int i) { return owns(side.ids[static_cast<std::size_t>(i)]); }))
      for (int i : nodes(k)) near[static_cast<std::size_t>(i)] = 1;
  for (std::size_t k = 0; k < n; ++k)
    if (!slave || std::ranges::any_of(nodes(k), [&](int i) { return near[static_cast<std::size_t>(i)] != 0; })) f(k);
}

/// The part's piece of a large-sliding pair `s` (WholeMeshData::sliding); none where it owns no
/// slave node. `local`: the whole mesh's node -> the part's; `n_owned`: the part's owned nodes.
std::optional<SlidingPairPiece> sliding_piece(const Mesh& mesh, const WholeMeshData::SlidingPair& s,
                                              const std::unordered_map<int, int>& local, int n_owned) {
  const int d = mesh.dim(), npc = mesh.nodes_per_cell();
  auto part_node = [&](int v) {
    const auto it = local.find(v);
    require(it != local.end(), "internal: node {} of sliding contact pair {}'s surfaces is not in the part", v, s.pair);
    return it->second;
  };
  const auto owns = [&](int v) {
    const auto it = local.find(v);
    return it != local.end() && it->second < n_owned;
  };
  auto side = [&](const SurfaceFacets& from, bool slave) {
    SlidingSurface to;
    std::unordered_map<int, int> index;  // the part's node -> its index in to.nodes
    piece_facets(from, d, slave, owns, [&](std::size_t f) {
      for (int a = 0; a < d; ++a) {
        const int l = part_node(from.ids[static_cast<std::size_t>(from.facets[f * d + a])]);
        const auto [it, fresh] = index.emplace(l, static_cast<int>(to.nodes.size()));
        if (fresh) to.nodes.push_back(l);
        to.facets.push_back(it->second);
      }
      for (int a = 0; a < npc; ++a) to.cell_nodes.push_back(part_node(mesh.cell(from.cells[f])[a]));
    });
    return to;
  };
  SlidingPairPiece piece;
  piece.pair = s.pair;
  piece.slave = side(s.slave, true);
  if (piece.slave.facets.empty()) return std::nullopt;
  piece.master = side(s.master, false);
  return piece;
}

}  // namespace

std::vector<int> sliding_band(const Mesh& mesh, const WholeMeshData& whole, const std::function<bool(int)>& owns) {
  const int d = mesh.dim(), npc = mesh.nodes_per_cell();
  std::vector<int> band;
  for (const WholeMeshData::SlidingPair& s : whole.sliding) {
    bool any = false;
    piece_facets(s.slave, d, true, owns, [&](std::size_t) { any = true; });
    if (!any) continue;
    for (const SurfaceFacets* side : {&s.slave, &s.master})
      piece_facets(*side, d, side == &s.slave, owns, [&](std::size_t f) {
        for (int a = 0; a < npc; ++a) band.push_back(mesh.cell(side->cells[f])[a]);  // its facet's nodes among them
      });
  }
  std::sort(band.begin(), band.end());
  band.erase(std::unique(band.begin(), band.end()), band.end());
  return band;
}

PartPieces cut_part(const Problem& p, const WholeMeshData& whole, const WholeNumbering& numbering,
                    const std::vector<int>& nodes, int n_owned, const std::vector<int>& cells) {
  const int d = p.mesh.dim();
  const DirichletDofs& dirichlet = whole.dirichlet;
  PartPieces part;
  part.n_owned_nodes = n_owned;
  for (std::size_t a = 0; a < nodes.size(); ++a) {
    const int v = nodes[a];
    part.global_node.push_back(numbering.node[v]);
    part.original_node.push_back(v);
    part.first_dof.push_back(numbering.first_dof[v]);
    part.dirichlet_on_parts.push_back(dirichlet.on_parts[v]);
    const auto begin = dirichlet.condition.begin() + static_cast<std::ptrdiff_t>(v) * d;
    part.dirichlet.insert(part.dirichlet.end(), begin, begin + d);
    if (const int k = whole.row_of[v]; k >= 0)
      part.contact.push_back(part_contact_node(k, whole.rows[k], static_cast<int>(a), a < static_cast<std::size_t>(n_owned)));
  }
  // An owned pair row's master nodes in the part's numbering: they are owned with the row
  // (own_pairs_together in parallel/distributed_mesh.cpp; on one process every node is), or ghosts
  // of the part where its pairs are spread (pack_parts). A ghost row, another rank's, needs none: its
  // master nodes may lie outside the part.
  std::unordered_map<int, int> local;  // node (whole mesh) -> the part's: made where a master or a piece needs it
  const auto part_nodes = [&]() -> const std::unordered_map<int, int>& {
    if (local.empty())
      for (std::size_t a = 0; a < nodes.size(); ++a) local.emplace(nodes[a], static_cast<int>(a));
    return local;
  };
  for (PartContactNode& c : part.contact)
    for (const auto& [k, w] : whole.rows[static_cast<std::size_t>(c.row)].masters) {
      if (!c.owned) break;
      const auto it = part_nodes().find(k);
      require(it != local.end(), "contact pair row {}: master node {} is not among the nodes of its slave node {}'s "
              "part (a bug: a part holds an owned row's masters, owned or ghosts)", c.row, k,
              nodes[static_cast<std::size_t>(c.local_node)]);
      c.masters.emplace_back(it->second, w);
    }
  for (const WholeMeshData::SlidingPair& s : whole.sliding)
    if (auto piece = sliding_piece(p.mesh, s, part_nodes(), n_owned)) part.sliding.push_back(std::move(*piece));
  part.original_cell = cells;
  for (int c : cells) {
    part.cell_material.push_back(whole.cell_material[c]);
    part.cell_body.push_back(whole.cell_body[c]);
  }
  part.dirichlet_components = dirichlet.components;
  part.n_contact = static_cast<int>(whole.rows.size());
  part.n_global_nodes = p.mesh.n_nodes();
  part.n_global_dofs = numbering.n_dofs;
  part.n_global_cells = p.mesh.n_cells();
  return part;
}

}  // namespace vpc
