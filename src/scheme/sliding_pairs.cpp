#include "scheme/sliding_pairs.hpp"

#include "core/error.hpp"
#include "scheme/contact_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace vpc {

bool slides(const Problem& p) {
  return std::ranges::any_of(p.contact.pairs, [](const ContactPair& q) { return q.large_sliding; });
}

void slide_pairs(DiscreteSystem& sys, const Vector& u) {
  const Problem& p = *sys.problem;
  MeshPart& part = sys.part;
  const int d = part.mesh().dim();
  // Every node of a sliding pair's parts is rank 0's (own_pairs_together), which keeps the whole mesh
  // (petsc_stepper); another rank has none of their rows.
  if (std::ranges::none_of(part.contact, [&](const PartContactNode& n) {
        return n.pair >= 0 && p.contact.pairs[static_cast<std::size_t>(n.pair)].large_sliding;
      }))
    return;
  require(p.mesh.n_nodes() > 0, "internal: the rows of a sliding pair on a rank without the whole mesh");
  Mesh moved = p.mesh;
  std::map<int, int> local;  // original node -> the part's
  for (int l = 0; l < part.mesh().n_nodes(); ++l) {
    const int o = part.original_node[static_cast<std::size_t>(l)];
    local[o] = l;
    for (int i = 0; i < d; ++i) moved.nodes()[static_cast<std::size_t>(o)][static_cast<std::size_t>(i)] += u[l * d + i];
  }
  std::map<int, const ContactRow*> row_of;  // slave node (original) -> its row in the moved configuration
  const std::vector<ContactRow> rows = pair_rows(p, dirichlet_dofs(p).condition, &moved);
  for (const ContactRow& r : rows) row_of[r.node] = &r;
  for (PartContactNode& node : part.contact) {
    if (node.pair < 0 || !p.contact.pairs[static_cast<std::size_t>(node.pair)].large_sliding) continue;
    const int o = part.original_node[static_cast<std::size_t>(node.local_node)];
    const auto it = row_of.find(o);
    if (it == row_of.end()) {  // no master facet within reach: the node cannot touch this step
      node.masters.clear();
      node.gap = sys.contact.miss_gap;
      for (int i = 0; i < d; ++i) node.gap += node.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
      continue;
    }
    const ContactRow& r = *it->second;
    static_cast<ContactNode&>(node) = r;  // the pair's law, its obstacles (none) and index are the node's already
    node.masters.clear();
    // The bound of N u_n: g(x + u) + ν·u_j − Σ_k w_k ν·u_k (all components: a master's prescribed
    // ones join at t_n in step_data.cpp, so their increment is what moves the bound).
    double bound = r.gap;
    for (int i = 0; i < d; ++i) bound += r.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
    for (const auto& [k, w] : r.masters) {
      const int l = local.at(k);
      node.masters.emplace_back(l, w);
      for (int i = 0; i < d; ++i) bound -= w * r.direction[static_cast<std::size_t>(i)] * u[l * d + i];
    }
    node.gap = bound;
  }
  sys.contact.set_rows(p, part);
}

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

std::vector<PairSlide> small_slides(const Problem& p, const MeshPart& part, const State& state) {
  if (std::ranges::all_of(p.contact.pairs, [](const ContactPair& q) { return q.large_sliding; })) return {};
  const la::Comm& comm = part.comm;
  std::vector<PairSlide> slides(p.contact.pairs.size());
  for (std::size_t q = 0; q < slides.size(); ++q) {
    if (p.contact.pairs[q].large_sliding) continue;
    PairSlide& s = slides[q];
    for (const PartContactNode& node : part.contact) {
      if (!node.owned || node.pair != static_cast<int>(q)) continue;
      if (!(state.lambda.size() > 0 && state.lambda[static_cast<Eigen::Index>(node.row) * state.contact_block] > 0))
        continue;  // not in contact
      const double facet = master_facet_at(part, node);
      if (!(facet > 0)) continue;
      const double slide = slide_at(part, node, state.u), ratio = slide / facet;
      const int original = part.original_node[static_cast<std::size_t>(node.local_node)];
      if (s.node < 0 || ratio > s.ratio || (ratio == s.ratio && original < s.node))
        s = {ratio, slide, facet, original, part.mesh().node(node.local_node)};
    }
    // The largest ratio over the ranks, at the lowest node number among equal ones (its rank's values).
    const double largest = comm.max(s.node >= 0 ? s.ratio : -1.0);
    const int node = s.node >= 0 && s.ratio == largest ? s.node : std::numeric_limits<int>::max();
    const int at = static_cast<int>(-comm.max(-static_cast<double>(node)));
    if (s.node != at) s = {};
    comm.sum(s.x.data(), 3);
    s.slide = comm.sum(s.slide);
    s.facet = comm.sum(s.facet);
    s.ratio = std::max(largest, 0.0);
    s.node = at == std::numeric_limits<int>::max() ? -1 : at;
  }
  return slides;
}

}  // namespace vpc
