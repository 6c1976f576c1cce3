#include "mortar/surface.hpp"

#include "core/error.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>

namespace vpc::mortar {

namespace {

/// The Outward-convention normal of facet nodes f, not normalized: its length is the
/// segment's length (2D) or twice the triangle's area (3D).
Eigen::Vector3d raw_normal(int dim, const std::vector<Point>& x, const int* f) {
  const Eigen::Vector3d a = vec(x[f[0]]), b = vec(x[f[1]]);
  if (dim == 2) return {b[1] - a[1], a[0] - b[0], 0};
  return (b - a).cross(vec(x[f[2]]) - a);
}

double facet_longest_edge(int dim, const std::vector<Point>& x, const int* f) {
  double h = 0;
  for (int a = 0; a < dim; ++a)
    for (int b = a + 1; b < dim; ++b) h = std::max(h, (vec(x[f[a]]) - vec(x[f[b]])).norm());
  return h;
}

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace

Surface::Surface(int dim, std::vector<Point> x, std::vector<int> ids, std::vector<int> facets, FacetOrder order)
    : dim_(dim), x_(std::move(x)), id_(std::move(ids)), facets_(std::move(facets)) {
  require(dim_ == 2 || dim_ == 3, "mortar surface: dimension {} (expected 2 or 3)", dim_);
  require(id_.size() == x_.size(), "mortar surface: {} global ids for {} nodes", id_.size(), x_.size());
  require(facets_.size() % dim_ == 0, "mortar surface: {} facet node indices is not a multiple of {}", facets_.size(),
          dim_);
  {
    std::unordered_map<int, int> seen;
    for (int i = 0; i < n_nodes(); ++i) {
      const auto [it, fresh] = seen.emplace(id_[i], i);
      require(fresh, "mortar surface: nodes {} and {} have the same global id {}", it->second, i, id_[i]);
      if (dim_ == 2)
        require(x_[i][2] == 0, "mortar surface: 2D node {} (id {}) has z = {} (expected 0)", i, id_[i], x_[i][2]);
    }
  }
  const int n_f = static_cast<int>(facets_.size()) / dim_;
  if (order == FacetOrder::Inward)
    for (int f = 0; f < n_f; ++f) std::swap(facets_[f * dim_], facets_[f * dim_ + 1]);
  normal_.resize(n_f);
  measure_.resize(n_f);
  for (int f = 0; f < n_f; ++f) {
    const int* v = facet(f);
    for (int a = 0; a < dim_; ++a) {
      require(v[a] >= 0 && v[a] < n_nodes(), "mortar surface: facet {} names node {} (the surface has {})", f, v[a],
              n_nodes());
      for (int b = 0; b < a; ++b) require(v[a] != v[b], "mortar surface: facet {} names node {} twice", f, v[a]);
    }
    const Eigen::Vector3d n = raw_normal(dim_, x_, v);
    const double len = n.norm(), h = facet_longest_edge(dim_, x_, v);
    // Degenerate: a zero-length segment, or a triangle whose area is below 1e-12 of its
    // longest edge squared (a sliver whose normal is roundoff).
    require(len > 0 && (dim_ == 2 || len > 2e-12 * h * h), "mortar surface: facet {} (node ids {}, {}{}) is degenerate",
            f, id_[v[0]], id_[v[1]], dim_ == 3 ? fmt::format(", {}", id_[v[2]]) : std::string());
    normal_[f] = point(n / len);
    measure_[f] = dim_ == 2 ? len : len / 2;
  }
  check_orientation();
}

void Surface::check_orientation() const {
  // Consistently ordered neighbours walk their shared node (2D) or edge (3D) in opposite
  // directions: in 2D each node starts at most one segment and ends at most one, in 3D
  // each directed edge a -> b occurs at most once.
  if (dim_ == 2) {
    std::vector<int> starts(n_nodes(), -1), ends(n_nodes(), -1);
    for (int f = 0; f < n_facets(); ++f)
      for (int end = 0; end < 2; ++end) {
        const int a = facet(f)[end];
        int& other = (end == 0 ? starts : ends)[a];
        if (other >= 0)
          fail(
              "mortar surface: segments {} and {} both {} at node id {}: neighbouring facets must be ordered alike "
              "(see FacetOrder), and at most two segments may share a node",
              other, f, end == 0 ? "start" : "end", id_[a]);
        other = f;
      }
    return;
  }
  std::unordered_map<std::uint64_t, int> owner;
  for (int f = 0; f < n_facets(); ++f)
    for (int e = 0; e < 3; ++e) {
      const int a = facet(f)[e], b = facet(f)[(e + 1) % 3];
      const auto [it, fresh] = owner.emplace(edge_key(a, b), f);
      if (!fresh)
        fail(
            "mortar surface: triangles {} and {} both run from node id {} to node id {}: neighbouring facets must "
            "be ordered alike (see FacetOrder), and at most two triangles may share an edge",
            it->second, f, id_[a], id_[b]);
    }
}

void orient_away_from(int dim, const std::vector<Point>& x, std::vector<int>& facets,
                      const std::vector<Point>& inside) {
  require(dim == 2 || dim == 3, "orient_away_from: dimension {} (expected 2 or 3)", dim);
  require(facets.size() == inside.size() * dim, "orient_away_from: {} inside points for {} facets", inside.size(),
          facets.size() / dim);
  for (size_t f = 0; f < inside.size(); ++f) {
    int* v = &facets[f * dim];
    const Eigen::Vector3d n = raw_normal(dim, x, v);
    const double side = n.dot(vec(inside[f]) - vec(x[v[0]]));
    const double h = facet_longest_edge(dim, x, v);
    require(std::abs(side) > 1e-12 * n.norm() * h,
            "orient_away_from: the inside point of facet {} lies in the facet's {} (or the facet is degenerate)", f,
            dim == 2 ? "line" : "plane");
    if (side > 0) std::swap(v[0], v[1]);
  }
}

double Surface::longest_edge() const {
  double h = 0;
  for (int f = 0; f < n_facets(); ++f) h = std::max(h, facet_longest_edge(dim_, x_, facet(f)));
  return h;
}

}  // namespace vpc::mortar
