// The one builder of a part (part/part_cut.hpp, make_mesh_part): on one process
// the part is the whole problem in its own numbering; cut in two on one process,
// the parts agree with each other and with the whole (what distribute_mesh sends).
#include "io/case_file.hpp"
#include "part/mesh_part.hpp"
#include "part/part_cut.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <set>
#include <utility>

namespace vpc {
namespace {

/// Every kind of datum a part carries: Γ1, a prescribed displacement, Γ3, Γ2 and a pressure.
std::shared_ptr<const Problem> plate() {
  return parse_case(R"(
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [6, 3]
[boundary]
clamped = ["left"]
contact = ["bottom"]
[[boundary.displacement]]
parts = ["right"]
ux = "0.01*t"
[elasticity]
kind = "plane-stress"
E = 100.0
nu = 0.3
[viscoplasticity]
law = "maxwell-damage"
[contact]
gap = 0.0
[[loads.pressure]]
parts = "top"
p = "t"
[time]
T = 1.0
steps = 2
)",
                    "plate.toml", ".", {})
      .problem;
}

void expect_same(const PartContactNode& a, const PartContactNode& b) {
  EXPECT_EQ(a.row, b.row);
  EXPECT_EQ(a.direction, b.direction);
  EXPECT_EQ(a.gap, b.gap);
  EXPECT_EQ(a.measure, b.measure);
  EXPECT_EQ(a.datum, b.datum);
  EXPECT_EQ(a.law, b.law);
  EXPECT_EQ(a.obstacles, b.obstacles);
}

// What whole_mesh_part filled field by field before the one builder.
TEST(MeshPart, OnOneProcessIsTheWholeProblemInItsOwnNumbering) {
  const auto problem = plate();
  const Problem& p = *problem;
  const MeshPart part = whole_mesh_part(problem);
  const int n = p.mesh.n_nodes();
  EXPECT_EQ(&part.mesh(), &p.mesh);  // shared, not copied
  EXPECT_EQ(part.n_owned_nodes, n);
  std::vector<long long> iota_ll(n);
  std::iota(iota_ll.begin(), iota_ll.end(), 0LL);
  std::vector<int> iota_n(n), iota_c(p.mesh.n_cells());
  std::iota(iota_n.begin(), iota_n.end(), 0);
  std::iota(iota_c.begin(), iota_c.end(), 0);
  EXPECT_EQ(part.global_node, iota_ll);
  EXPECT_EQ(part.original_node, iota_n);
  EXPECT_EQ(part.original_cell, iota_c);
  EXPECT_EQ(part.cell_material, cell_materials(p));
  EXPECT_EQ(part.traction_facets, traction_facets(p));
  EXPECT_EQ(part.pressure_facets, pressure_facets(p));
  ASSERT_EQ(part.pressure_facets.size(), 1u);
  EXPECT_FALSE(part.pressure_facets[0].empty());

  const DirichletDofs dirichlet = dirichlet_dofs(p);
  EXPECT_EQ(part.dirichlet, dirichlet.condition);
  EXPECT_EQ(part.dirichlet_components, dirichlet.components);
  std::vector<std::pair<int, std::uint64_t>> on_parts;
  for (int i = 0; i < n; ++i)
    if (dirichlet.on_parts[i]) on_parts.emplace_back(i, dirichlet.on_parts[i]);
  EXPECT_EQ(part.dirichlet_nodes, on_parts);

  const DofMap dofs(p.mesh.dim(), dirichlet.condition);
  EXPECT_EQ(part.dofs.n_free(), dofs.n_free());
  EXPECT_EQ(part.n_owned_dofs, dofs.n_free());
  EXPECT_EQ(part.n_global_dofs, dofs.n_free());
  std::vector<long long> free(dofs.n_free());
  std::iota(free.begin(), free.end(), 0LL);
  EXPECT_EQ(part.global_dof, free);
  EXPECT_EQ(part.n_global_nodes, n);
  EXPECT_EQ(part.n_global_cells, p.mesh.n_cells());
  EXPECT_EQ(part.node_layout->n_owned(), n);
  EXPECT_EQ(part.dof_layout->n_owned(), dofs.n_free());

  const std::vector<ContactRow> rows = contact_rows(p, dirichlet.condition);
  const std::vector<double> measure = tributary_measures(p.mesh, p.contact.parts);
  ASSERT_EQ(part.contact.size(), rows.size());
  ASSERT_GT(rows.size(), 2u);
  EXPECT_EQ(part.n_contact, static_cast<int>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(part.contact[k].local_node, rows[k].node);
    EXPECT_TRUE(part.contact[k].owned);
    expect_same(part.contact[k], part_contact_node(static_cast<int>(k), rows[k], rows[k].node, true));
    EXPECT_EQ(part.contact[k].measure, measure[rows[k].node]);
  }
}

// Two parts cut on one process as rank 0 cuts them for two ranks: a ghost node has
// the global numbers its owner gives it, the owned dofs are contiguous and cover the
// free dofs once, and each contact row is owned once, with the whole part's data.
TEST(MeshPart, PartsCutFromTheWholeAgree) {
  const auto problem = plate();
  const Problem& p = *problem;
  const Mesh& mesh = p.mesh;
  const MeshPart whole_part = whole_mesh_part(problem);
  const WholeMeshData whole(p);
  std::vector<int> part_of_cell(mesh.n_cells());
  for (int c = 0; c < mesh.n_cells(); ++c) part_of_cell[c] = mesh.cell_centroid(c)[0] < 1.0 ? 0 : 1;
  std::vector<std::vector<int>> owned(2), cells(2);
  for (int i = 0; i < mesh.n_nodes(); ++i) owned[mesh.node(i)[0] < 1.0 - 1e-12 ? 0 : 1].push_back(i);
  // Nodes on x = 1 belong to part 1 but touch cells of part 0: they are part 0's ghosts.
  for (int c = 0; c < mesh.n_cells(); ++c) cells[part_of_cell[c]].push_back(c);
  const WholeNumbering numbering(owned, whole.dirichlet, mesh.dim());

  std::map<std::pair<long long, int>, long long> dof_of;  // (global node, component) -> global dof
  std::set<long long> owned_dofs;
  std::vector<int> owned_rows(whole.rows.size(), 0);
  for (int r = 0; r < 2; ++r) {
    std::vector<int> nodes = owned[r];
    std::set<int> ghosts;
    for (int c : cells[r])
      for (int a = 0; a <= mesh.dim(); ++a)
        if (std::find(owned[r].begin(), owned[r].end(), mesh.cell(c)[a]) == owned[r].end())
          ghosts.insert(mesh.cell(c)[a]);
    nodes.insert(nodes.end(), ghosts.begin(), ghosts.end());
    std::vector<int> local(mesh.n_nodes(), -1);
    for (std::size_t k = 0; k < nodes.size(); ++k) local[nodes[k]] = static_cast<int>(k);
    auto local_mesh = std::make_shared<Mesh>(mesh.dim());
    for (int v : nodes) local_mesh->add_node(mesh.node(v));
    for (int c : cells[r]) {
      int cell[4];
      for (int a = 0; a <= mesh.dim(); ++a) cell[a] = local[mesh.cell(c)[a]];
      local_mesh->add_cell(cell);
    }
    PartPieces pieces = cut_part(p, whole, numbering, nodes, static_cast<int>(owned[r].size()), cells[r]);
    pieces.mesh_ptr = local_mesh;
    const MeshPart part = make_mesh_part(std::move(pieces));

    EXPECT_EQ(part.n_global_dofs, whole_part.n_global_dofs);
    for (int k = 0; k < part.n_owned_dofs; ++k) {
      EXPECT_EQ(part.global_dof[k], part.global_dof[0] + k);
      EXPECT_TRUE(owned_dofs.insert(part.global_dof[k]).second);
    }
    for (int i = 0; i < part.n_local_nodes(); ++i)
      for (int c = 0; c < mesh.dim(); ++c) {
        const int k = part.dofs.free_index(part.dofs.full_index(i, c));
        EXPECT_EQ(k >= 0, whole_part.dofs.free_index(whole_part.dofs.full_index(nodes[i], c)) >= 0);
        if (k < 0) continue;
        const auto [it, first] = dof_of.emplace(std::pair{part.global_node[i], c}, part.global_dof[k]);
        EXPECT_EQ(it->second, part.global_dof[k]);  // the same in both parts
        (void)first;
      }
    for (const PartContactNode& node : part.contact) {
      EXPECT_EQ(node.owned, node.local_node < part.n_owned_nodes);
      const int i = nodes[node.local_node];
      ASSERT_EQ(whole.row_of[i], node.row);
      expect_same(node, whole_part.contact[node.row]);
      owned_rows[node.row] += node.owned;
    }
    for (const auto& [i, bits] : part.dirichlet_nodes)
      EXPECT_EQ(bits, whole.dirichlet.on_parts[nodes[i]]);
  }
  EXPECT_EQ(static_cast<long long>(owned_dofs.size()), whole_part.n_global_dofs);
  EXPECT_EQ(*owned_dofs.rbegin(), whole_part.n_global_dofs - 1);
  for (int n : owned_rows) EXPECT_EQ(n, 1);
}

}  // namespace
}  // namespace vpc
