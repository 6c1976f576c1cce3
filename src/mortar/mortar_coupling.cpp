#include "mortar/mortar_coupling.hpp"

#include "core/error.hpp"
#include "mortar/nodal_normals.hpp"
#include "mortar/polygon_clip.hpp"
#include "mortar/segment_projection.hpp"

#include <algorithm>
#include <atomic>
#include <string>
#include <utility>

namespace vpc::mortar {

namespace {

// A pair faces when n_s·n_m < −kFacing (see the header).
constexpr double kFacing = 1e-8;

std::string facet_name(const Surface& s, int f) {
  std::string ids;
  for (int a = 0; a < s.nodes_per_facet(); ++a) ids += (a ? ", " : "") + std::to_string(s.id(s.facet(f)[a]));
  return "facet " + std::to_string(f) + " (node ids " + ids + ")";
}

Eigen::Vector2d xy(const Point& p) { return {p[0], p[1]}; }

std::atomic<long long> builds{0};

}  // namespace

long long mortar_coupling_builds() { return builds.load(); }

std::vector<FacetCover> facet_cover(const Surface& slave, const std::vector<Point>& slave_normals, int e,
                                    const Surface& master, std::span<const int> candidates, double tol) {
  const int* v = slave.facet(e);
  const Eigen::Vector3d n_e = vec(slave.normal(e));
  std::vector<FacetCover> covers;
  for (const int f : candidates) {
    if (!(n_e.dot(vec(master.normal(f))) < -kFacing)) continue;
    const int* w = master.facet(f);
    std::vector<MortarPoint> points;
    try {
      if (slave.dim() == 2) {
        const SlaveSegment s{xy(slave.node(v[0])), xy(slave.node(v[1])), xy(slave_normals[v[0]]),
                             xy(slave_normals[v[1]])};
        points = segment_pair_points(s, xy(master.node(w[0])), xy(master.node(w[1])), tol);
      } else {
        const std::array<Eigen::Vector3d, 3> s{vec(slave.node(v[0])), vec(slave.node(v[1])), vec(slave.node(v[2]))};
        const std::array<Eigen::Vector3d, 3> m{vec(master.node(w[0])), vec(master.node(w[1])), vec(master.node(w[2]))};
        points = triangle_pair_points(s, n_e, m, tol);
      }
    } catch (const Error& err) {  // vpc::located, with the names built only on failure
      throw Error("mortar: slave " + facet_name(slave, e) + ", master " + facet_name(master, f) + ": " + err.what());
    }
    if (!points.empty()) covers.push_back({f, std::move(points)});
  }
  return covers;
}

MortarCoupling mortar_coupling(const Surface& slave, const Surface& master, const MortarOptions& options) {
  ++builds;
  require(slave.dim() == master.dim(), "mortar: the slave surface is {}D and the master {}D", slave.dim(),
          master.dim());
  require(options.coefficient_bound >= 3, "mortar: coefficient_bound is {} (expected >= 3, a full triangle's)",
          options.coefficient_bound);
  require(options.clip_tolerance > 0 && options.clip_tolerance <= 1e-3,
          "mortar: clip_tolerance is {} (expected in (0, 1e-3])", options.clip_tolerance);
  const std::vector<Point> normals = nodal_normals(slave);
  const FacetPairs pairs = candidate_pairs(slave, master, options.search_margin);

  int n_facing = 0, n_backward = 0;
  for (int e = 0; e < slave.n_facets(); ++e)
    for (const int f : pairs.of(e)) {
      const double c = vec(slave.normal(e)).dot(vec(master.normal(f)));
      n_facing += c < -kFacing;
      n_backward += c > kFacing;
    }
  require(n_facing > 0 || n_backward == 0,
          "mortar: none of the {} candidate pairs of slave and master facets face each other (every slave normal "
          "points the same way as the master normals near it): the master part is on the far side of its body from "
          "the slave (name the face that meets the slave), or one surface's facets are ordered with their normals "
          "pointing into its body (FacetOrder)",
          pairs.n_pairs());

  // Per slave node: D_jj and the row of M as (master node, value), accumulated facet by facet.
  std::vector<double> d(slave.n_nodes(), 0.0);
  std::vector<std::vector<std::pair<int, double>>> rows(slave.n_nodes());
  const int n = slave.nodes_per_facet();
  for (int e = 0; e < slave.n_facets(); ++e) {
    const std::vector<FacetCover> covers = facet_cover(slave, normals, e, master, pairs.of(e), options.clip_tolerance);
    if (covers.empty()) continue;
    Eigen::Matrix3d mass = Eigen::Matrix3d::Zero();
    for (const FacetCover& c : covers) add_covered_mass(c.points, mass);
    const DualBasis basis = dual_basis(n, mass, options.coefficient_bound);
    for (int j = 0; j < n; ++j) {
      if (basis.merged[j]) continue;
      const int node = slave.facet(e)[j];
      d[node] += basis.weight[j];
      auto& row = rows[node];
      for (const FacetCover& c : covers)
        for (const MortarPoint& p : c.points) {
          const double phi = basis.phi(j, p.slave) * p.weight;
          for (int k = 0; k < n; ++k) {
            const int m_node = master.facet(c.master_facet)[k];
            auto it = std::find_if(row.begin(), row.end(), [&](const auto& entry) { return entry.first == m_node; });
            if (it == row.end()) it = row.insert(row.end(), {m_node, 0.0});
            it->second += phi * p.master[k];
          }
        }
    }
  }

  MortarCoupling out;
  out.nodes.resize(slave.n_nodes());
  for (int j = 0; j < slave.n_nodes(); ++j) {
    SlaveNodeCoupling& c = out.nodes[j];
    c.id = slave.id(j);
    c.normal = normals[j];
    if (!(d[j] > 0)) continue;  // uncovered (a node whose facets were all merged away, too)
    c.d = d[j];
    const Eigen::Vector3d n_j = vec(normals[j]);
    // g̃_j = Σ_k M_jk n_j·(x_k^m − x_j^s): the header's formula, as Σ_k M_jk = D_jj (dual_basis),
    // without its cancellation of two terms of the size of the coordinates.
    double gap = 0;
    for (const auto& [k, value] : rows[j]) {
      gap += value * n_j.dot(vec(master.node(k)) - vec(slave.node(j)));
      out.m.emplace_back(c.id, master.id(k), value);
    }
    c.gap = gap;
    out.covered_area += d[j];
  }
  std::sort(out.m.begin(), out.m.end(),
            [](const auto& a, const auto& b) { return a.row() != b.row() ? a.row() < b.row() : a.col() < b.col(); });
  return out;
}

}  // namespace vpc::mortar
