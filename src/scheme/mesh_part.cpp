#include "scheme/mesh_part.hpp"

#include "contact/contact_rows.hpp"
#include "scheme/problem.hpp"

#include <numeric>

namespace vpc {

void MeshPart::make_layouts() {
  const std::vector<long long> ghost_nodes(global_node.begin() + n_owned_nodes, global_node.end());
  const std::vector<long long> owned_original(original_node.begin(), original_node.begin() + n_owned_nodes);
  const std::vector<long long> ghost_dofs(global_dof.begin() + n_owned_dofs, global_dof.end());
  // Dofs keep their global number as the "original" one: fields leave the part by nodes.
  const std::vector<long long> owned_dofs(global_dof.begin(), global_dof.begin() + n_owned_dofs);
  if (comm.serial()) {
    node_layout = std::make_shared<const la::Layout>(n_owned_nodes);
    dof_layout = std::make_shared<const la::Layout>(n_owned_dofs);
  } else {
    node_layout = std::make_shared<const la::Layout>(comm, n_owned_nodes, ghost_nodes, owned_original);
    dof_layout = std::make_shared<const la::Layout>(comm, n_owned_dofs, ghost_dofs, owned_dofs);
  }
}

MeshPart whole_mesh_part(std::shared_ptr<const Problem> problem) {
  const Problem& p = *problem;
  const Mesh& mesh = p.mesh;
  MeshPart part;
  part.mesh_ptr = std::shared_ptr<const Mesh>(problem, &p.mesh);
  const int n = mesh.n_nodes();
  part.n_owned_nodes = n;
  part.global_node.resize(n);
  std::iota(part.global_node.begin(), part.global_node.end(), 0LL);
  part.original_node.resize(n);
  std::iota(part.original_node.begin(), part.original_node.end(), 0);
  part.original_cell.resize(mesh.n_cells());
  std::iota(part.original_cell.begin(), part.original_cell.end(), 0);
  part.cell_material = cell_materials(p);
  part.traction_facets = traction_facets(p);
  part.pressure_facets = pressure_facets(p);
  DirichletDofs dirichlet = dirichlet_dofs(p);
  part.dofs = DofMap(mesh.dim(), dirichlet.condition);
  part.n_owned_dofs = part.dofs.n_free();
  part.global_dof.resize(part.n_owned_dofs);
  std::iota(part.global_dof.begin(), part.global_dof.end(), 0LL);
  const std::vector<ContactRow> rows = contact_rows(p, dirichlet.condition);
  part.dirichlet = std::move(dirichlet.condition);
  for (int i = 0; i < n; ++i)
    if (dirichlet.on_parts[i]) part.dirichlet_nodes.emplace_back(i, dirichlet.on_parts[i]);
  part.dirichlet_components = std::move(dirichlet.components);
  const std::vector<double> measure = tributary_measures(mesh, p.contact.parts);
  for (std::size_t k = 0; k < rows.size(); ++k)
    part.contact.push_back({static_cast<int>(k), rows[k].node, true, rows[k].direction, rows[k].gap,
                            measure[rows[k].node], rows[k].law, rows[k].stiffness, rows[k].obstacles});
  part.n_contact = static_cast<int>(rows.size());
  part.n_global_nodes = n;
  part.n_global_dofs = part.n_owned_dofs;
  part.n_global_cells = mesh.n_cells();
  part.make_layouts();
  return part;
}

}  // namespace vpc
