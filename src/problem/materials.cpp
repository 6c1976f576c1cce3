// Several materials (SPEC §6): which of ℰ, G, φ each cell has.
#include "core/error.hpp"
#include "problem/problem.hpp"

#include <algorithm>
#include <map>

namespace vpc {

std::vector<Material> Problem::material_list() const {
  std::vector<Material> list{{"body", {}, elasticity, law, source}};
  list.insert(list.end(), materials.begin(), materials.end());
  for (const Body& b : bodies) list.push_back(b.material);
  return list;
}

std::vector<int> cell_bodies(const Mesh& mesh) {
  std::vector<int> out(static_cast<std::size_t>(mesh.n_cells()));
  for (int c = 0; c < mesh.n_cells(); ++c) out[static_cast<std::size_t>(c)] = mesh.cell_body(c);
  return out;
}

std::vector<int> node_bodies(const Mesh& mesh, const std::vector<int>& cell_body) {
  std::vector<int> body(static_cast<std::size_t>(mesh.n_nodes()), 0);
  for (std::size_t c = 0; c < cell_body.size(); ++c)
    for (int a = 0; a < mesh.nodes_per_cell(); ++a)
      body[static_cast<std::size_t>(mesh.cell(static_cast<int>(c))[a])] = cell_body[c];
  return body;
}

Vector Problem::initial_damage(const Mesh& m, const std::vector<int>& cell_body) const {
  const std::vector<int> body = node_bodies(m, cell_body);
  Vector beta(m.n_nodes());
  for (int i = 0; i < m.n_nodes(); ++i) {
    const ScalarField& b0 = beta0_of(body[static_cast<std::size_t>(i)]);
    beta[i] = b0 ? b0(m.node(i), 0.0) : 1.0;
  }
  return beta;
}

std::vector<int> cell_materials(const Problem& p) {
  const std::string where = p.name.empty() ? "problem" : p.name;
  const Mesh& mesh = p.mesh;
  std::vector<int> material_of_region(mesh.region_names().size(), 0);
  std::map<std::string, std::string> owner;  // region -> material
  for (const Body& b : p.bodies)
    require(b.material.elasticity.kind() == p.elasticity.kind(),
            "{}: body '{}' has elasticity '{}' but the case's is '{}'; every body has the same kind (the stresses "
            "have the same components)",
            where, b.name, b.material.elasticity.name(), p.elasticity.name());
  for (std::size_t k = 0; k < p.materials.size(); ++k) {
    const Material& m = p.materials[k];
    require(m.elasticity.kind() == p.elasticity.kind(),
            "{}: material '{}' has elasticity '{}' but the body's is '{}'; every material of a body has the "
            "same kind (the stresses have the same components)",
            where, m.name, m.elasticity.name(), p.elasticity.name());
    require(m.law != nullptr && m.source != nullptr, "{}: material '{}' has no viscoplastic law or damage source",
            where, m.name);
    require(!m.regions.empty(), "{}: material '{}' has no region", where, m.name);
    for (const auto& region : m.regions) {
      // On a block (Problem::block) the region may lie in other blocks: validate_blocks checks it.
      require(p.block || mesh.region_size(region) > 0,
              "{}: material '{}': the mesh has no cell in region '{}'{}", where, m.name, region,
              mesh.region_names().empty()
                  ? " (it has no regions: name the cells with a Gmsh physical group of the mesh's dimension, or give the material a `where`)"
                  : fmt::format(" (its regions: {})", fmt::join(mesh.region_names(), ", ")));
      const auto [it, fresh] = owner.emplace(region, m.name);
      require(fresh, "{}: region '{}' is in materials '{}' and '{}'; a cell has one material", where, region,
              it->second, m.name);
      if (const int r = mesh.find_region(region); r >= 0) material_of_region[static_cast<std::size_t>(r)] = static_cast<int>(k) + 1;
    }
  }
  require(mesh.n_bodies() == 1 + static_cast<int>(p.bodies.size()), "{}: the mesh has {} bodies for {} described",
          where, mesh.n_bodies(), 1 + p.bodies.size());
  // A cell of no material's region has its body's material: 0, or the body's after p.materials.
  const int first_body_material = 1 + static_cast<int>(p.materials.size());
  std::vector<int> out(mesh.n_cells(), 0);
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const int r = mesh.cell_region(c), m = r >= 0 ? material_of_region[static_cast<std::size_t>(r)] : 0;
    const int b = mesh.cell_body(c);
    out[c] = m > 0 || b == 0 ? m : first_body_material + b - 1;
  }
  return out;
}

}  // namespace vpc
