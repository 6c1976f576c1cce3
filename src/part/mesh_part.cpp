#include "part/mesh_part.hpp"

#include "core/error.hpp"
#include "part/part_cut.hpp"

#include <algorithm>
#include <cstddef>
#include <numeric>

namespace vpc {

namespace {

/// The layouts of the part's nodes and free dofs (owned first, then ghosts). Collective.
void make_layouts(MeshPart& part) {
  const std::vector<long long> ghost_nodes(part.global_node.begin() + part.n_owned_nodes, part.global_node.end());
  const std::vector<long long> owned_original(part.original_node.begin(),
                                              part.original_node.begin() + part.n_owned_nodes);
  const std::vector<long long> ghost_dofs(part.global_dof.begin() + part.n_owned_dofs, part.global_dof.end());
  // Dofs keep their global number as the "original" one: fields leave the part by nodes.
  const std::vector<long long> owned_dofs(part.global_dof.begin(), part.global_dof.begin() + part.n_owned_dofs);
  if (part.comm.serial()) {
    part.node_layout = std::make_shared<const la::Layout>(part.n_owned_nodes);
    part.dof_layout = std::make_shared<const la::Layout>(part.n_owned_dofs);
  } else {
    part.node_layout = std::make_shared<const la::Layout>(part.comm, part.n_owned_nodes, ghost_nodes, owned_original);
    part.dof_layout = std::make_shared<const la::Layout>(part.comm, part.n_owned_dofs, ghost_dofs, owned_dofs);
  }
}

}  // namespace

MeshPart make_mesh_part(PartPieces pieces) {
  MeshPart part;
  static_cast<PartPieces&>(part) = std::move(pieces);
  const int d = part.mesh().dim(), n_local = part.n_local_nodes();
  part.dofs = DofMap(d, part.dirichlet);
  for (int i = 0; i < n_local; ++i)
    if (part.dirichlet_on_parts[i]) part.dirichlet_nodes.emplace_back(i, part.dirichlet_on_parts[i]);
  // The free components of a node follow its first free dof; the owned nodes come first.
  part.global_dof.assign(part.dofs.n_free(), -1);
  for (int i = 0; i < n_local; ++i)
    for (int c = 0, j = 0; c < d; ++c) {  // j: the node's free components before c
      const int k = part.dofs.free_index(part.dofs.full_index(i, c));
      if (k >= 0) part.global_dof[k] = part.first_dof[i] + j++;
    }
  part.n_owned_dofs = static_cast<int>(
      std::count(part.dirichlet.begin(), part.dirichlet.begin() + static_cast<std::ptrdiff_t>(part.n_owned_nodes) * d, -1));
  for (int k = 1; k < part.n_owned_dofs; ++k)
    require(part.global_dof[k] == part.global_dof[0] + k, "internal: the owned dofs of a part are not contiguous");
  make_layouts(part);
  return part;
}

MeshPart whole_mesh_part(std::shared_ptr<const Problem> problem, ContactRows rows) {
  const Problem& p = *problem;
  const WholeMeshData whole(p, std::move(rows));
  std::vector<int> all(p.mesh.n_nodes()), cells(p.mesh.n_cells());
  std::iota(all.begin(), all.end(), 0);
  std::iota(cells.begin(), cells.end(), 0);
  const WholeNumbering numbering({all}, whole.dirichlet, p.mesh.dim());
  PartPieces pieces = cut_part(p, whole, numbering, all, p.mesh.n_nodes(), cells);
  pieces.mesh_ptr = std::shared_ptr<const Mesh>(problem, &p.mesh);
  pieces.traction_facets = whole.traction_facets;
  pieces.pressure_facets = whole.pressure_facets;
  return make_mesh_part(std::move(pieces));
}

}  // namespace vpc
