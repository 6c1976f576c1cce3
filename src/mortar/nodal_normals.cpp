#include "mortar/nodal_normals.hpp"

#include "core/error.hpp"

namespace vpc::mortar {

std::vector<Point> nodal_normals(const Surface& s) {
  std::vector<Eigen::Vector3d> sum(s.n_nodes(), Eigen::Vector3d::Zero());
  std::vector<double> weight(s.n_nodes(), 0.0);
  for (int f = 0; f < s.n_facets(); ++f)
    for (int a = 0; a < s.nodes_per_facet(); ++a) {
      sum[s.facet(f)[a]] += s.measure(f) * vec(s.normal(f));
      weight[s.facet(f)[a]] += s.measure(f);
    }
  std::vector<Point> n(s.n_nodes());
  for (int j = 0; j < s.n_nodes(); ++j) {
    require(weight[j] > 0, "mortar nodal normals: node id {} is on no facet of the surface", s.id(j));
    // |Σ|e| n_e| / Σ|e| is 1 on a flat surface and cos(θ/2) between two facets at an angle θ;
    // below 1e-8 the facets face (almost) opposite ways and the average has no direction.
    const double len = sum[j].norm();
    require(len > 1e-8 * weight[j],
            "mortar nodal normals: the facets at node id {} face opposite ways (their normals cancel)", s.id(j));
    n[j] = point(sum[j] / len);
  }
  return n;
}

}  // namespace vpc::mortar
