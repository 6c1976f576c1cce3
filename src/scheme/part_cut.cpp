#include "scheme/part_cut.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
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
  std::unordered_map<int, int> local;  // node (whole mesh) -> the part's, at the first master met
  for (PartContactNode& c : part.contact)
    for (const auto& [k, w] : whole.rows[static_cast<std::size_t>(c.row)].masters) {
      if (!c.owned) break;
      if (local.empty())
        for (std::size_t a = 0; a < nodes.size(); ++a) local.emplace(nodes[a], static_cast<int>(a));
      const auto it = local.find(k);
      require(it != local.end(), "contact pair row {}: master node {} is not among the nodes of its slave node {}'s "
              "part (a bug: a part holds an owned row's masters, owned or ghosts)", c.row, k,
              nodes[static_cast<std::size_t>(c.local_node)]);
      c.masters.emplace_back(it->second, w);
    }
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
