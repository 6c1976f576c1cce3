#include "part/contact_matrix.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <string>

namespace vpc {

namespace {

std::atomic<long long> builds{0};

}  // namespace

long long contact_matrix_builds() { return builds.load(); }

ContactMatrix contact_matrix(const DofMap& dofs, std::span<const PartContactNode> nodes, ContactColumns columns) {
  ++builds;
  const int d = dofs.dim();
  ContactMatrix out;
  std::vector<Eigen::Triplet<double>> entries, mean;
  int row = 0;
  for (const PartContactNode& node : nodes) {
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
    // A pair's row: −w_k ν on each master node's free dofs (problem/contact_pairs.hpp), which the
    // row's rank owns or, where the pairs are spread, may hold as ghosts (cut_part).
    for (const auto& [master, w] : node.masters)
      for (int i = 0; i < d && columns != ContactColumns::compact; ++i) {
        const int k = dofs.free_index(dofs.full_index(master, i));
        if (k < 0) continue;
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

ContactMatrix owned_rows(const ContactMatrix& local, const MeshPart& part, std::span<const PartContactNode> nodes) {
  std::vector<int> owned_row(nodes.size(), -1);  // per row of `local`: its owned row, or −1
  ContactMatrix out;
  for (std::size_t k = 0; k < nodes.size(); ++k)
    if (nodes[k].owned) {
      owned_row[k] = static_cast<int>(out.node_dofs.size());
      out.node_dofs.push_back(local.node_dofs[k]);
    }
  // An owned row's entries lie in owned columns (its node's, and its masters' where they are owned
  // with it: cut_part) or, where the pairs are spread, in its ghost masters' columns.
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < local.N.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(local.N, k); it; ++it)
      if (const int row = owned_row[static_cast<std::size_t>(it.row())]; row >= 0) {
        require(k < part.n_owned_dofs || part.pairs_spread, "contact row {}: dof {} is not owned with the row (a bug)",
                nodes[static_cast<std::size_t>(it.row())].row, k);
        entries.emplace_back(row, k, it.value());
      }
  out.N.resize(static_cast<Eigen::Index>(out.node_dofs.size()), local.N.cols());
  out.N.setFromTriplets(entries.begin(), entries.end());
  return out;  // (the masters' mean: local's, whose rows are the owned rows' alone: a ghost row has no masters)
}

SparseMatrix owned_columns(const SparseMatrix& A, const MeshPart& part) {
  return A.cols() == 0 ? A : SparseMatrix(A.leftCols(part.n_owned_dofs));  // (0 rows: still the owned columns)
}

namespace {

/// Adds A's entries in ghost columns (this rank's rows `rows`, `per_row` rows of A each; the slot of
/// A's row r is `slot0` + r mod per_row: 0 for N, j + 1 for T's tangent j) to the message of each
/// column's owner: (row, slot, global dof) and the value.
void send_ghost_entries(const SparseMatrix& A, int per_row, int slot0, const std::vector<int>& rows,
                        const MeshPart& part, std::vector<std::vector<long long>>& ints,
                        std::vector<std::vector<double>>& values) {
  for (int k = part.n_owned_dofs; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it) {
      const long long dof = part.global_dof[static_cast<std::size_t>(k)];
      // The part's ghost dofs are its dof layout's ghosts, in order (make_mesh_part).
      const auto to = static_cast<std::size_t>(part.dof_layout->ghost_owner(k - part.n_owned_dofs));
      const auto r = static_cast<int>(it.row());
      ints[to].insert(ints[to].end(), {rows[static_cast<std::size_t>(r / per_row)], slot0 + r % per_row, dof});
      values[to].push_back(it.value());
    }
}

}  // namespace

RemoteRows remote_pieces(const MeshPart& part, const std::vector<int>& rows, const SparseMatrix& N,
                         const SparseMatrix& T, int tangents) {
  if (!part.pairs_spread) return {};
  const auto n_ranks = static_cast<std::size_t>(part.comm.size());
  std::vector<std::vector<long long>> ints(n_ranks);
  std::vector<std::vector<double>> values(n_ranks);
  send_ghost_entries(N, 1, 0, rows, part, ints, values);
  if (tangents > 0 && T.size() > 0) send_ghost_entries(T, tangents, 1, rows, part, ints, values);
  const std::vector<std::vector<long long>> got_ints = part.comm.exchange(ints);
  const std::vector<std::vector<double>> got = part.comm.exchange(values);
  // The pieces' rows, increasing; each entry at its row's place and its owned column.
  RemoteRows out;
  for (const std::vector<long long>& in : got_ints)
    for (std::size_t e = 0; e < in.size(); e += 3) out.rows.push_back(static_cast<int>(in[e]));
  std::ranges::sort(out.rows);
  out.rows.erase(std::unique(out.rows.begin(), out.rows.end()), out.rows.end());
  const long long first = part.dof_layout->begin();
  std::vector<Eigen::Triplet<double>> n_entries, t_entries;
  std::string bad;  // a piece at a dof not owned here: a bug, every rank's error (no rank left waiting)
  for (std::size_t from = 0; from < n_ranks; ++from)
    for (std::size_t e = 0; e < got[from].size(); ++e) {
      const long long* x = got_ints[from].data() + 3 * e;
      const auto piece = static_cast<int>(std::ranges::lower_bound(out.rows, static_cast<int>(x[0])) - out.rows.begin());
      const auto col = static_cast<int>(x[2] - first);
      if (col < 0 || col >= part.n_owned_dofs) {
        if (bad.empty()) bad = fmt::format("internal: a remote piece of contact row {} at dof {}, not owned here", x[0], x[2]);
        continue;
      }
      if (x[1] == 0)
        n_entries.emplace_back(piece, col, got[from][e]);
      else
        t_entries.emplace_back(piece * tangents + static_cast<int>(x[1]) - 1, col, got[from][e]);
    }
  part.comm.throw_if_any(!bad.empty(), bad);
  const auto n_pieces = static_cast<Eigen::Index>(out.rows.size());
  out.N.resize(n_pieces, part.n_owned_dofs);
  out.N.setFromTriplets(n_entries.begin(), n_entries.end());
  if (tangents > 0) {
    out.T.resize(n_pieces * tangents, part.n_owned_dofs);
    out.T.setFromTriplets(t_entries.begin(), t_entries.end());
  }
  return out;
}

}  // namespace vpc
