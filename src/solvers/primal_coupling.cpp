#include "solvers/primal_coupling.hpp"

#include "solvers/primal_operator.hpp"

#include <algorithm>

namespace vpc {

la::Perturbation CoulombCoupling::build(const PrimalOperator& op, const PrimalFriction& friction, bool couple,
                                        const std::vector<char>& active, const Vector& b, Vector& rhs,
                                        Vector& law_rhs) {
  const ContactConstraints& c = op.constraints();
  const std::vector<RotatedRow>& rows = op.rows();
  const int t = friction.tangents();
  coupled_.assign(rows.size(), 0);
  entries_.clear();
  law_rows_.clear();
  bool signorini = false;
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    // (A bonded row on its bond's spring pulls: its bound μ max(λ_ν, 0) does not move with λ_ν there.)
    if (!couple || active[i] != PrimalOperator::kOn || friction.stick()[i] || !(c.mu[e] > 0) ||
        friction.direction(i).isZero(0.0))
      continue;
    // At its shear limit the bound does not move with λ_ν: the force s n stays a load (its size
    // |s n|_C = s to s's rounding).
    if (force_size(c.friction_of(e), friction.slip_force(i)) >= (1 - 1e-12) * c.bound_of(e).limit) continue;
    coupled_[i] = 1;
    const RotatedRow& row = rows[i];
    const bool law = law_determines(e, c);
    if (law) law_rows_.push_back({{}, Vector::Zero(t), friction.along(i), 1 / c.mu[e]});
    for (int j = 0; j < t; ++j) {
      const int dof = friction.tangent_dof(i, j);
      if (law) {
        law_rows_.back().dofs.push_back(dof);
        if (dof >= 0) law_rows_.back().n[j] = friction.direction(i)[j];
      }
      // μ n_j, over μ at a law row (D's factor along n; D n = n/μ)
      const double mu_n = (law ? 1.0 : c.mu[e]) * friction.direction(i)[j];
      if (dof < 0 || mu_n == 0) continue;
      Vector& load = law ? law_rhs : rhs;
      if (op.compliant(e)) {
        entries_.push_back({dof, row.dof, mu_n * row.alpha / op.spring(i), false});
        load[dof] += mu_n * c.gap[e] / op.spring(i);
      } else {
        entries_.push_back({dof, row.dof, -mu_n / row.alpha, true});
        load[dof] -= mu_n / row.alpha * b[row.dof];
        signorini = true;
      }
    }
  }
  const la::Comm& comm = op.comm();
  weighted_ = comm.any(!law_rows_.empty());
  any_entries_ = comm.any(!entries_.empty());
  if (!any_entries_ && !op.changed()) return {};
  // K_rot's normal rows at the coupled Signorini rows only (collective): with the whole product
  // a GMRES iteration cost 1.8 CG iterations (frictional foundation-3d n = 40, 2 ranks).
  la::RowProduct normal_rows;
  if (comm.any(signorini)) {
    std::vector<int> dofs;
    for (const Entry& x : entries_)
      if (x.reaction) dofs.push_back(x.normal);
    std::sort(dofs.begin(), dofs.end());
    dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
    for (Entry& x : entries_)
      if (x.reaction) x.normal = static_cast<int>(std::lower_bound(dofs.begin(), dofs.end(), x.normal) - dofs.begin());
    normal_rows = op.K_rot().rows(dofs);
  }
  // (Applied within the operator's solve: `op`, its A and spring change, outlive it.)
  return [this, &op, normal_rows](const Vector& x, Vector& y) {
    y = Vector::Zero(x.size());
    Vector Kx;
    if (normal_rows) normal_rows(x, Kx);
    for (const Entry& entry : entries_)
      y[entry.tangent] += entry.coefficient * (entry.reaction ? Kx[entry.normal] : x[entry.normal]);
    Vector change;
    if (op.changed()) op.change(x, change);
    if (!weighted_) {
      if (op.changed()) y += change;
      return;
    }
    Vector Ax, v;  // (D − I) A x + D (A now − A) x (collective: A's product)
    op.A().mult(x, Ax);
    v = op.changed() ? Vector(Ax + change) : Ax;
    weigh(v);
    y += v - Ax;
  };
}

void CoulombCoupling::weigh(Vector& y) const {
  for (const LawRow& x : law_rows_) {
    double along = 0;
    for (std::size_t j = 0; j < x.dofs.size(); ++j)
      if (x.dofs[j] >= 0) along += x.v[static_cast<Eigen::Index>(j)] * y[x.dofs[j]];
    for (std::size_t j = 0; j < x.dofs.size(); ++j)
      if (const int dof = x.dofs[j]; dof >= 0) {
        const double n = x.n[static_cast<Eigen::Index>(j)];
        y[dof] = (y[dof] - along * n) + x.inverse * along * n;
      }
  }
}

double CoulombCoupling::law_normal_force(Eigen::Index i, const Vector& r, const PrimalFriction& friction,
                                         const ContactConstraints& c) {
  const auto row = static_cast<std::size_t>(i);
  const Vector v = friction.along(row);
  double along = 0;
  for (int j = 0; j < friction.tangents(); ++j)
    if (const int dof = friction.tangent_dof(row, j); dof >= 0) along += v[j] * r[dof];
  return c.bound_of(i).normal_force_at(along);
}

}  // namespace vpc
