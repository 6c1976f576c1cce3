#include "mesh/mesh_bytes.hpp"

#include "core/error.hpp"
#include "mesh/gmsh_model.hpp"

#include <cstddef>
#include <vector>

namespace vpc {

std::string mesh_bytes(const Mesh& mesh) {
  require(mesh.n_bodies() == 1, "internal: mesh_bytes of a mesh of {} bodies", mesh.n_bodies());
  gmsh_model::Writer w;
  w.value(mesh.dim());
  std::vector<double> x;
  x.reserve(static_cast<std::size_t>(mesh.n_nodes()) * 3);
  for (const Point& p : mesh.nodes()) x.insert(x.end(), p.begin(), p.end());
  w.array(x);
  w.array(mesh.cell_array());
  std::vector<int> facets, parts, regions;
  for (int f = 0; f < mesh.n_facets(); ++f) {
    facets.insert(facets.end(), mesh.facet(f), mesh.facet(f) + mesh.nodes_per_facet());
    parts.push_back(mesh.facet_part(f));
  }
  w.array(facets);
  w.array(parts);
  for (int c = 0; c < mesh.n_cells(); ++c) regions.push_back(mesh.cell_region(c));
  w.array(regions);
  w.value(mesh.part_names().size());
  for (const std::string& name : mesh.part_names()) w.string(name);
  w.value(mesh.region_names().size());
  for (const std::string& name : mesh.region_names()) w.string(name);
  return w.bytes();
}

Mesh mesh_from_bytes(std::string_view bytes) {
  try {
    gmsh_model::Reader r(bytes);
    const int d = r.value<int>();
    require(d >= 1 && d <= 3, "internal: a mesh's bytes of dimension {}", d);
    Mesh mesh(d);
    const auto x = r.array<double>();
    const auto cells = r.array<int>(), facets = r.array<int>(), parts = r.array<int>(), regions = r.array<int>();
    std::vector<std::string> part_names(r.value<std::size_t>());
    for (auto& name : part_names) name = r.string();
    std::vector<std::string> region_names(r.value<std::size_t>());
    for (auto& name : region_names) name = r.string();
    const auto npc = static_cast<std::size_t>(d + 1), npf = static_cast<std::size_t>(d);
    const std::size_t n_nodes = x.size() / 3, n_cells = cells.size() / npc;
    require(x.size() % 3 == 0 && cells.size() % npc == 0 && facets.size() == parts.size() * npf &&
                regions.size() == n_cells, "internal: a mesh's bytes of inconsistent sizes");
    for (std::size_t i = 0; i < n_nodes; ++i) mesh.add_node({x[3 * i], x[3 * i + 1], x[3 * i + 2]});
    for (const int v : cells) require(v >= 0 && static_cast<std::size_t>(v) < n_nodes, "internal: a mesh's bytes name node {}", v);
    for (const int v : facets) require(v >= 0 && static_cast<std::size_t>(v) < n_nodes, "internal: a mesh's bytes name node {}", v);
    for (std::size_t c = 0; c < n_cells; ++c) mesh.add_cell(&cells[c * npc]);
    for (const std::string& name : part_names) mesh.part_id(name);
    for (const std::string& name : region_names) mesh.region_id(name);
    auto name_of = [](const std::vector<std::string>& names, int k) {
      require(k >= -1 && k < static_cast<int>(names.size()), "internal: a mesh's bytes name group {}", k);
      return k < 0 ? std::string() : names[static_cast<std::size_t>(k)];
    };
    for (std::size_t f = 0; f < parts.size(); ++f) mesh.add_facet(&facets[f * npf], name_of(part_names, parts[f]));
    for (std::size_t c = 0; c < n_cells; ++c)
      if (regions[c] >= 0) mesh.set_cell_region(static_cast<int>(c), name_of(region_names, regions[c]));
    return mesh;
  } catch (const gmsh_model::Reader::Truncated&) {
    fail("internal: a mesh's bytes end early");
  }
}

}  // namespace vpc
