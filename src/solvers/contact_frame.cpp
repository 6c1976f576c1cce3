#include "solvers/contact_frame.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

std::vector<RotatedRow> rotated_rows(const SparseMatrix& N) {
  const SparseMatrix Nt = N.transpose();
  std::vector<RotatedRow> rows(static_cast<size_t>(N.rows()));
  for (int i = 0; i < Nt.outerSize(); ++i) {
    double rho2 = 0, best = -1;
    const bool reflected = Nt.col(i).nonZeros() > 1;  // then Q e_k = −sν (see contact_reflections)
    for (SparseMatrix::InnerIterator it(Nt, i); it; ++it) {
      rho2 += it.value() * it.value();
      if (std::abs(it.value()) > best) {
        best = std::abs(it.value());
        rows[i].dof = static_cast<int>(it.row());
        rows[i].alpha = (it.value() < 0) != reflected ? -1.0 : 1.0;
      }
    }
    require(rows[i].dof >= 0, "internal: contact row {} has no entries", i);
    rows[i].alpha *= std::sqrt(rho2);
  }
  return rows;
}

SparseMatrix contact_reflections(const SparseMatrix& N) {
  const SparseMatrix Nt = N.transpose();
  bool rotate = false;
  for (int i = 0; i < Nt.outerSize() && !rotate; ++i) rotate = Nt.col(i).nonZeros() > 1;
  if (!rotate) return {};
  const std::vector<RotatedRow> rows = rotated_rows(N);
  std::vector<Eigen::Triplet<double>> t;
  std::vector<char> reflected(static_cast<size_t>(N.cols()), 0);
  for (int i = 0; i < Nt.outerSize(); ++i) {
    if (Nt.col(i).nonZeros() < 2) continue;
    // v = e_k + sν over the row's dofs (s = sign ν_k: no cancellation, vᵀv ≥ 2);
    // H = I − 2vvᵀ/(vᵀv) maps e_k to −sν, so N_i Q e_k = −ρs = α_i.
    const double rho = std::abs(rows[i].alpha), s = rows[i].alpha < 0 ? 1.0 : -1.0;
    std::vector<std::pair<int, double>> v;
    for (SparseMatrix::InnerIterator it(Nt, i); it; ++it)
      v.emplace_back(static_cast<int>(it.row()), (it.row() == rows[i].dof ? 1.0 : 0.0) + s * it.value() / rho);
    double vv = 0;
    for (const auto& [j, x] : v) vv += x * x;
    for (const auto& [j, x] : v) {
      require(!reflected[j], "internal: contact rows {} share dof {}", i, j);
      reflected[j] = 1;
      for (const auto& [l, y] : v) t.emplace_back(j, l, (j == l ? 1.0 : 0.0) - 2 * x * y / vv);
    }
  }
  for (int j = 0; j < N.cols(); ++j)
    if (!reflected[j]) t.emplace_back(j, j, 1.0);
  SparseMatrix Q(N.cols(), N.cols());
  Q.setFromTriplets(t.begin(), t.end());
  return Q;
}

namespace {

/// N split into each row's own node's entries and the rest (a pair row's masters').
std::pair<SparseMatrix, SparseMatrix> split_rows(const SparseMatrix& N, const std::vector<std::vector<int>>& node_dofs) {
  require(static_cast<Eigen::Index>(node_dofs.size()) == N.rows(), "internal: node dofs of {} rows for {} contact rows",
          node_dofs.size(), N.rows());
  std::vector<Eigen::Triplet<double>> own, masters;
  for (int k = 0; k < N.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(N, k); it; ++it) {
      const std::vector<int>& mine = node_dofs[static_cast<std::size_t>(it.row())];
      (std::find(mine.begin(), mine.end(), k) != mine.end() ? own : masters)
          .emplace_back(static_cast<int>(it.row()), k, it.value());
    }
  SparseMatrix A(N.rows(), N.cols()), B(N.rows(), N.cols());
  A.setFromTriplets(own.begin(), own.end());
  B.setFromTriplets(masters.begin(), masters.end());
  return {std::move(A), std::move(B)};
}

/// The first master column of `masters` that is some row's own dof (−1: none).
int slave_among_masters(const SparseMatrix& masters, const std::vector<std::vector<int>>& node_dofs) {
  std::vector<char> own(static_cast<std::size_t>(masters.cols()), 0);
  for (const std::vector<int>& dofs : node_dofs)
    for (const int k : dofs) own[static_cast<std::size_t>(k)] = 1;
  for (int k = 0; k < masters.outerSize(); ++k)
    if (masters.col(k).nonZeros() > 0 && own[static_cast<std::size_t>(k)]) return k;
  return -1;
}

}  // namespace

bool masters_apart_from_slaves(const SparseMatrix& N, const std::vector<std::vector<int>>& node_dofs,
                               const SparseMatrix& master_mean) {
  return node_dofs.empty() || (slave_among_masters(split_rows(N, node_dofs).second, node_dofs) < 0 &&
                               (master_mean.size() == 0 || slave_among_masters(master_mean, node_dofs) < 0));
}

ContactBasis contact_basis(const SparseMatrix& N, const std::vector<std::vector<int>>& node_dofs,
                           const SparseMatrix& master_mean) {
  ContactBasis b;
  if (node_dofs.empty()) {
    b.P = contact_reflections(N);
    b.rows = rotated_rows(N);
    return b;
  }
  const auto [own, masters] = split_rows(N, node_dofs);
  b.rows = rotated_rows(own);
  SparseMatrix H = contact_reflections(own);
  const bool mean = master_mean.nonZeros() > 0;
  if (masters.nonZeros() == 0 && !mean) {
    b.P = std::move(H);
    return b;
  }
  int slave = slave_among_masters(masters, node_dofs);
  if (slave < 0 && mean) slave = slave_among_masters(master_mean, node_dofs);
  require(slave < 0,
          "free dof {} is a contact pair's slave dof and a master dof of another row (a node on the slave and the "
          "master side): the primal contact solver needs them apart; --contact-solver active-set solves it",
          slave);
  const Eigen::Index n = N.cols();
  if (H.size() == 0) {
    H.resize(n, n);
    H.setIdentity();
  }
  // P = H + F, F = M + E. M (friction only) moves every free dof of a slave node by its masters'
  // weighted mean, so that its tangential dofs in w are the slip relative to the master side too.
  // E = −Σ_i (H e_{k_i}/α_i) r_i cancels what N_i (H + M) has on master dofs, r_i = m_i H + own_i M
  // (m_i row i's master part; without M, r_i = m_i H and N_i E = −m_i H), so N_i P w = α_i w_k.
  SparseMatrix R = masters * H;
  if (mean) R = SparseMatrix(R + own * master_mean).pruned();  // 0 where M and m agree (no slave dof fixed)
  std::vector<Eigen::Triplet<double>> t;
  for (std::size_t i = 0; i < b.rows.size(); ++i)
    for (SparseMatrix::InnerIterator it(H, b.rows[i].dof); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), static_cast<int>(i), it.value() / b.rows[i].alpha);
  SparseMatrix C(n, N.rows());
  C.setFromTriplets(t.begin(), t.end());
  SparseMatrix F = -(C * R);
  if (mean) F += master_mean;
  // F's rows are slave dofs, its columns master dofs, so (FH)² = 0 and P⁻¹ = (I − FH)H = H − HFH.
  b.P = H + F;
  b.P_inverse = H - SparseMatrix(H * F * H);
  return b;
}

void set_tangents(ContactConstraints& c, const std::vector<std::vector<int>>& node_dofs) {
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  const int t = c.block - 1;
  require(t >= 1 && static_cast<Eigen::Index>(node_dofs.size()) == rows,
          "internal: tangents for {} nodes of {} contact rows (block {})", node_dofs.size(), rows, c.block);
  // In w = Qu a row's normal is its dof k (rotated_rows) and every other free dof j of its node
  // is a tangent: Q e_j is a unit vector orthogonal to ν (Q is a reflection, symmetric). A pair
  // row's frame is its own node's (its master entries are the masters' share of ν, not ν).
  const SparseMatrix own = split_rows(c.N, node_dofs).first;
  const SparseMatrix Q = contact_reflections(own);
  const std::vector<RotatedRow> normal = rotated_rows(own);
  std::vector<Eigen::Triplet<double>> entries;
  c.tangent_dof.assign(static_cast<std::size_t>(rows * t), -1);
  for (Eigen::Index i = 0; i < rows; ++i) {
    int j = 0;
    for (const int dof : node_dofs[static_cast<std::size_t>(i)]) {
      if (dof == normal[static_cast<std::size_t>(i)].dof) continue;
      require(j < t, "internal: contact row {} has more than {} tangents", i, t);
      const auto row = static_cast<int>(i * t + j);
      c.tangent_dof[static_cast<std::size_t>(row)] = dof;
      if (Q.size() == 0) {
        entries.emplace_back(row, dof, 1.0);
      } else {
        for (SparseMatrix::InnerIterator it(Q, dof); it; ++it) entries.emplace_back(row, static_cast<int>(it.row()), it.value());
      }
      ++j;
    }
  }
  c.T.resize(rows * t, c.N.cols());
  c.T.setFromTriplets(entries.begin(), entries.end());
  if (c.master_mean.nonZeros() > 0) c.T = SparseMatrix(c.T - c.T * c.master_mean);  // t·(u_j − Σ w_k u_k)
  c.shift = Vector::Zero(rows * t);
  c.tresca = Vector::Zero(rows);
  if (c.mu.size() != rows) c.mu = Vector::Zero(rows);
}

}  // namespace vpc
