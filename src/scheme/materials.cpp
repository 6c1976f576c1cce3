// Several materials (SPEC §6): which of ℰ, G, φ each cell has.
#include "core/error.hpp"
#include "scheme/problem.hpp"

#include <algorithm>
#include <map>

namespace vpc {

std::vector<Material> Problem::material_list() const {
  std::vector<Material> list{{"body", {}, elasticity, law, source}};
  list.insert(list.end(), materials.begin(), materials.end());
  return list;
}

std::vector<int> cell_materials(const Problem& p) {
  const std::string where = p.name.empty() ? "problem" : p.name;
  const Mesh& mesh = p.mesh;
  std::vector<int> material_of_region(mesh.region_names().size(), 0);
  std::map<std::string, std::string> owner;  // region -> material
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
      require(mesh.region_size(region) > 0,
              "{}: material '{}': the mesh has no cell in region '{}'{}", where, m.name, region,
              mesh.region_names().empty()
                  ? " (it has no regions: name the cells with a Gmsh physical group of the mesh's dimension, or give the material a `where`)"
                  : fmt::format(" (its regions: {})", fmt::join(mesh.region_names(), ", ")));
      const auto [it, fresh] = owner.emplace(region, m.name);
      require(fresh, "{}: region '{}' is in materials '{}' and '{}'; a cell has one material", where, region,
              it->second, m.name);
      material_of_region[static_cast<std::size_t>(mesh.find_region(region))] = static_cast<int>(k) + 1;
    }
  }
  std::vector<int> out(mesh.n_cells(), 0);
  for (int c = 0; c < mesh.n_cells(); ++c)
    if (const int r = mesh.cell_region(c); r >= 0) out[c] = material_of_region[static_cast<std::size_t>(r)];
  return out;
}

}  // namespace vpc
