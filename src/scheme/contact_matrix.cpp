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
  const int n_columns = columns == ContactColumns::local ? dofs.n_free() : static_cast<int>(out.component.size());
  out.N.resize(row, n_columns);
  out.N.setFromTriplets(entries.begin(), entries.end());
  if (!mean.empty()) {
    out.master_mean.resize(n_columns, n_columns);
    out.master_mean.setFromTriplets(mean.begin(), mean.end());
  }
  return out;
}

ContactMatrix owned_rows(const ContactMatrix& local, const MeshPart& part) {
  const int n = part.n_owned_dofs;
  std::vector<int> owned_row(part.contact.size(), -1);  // per row of `local`: its owned row, or −1
  ContactMatrix out;
  for (std::size_t k = 0; k < part.contact.size(); ++k)
    if (part.contact[k].owned) {
      owned_row[k] = static_cast<int>(out.node_dofs.size());
      out.node_dofs.push_back(local.node_dofs[k]);
    }
  // An owned row's entries lie in owned columns (its node's and its masters' dofs: cut_part).
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < local.N.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(local.N, k); it; ++it)
      if (const int row = owned_row[static_cast<std::size_t>(it.row())]; row >= 0) {
        require(k < n, "contact row {}: dof {} is not owned with the row (a bug)",
                part.contact[static_cast<std::size_t>(it.row())].row, k);
        entries.emplace_back(row, k, it.value());
      }
  out.N.resize(static_cast<Eigen::Index>(out.node_dofs.size()), n);
  out.N.setFromTriplets(entries.begin(), entries.end());
  // The masters' mean has entries in owned rows alone (a ghost row has no masters).
  if (local.master_mean.size() > 0) out.master_mean = local.master_mean.topLeftCorner(n, n);
  return out;
}

}  // namespace vpc
