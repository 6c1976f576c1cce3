#include "scheme/sliding_pairs.hpp"

#include "core/error.hpp"
#include "scheme/contact_pairs.hpp"

#include <algorithm>
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
      node.gap = sys.miss_gap;
      for (int i = 0; i < d; ++i) node.gap += node.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
      continue;
    }
    const ContactRow& r = *it->second;
    node.direction = r.direction;
    node.measure = r.measure;
    node.stiffness = r.stiffness;
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
  sys.set_contact_rows();
}

}  // namespace vpc
