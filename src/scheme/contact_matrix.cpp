#include "scheme/contact_matrix.hpp"

#include "core/error.hpp"

#include <atomic>

namespace vpc {

namespace {

std::atomic<long long> builds{0};

}  // namespace

long long contact_matrix_builds() { return builds.load(); }

ContactMatrix contact_matrix(const MeshPart& part, ContactColumns columns) {
  ++builds;
  const DofMap& dofs = part.dofs;
  const int d = dofs.dim();
  ContactMatrix out;
  std::vector<Eigen::Triplet<double>> entries, mean;
  int row = 0;
  for (const PartContactNode& node : part.contact) {
    if (columns == ContactColumns::owned && !node.owned) continue;
    std::vector<int>& node_dofs = out.node_dofs.emplace_back();
    for (int i = 0; i < d; ++i) {
      int k = dofs.free_index(dofs.full_index(node.local_node, i));
      if (k < 0) continue;
      if (columns == ContactColumns::compact) {
        k = static_cast<int>(out.component.size());
        out.component.push_back(i);
      }
      node_dofs.push_back(k);
      if (node.direction[i] != 0) entries.emplace_back(row, k, node.direction[i]);
    }
    // A pair's row: −w_k ν on each master node's free dofs (scheme/contact_pairs.hpp), which the
    // row's rank owns (cut_part).
    for (const auto& [master, w] : node.masters)
      for (int i = 0; i < d && columns != ContactColumns::compact; ++i) {
        const int k = dofs.free_index(dofs.full_index(master, i));
        if (k < 0) continue;
        require(k < part.n_owned_dofs, "contact row {}: master dof {} is not owned with the row (a bug)", node.row, k);
        if (const int j = dofs.free_index(dofs.full_index(node.local_node, i)); j >= 0) mean.emplace_back(j, k, w);
        if (node.direction[i] != 0) entries.emplace_back(row, k, -w * node.direction[i]);
      }
    ++row;
  }
  const int n_columns = columns == ContactColumns::owned   ? part.n_owned_dofs
                        : columns == ContactColumns::local ? dofs.n_free()
                                                           : static_cast<int>(out.component.size());
  out.N.resize(row, n_columns);
  out.N.setFromTriplets(entries.begin(), entries.end());
  if (!mean.empty()) {
    out.master_mean.resize(n_columns, n_columns);
    out.master_mean.setFromTriplets(mean.begin(), mean.end());
  }
  return out;
}

}  // namespace vpc
