#include "solvers/contact_frame.hpp"

#include "core/error.hpp"

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

void set_tangents(ContactConstraints& c, const std::vector<std::vector<int>>& node_dofs) {
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  const int t = c.block - 1;
  require(t >= 1 && static_cast<Eigen::Index>(node_dofs.size()) == rows,
          "internal: tangents for {} nodes of {} contact rows (block {})", node_dofs.size(), rows, c.block);
  // In w = Qu a row's normal is its dof k (rotated_rows) and every other free dof j of its node
  // is a tangent: Q e_j is a unit vector orthogonal to ν (Q is a reflection, symmetric).
  const SparseMatrix Q = contact_reflections(c.N);
  const std::vector<RotatedRow> normal = rotated_rows(c.N);
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
  c.shift = Vector::Zero(rows * t);
  c.tresca = Vector::Zero(rows);
  if (c.mu.size() != rows) c.mu = Vector::Zero(rows);
}

}  // namespace vpc
