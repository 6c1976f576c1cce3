#include "scheme/problem.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

void Problem::validate() const {
  const std::string where = name.empty() ? "problem" : name;
  require(mesh.n_cells() > 0, "{}: the mesh has no cells", where);
  require(elasticity.dim() == mesh.dim(),
          "{}: elasticity '{}' is for d = {} but the mesh has d = {}", where, elasticity.name(),
          elasticity.dim(), mesh.dim());
  require(std::isfinite(kappa) && kappa >= 0, "{}: kappa (damage diffusion) must be >= 0 (got {})", where, kappa);
  require(std::isfinite(final_time) && final_time > 0, "{}: final time T must be > 0 (got {})", where, final_time);
  require(n_steps >= 1, "{}: the number of time steps must be >= 1 (got {})", where, n_steps);
  require(law != nullptr, "{}: no viscoplastic law G", where);
  require(source != nullptr, "{}: no damage source phi", where);
  require(!clamped.empty(), "{}: no clamped part Γ1 given (meas Γ1 > 0 is required)", where);
  for (const auto& p : clamped)
    require(mesh.part_size(p) > 0, "{}: clamped part '{}' has no boundary facets in the mesh", where, p);
  require(!contact.parts.empty(), "{}: no contact part Γ3 given", where);
  for (const auto& p : contact.parts)
    require(mesh.part_size(p) > 0, "{}: contact part '{}' has no boundary facets in the mesh", where, p);
  for (const auto& p : traction)
    require(mesh.part_size(p) > 0, "{}: traction part '{}' has no boundary facets in the mesh", where, p);
  require(static_cast<bool>(contact.gap), "{}: no gap function g", where);
  if (contact.direction) {
    const Point& v = *contact.direction;
    require(std::hypot(v[0], v[1], v[2]) > 0, "{}: the contact direction must be a non-zero vector", where);
  }
}

std::vector<int> traction_facets(const Problem& p) {
  const Mesh& mesh = p.mesh;
  if (!p.traction.empty()) return mesh.facets_of_parts(p.traction);
  std::vector<int> excluded, facets;
  for (const auto& n : p.clamped) excluded.push_back(mesh.find_part(n));
  for (const auto& n : p.contact.parts) excluded.push_back(mesh.find_part(n));
  for (int f = 0; f < mesh.n_facets(); ++f)
    if (std::find(excluded.begin(), excluded.end(), mesh.facet_part(f)) == excluded.end()) facets.push_back(f);
  return facets;
}

std::vector<ContactRow> contact_rows(const Problem& p, const std::vector<char>& clamped) {
  const Mesh& mesh = p.mesh;
  std::vector<Point> normal(mesh.n_nodes(), Point{0, 0, 0});
  for (int f : mesh.facets_of_parts(p.contact.parts)) {
    const Point nf = mesh.facet_normal(f);
    const double w = mesh.facet_measure(f);
    for (int a = 0; a < mesh.nodes_per_facet(); ++a)
      for (int j = 0; j < 3; ++j) normal[mesh.facet(f)[a]][j] += w * nf[j];
  }
  std::vector<ContactRow> rows;
  for (int node : mesh.nodes_of_parts(p.contact.parts)) {
    if (clamped[node]) continue;  // u = 0 already
    Point v = p.contact.direction ? *p.contact.direction : normal[node];
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (double& c : v) c /= l;
    const double g = p.contact.gap(mesh.node(node), 0.0);
    require(std::isfinite(g) && g >= 0, "{}: the gap g must be >= 0; it is {} at node {}", p.name, g, node);
    rows.push_back({node, v, g});
  }
  require(!rows.empty(), "{}: the contact part has no free nodes (all are clamped or it is empty)", p.name);
  return rows;
}

}  // namespace vpc

namespace vpc {

std::vector<double> tributary_measures(const Mesh& mesh, const std::vector<std::string>& parts) {
  std::vector<double> m(static_cast<std::size_t>(mesh.n_nodes()), 0.0);
  const int nv = mesh.nodes_per_facet();
  for (int f : mesh.facets_of_parts(parts)) {
    const double share = mesh.facet_measure(f) / nv;
    for (int a = 0; a < nv; ++a) m[mesh.facet(f)[a]] += share;
  }
  return m;
}

}  // namespace vpc
