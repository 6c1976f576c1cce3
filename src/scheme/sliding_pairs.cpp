#include "scheme/sliding_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

namespace {

/// A master facet's size at slave node j: the largest distance from one of its masters to the nearest
/// other (the masters are the nodes of the master facets over its support, so in 2D each is a facet's
/// length), in the reference configuration.
double master_facet_at(const MeshPart& part, const PartContactNode& j) {
  double facet = 0;
  for (const auto& [k, wk] : j.masters) {
    double nearest = INFINITY;
    const Point& x = part.mesh().node(k);
    for (const auto& [l, wl] : j.masters) {
      const Point& y = part.mesh().node(l);
      if (l != k) nearest = std::min(nearest, std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]));
    }
    if (std::isfinite(nearest)) facet = std::max(facet, nearest);
  }
  return facet;
}

/// |(I − ν_j ν_jᵀ)(u_j − Σ_k w_k u_k)|: slave node j's slide across its normal from its masters' mean.
double slide_at(const MeshPart& part, const PartContactNode& j, const Vector& u) {
  const int d = part.mesh().dim();
  Point r{0, 0, 0};
  for (int i = 0; i < d; ++i) r[i] = u[j.local_node * d + i];
  for (const auto& [k, w] : j.masters)
    for (int i = 0; i < d; ++i) r[i] -= w * u[k * d + i];
  double along = 0;
  for (int i = 0; i < d; ++i) along += r[i] * j.direction[i];
  for (int i = 0; i < d; ++i) r[i] -= along * j.direction[i];
  return std::hypot(r[0], r[1], r[2]);
}

}  // namespace

std::vector<PairSlide> small_slides(const Problem& p, const MeshPart& part, std::span<const PartContactNode> nodes,
                                    const State& state) {
  const la::Comm& comm = part.comm;
  std::vector<PairSlide> slides;
  for (const std::size_t q : p.contact.sliding_pairs(false)) {
    PairSlide& s = slides.emplace_back();
    for (const PartContactNode& node : nodes) {
      if (!node.owned || node.pair != static_cast<int>(q)) continue;
      if (!(state.lambda.size() > 0 && state.lambda[static_cast<Eigen::Index>(node.row) * state.contact_block] > 0))
        continue;  // not in contact
      const double facet = master_facet_at(part, node);
      if (!(facet > 0)) continue;
      const double slide = slide_at(part, node, state.u), ratio = slide / facet;
      const int original = part.original_node[static_cast<std::size_t>(node.local_node)];
      if (s.node < 0 || ratio > s.ratio || (ratio == s.ratio && original < s.node))
        s = {q, ratio, slide, facet, original, part.mesh().node(node.local_node)};
    }
    // The largest ratio over the ranks, at the lowest node number among equal ones (its rank's values).
    const double largest = comm.max(s.node >= 0 ? s.ratio : -1.0);
    const int node = s.node >= 0 && s.ratio == largest ? s.node : std::numeric_limits<int>::max();
    const int at = static_cast<int>(-comm.max(-static_cast<double>(node)));
    if (s.node != at) s = {.pair = q};
    comm.sum(s.x.data(), 3);
    s.slide = comm.sum(s.slide);
    s.facet = comm.sum(s.facet);
    s.ratio = std::max(largest, 0.0);
    s.node = at == std::numeric_limits<int>::max() ? -1 : at;
  }
  return slides;
}

}  // namespace vpc
