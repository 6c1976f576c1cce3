#include "mortar/dual_basis.hpp"

#include <Eigen/Cholesky>
#include <cassert>

namespace vpc::mortar {

std::array<double, 3> segment_shape(double xi) { return {(1 - xi) / 2, (1 + xi) / 2, 0}; }

std::array<double, 3> triangle_shape(double r, double s) { return {1 - r - s, r, s}; }

void add_covered_mass(std::span<const MortarPoint> points, Eigen::Matrix3d& mass) {
  for (const MortarPoint& p : points)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) mass(j, k) += p.weight * p.slave[j] * p.slave[k];
}

DualBasis dual_basis(int n, const Eigen::Matrix3d& mass, double coefficient_bound) {
  assert(n == 2 || n == 3);
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
  DualBasis b;
  b.n = n;
  b.merged = {true, true, true};
  const Small M = mass.topLeftCorner(n, n);
  if (!(M.sum() > 0)) return b;  // nothing covered (or a NaN from upstream: no basis either way)

  std::array<bool, 3> merged{false, false, n == 2};
  for (int r = n; r >= 1; --r) {
    // Ñ = T N: the kept nodes' shape functions, each with an equal share of the merged ones'.
    Small T = Small::Zero(r, n);
    std::array<int, 3> kept{};
    for (int j = 0, i = 0; j < n; ++j)
      if (!merged[j]) kept[i++] = j;
    for (int i = 0; i < r; ++i)
      for (int l = 0; l < n; ++l) T(i, l) = l == kept[i] ? 1.0 : merged[l] ? 1.0 / r : 0.0;
    const Small Mt = T * M * T.transpose();
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> d = Mt.rowwise().sum();  // ∫_C Ñ_j (Σ Ñ = 1)

    // A = D M⁻¹ (M symmetric): Aᵀ = M⁻¹ D. One kept node: Φ = Ñ = 1 on C, always accepted.
    Small A = Small::Ones(1, 1);
    bool ok = true;
    if (r > 1) {
      const Eigen::LDLT<Small> ldlt(Mt);
      A = ldlt.solve(Small(d.asDiagonal())).transpose();
      ok = ldlt.info() == Eigen::Success;
    }
    const Small c = A * T;
    if (r == 1 || (ok && c.allFinite() && c.cwiseAbs().maxCoeff() <= coefficient_bound)) {
      for (int i = 0; i < r; ++i) {
        b.a.row(kept[i]).head(n) = c.row(i);
        b.weight[kept[i]] = d[i];
      }
      b.merged = merged;
      return b;
    }
    int least = 0;  // merge the kept node with the least covered weight
    for (int i = 1; i < r; ++i)
      if (d[i] < d[least]) least = i;
    merged[kept[least]] = true;
  }
  assert(false);  // r = 1 is always accepted
  return b;
}

}  // namespace vpc::mortar
