#include "solvers/primal_friction.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

PrimalFriction::PrimalFriction(const ContactConstraints& c, const Vector& diagonal)
    : t_(c.block - 1), dof_(c.tangent_dof) {
  const auto rows = c.rows.size();
  require(t_ >= 1 && dof_.size() == rows * static_cast<std::size_t>(t_) && c.mu.size() == c.gap.size(),
          "internal: friction data of {} tangent dofs and {} coefficients for {} contact rows of {} tangents",
          dof_.size(), c.mu.size(), rows, t_);
  // One c per row (the mean of K's diagonal over its tangent dofs): with one per dof, q's fixed
  // point would put λ_τ along diag(c) Δ, not along Δ.
  for (std::size_t i = 0; i < rows; ++i) {
    double sum = 0;
    int n = 0;
    for (int j = 0; j < t_; ++j)
      if (const int dof = dof_[i * t_ + j]; dof >= 0) sum += diagonal[dof], ++n;
    scale_.push_back(n ? sum / n : 0.0);
  }
  stick_.assign(rows, 0);
  force_ = Vector::Zero(static_cast<Eigen::Index>(dof_.size()));
}

void PrimalFriction::start(const ContactConstraints& c, const std::vector<char>& active, const Vector& normal,
                           const Vector& tangential) {
  force_.setZero();
  gamma_ = 1;
  last_force_ = Vector();
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    stick_[i] = 0;
    if (!active[i]) continue;
    if (tangential.size() == force_.size() && normal[e] > 0) {
      const auto l = tangential.segment(e * t_, t_);
      const double bound = c.bound(e, normal[e]), norm = l.norm();
      if (contact_status(normal[e], norm, bound) == ContactStatus::Slip) {
        if (norm > 0) force_.segment(e * t_, t_) = bound / norm * l;
        continue;
      }
    }
    stick_[i] = c.tresca[e] > 0 || c.mu[e] > 0;
  }
}

void PrimalFriction::fix(std::vector<char>& fixed) const {
  for (std::size_t i = 0; i < stick_.size(); ++i)
    if (stick_[i])
      for (int j = 0; j < t_; ++j)
        if (const int dof = dof_[i * t_ + j]; dof >= 0) fixed[dof] = 1;
}

void PrimalFriction::load(const ContactConstraints& c, Vector& rhs, Vector& fixed_values) const {
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    for (int j = 0; j < t_; ++j) {
      const auto k = static_cast<Eigen::Index>(i * t_ + j);
      const int dof = dof_[static_cast<std::size_t>(k)];
      if (dof < 0) continue;
      if (stick_[i])
        fixed_values[dof] = c.shift[k];
      else
        rhs[dof] -= force_[k];
    }
  }
}

Vector PrimalFriction::forces(const Vector& r) const {
  Vector l = Vector::Zero(force_.size());
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    for (int j = 0; j < t_; ++j) {
      const auto k = static_cast<Eigen::Index>(i * t_ + j);
      const int dof = dof_[static_cast<std::size_t>(k)];
      if (dof >= 0) l[k] = stick_[i] ? r[dof] : force_[k];
    }
  }
  return l;
}

PrimalFriction::Next PrimalFriction::next(const ContactConstraints& c, const Vector& w, const Vector& tangential,
                                          const Vector& bound_of) const {
  Next n;
  n.stick.assign(stick_.size(), 0);
  n.force = Vector::Zero(force_.size());
  n.excess.assign(stick_.size(), -1.0);
  Vector q(t_);
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    q.setZero();
    for (int j = 0; j < t_; ++j) {
      const auto k = static_cast<Eigen::Index>(i * t_ + j);
      if (const int dof = dof_[static_cast<std::size_t>(k)]; dof >= 0)
        q[j] = tangential[k] + gamma_ * scale_[i] * (w[dof] - c.shift[k]);
    }
    const double bound = bound_of[e], norm = q.norm();
    // A zero bound (no friction law, or no normal force yet) is slip with no force. In 2D a slip
    // row that slid against its force (Δ·λ_τ < 0: no slip state has that) sticks rather than turn
    // round: q flips with the overshoot of a force that the body's stiffness cannot take, and the
    // row would swing from one direction to the other (a block dragged by its obstacle never
    // converged); from stick, its reaction decides. In 3D a direction turns continuously, and
    // that rule makes rows near the stick zone chatter between stick and slip (a 3D block pressed
    // with Poisson's spread never converged): there the secant step (secant()) damps q's turn.
    const auto used = force_.segment(e * t_, t_);
    const bool reversed = t_ == 1 && !stick_[i] && (q - used).dot(used) < 0;
    n.stick[i] = bound > 0 && (norm <= bound || reversed);
    if (n.stick[i]) continue;
    if (norm > 0) n.force.segment(e * t_, t_) = bound / norm * q;
    if (stick_[i]) n.excess[i] = norm - bound;
    else n.change = std::max(n.change, (n.force.segment(e * t_, t_) - force_.segment(e * t_, t_)).cwiseAbs().maxCoeff());
  }
  return n;
}

void PrimalFriction::slip_one(Next& next, const la::Comm& comm) const {
  std::size_t worst = stick_.size();
  double most = -1;  // excess is ≥ 0 where a stick row would slip
  for (std::size_t i = 0; i < stick_.size(); ++i)
    if (next.excess[i] > most) {
      most = next.excess[i];
      worst = i;
    }
  const double global = comm.max(most);
  for (std::size_t i = 0; i < stick_.size(); ++i)
    if (next.excess[i] >= 0 && !(i == worst && most == global)) {
      next.stick[i] = 1;  // stays stick: its dofs stay fixed, no slip force
      next.force.segment(static_cast<Eigen::Index>(i) * t_, t_).setZero();
    }
}

void PrimalFriction::take(Next&& next) {
  stick_ = std::move(next.stick);
  force_ = std::move(next.force);
}

void PrimalFriction::secant(const ContactConstraints& c, const Vector& w, const la::Comm& comm, bool update) {
  Vector slip = Vector::Zero(force_.size());
  for (Eigen::Index k = 0; k < slip.size(); ++k)
    if (const int dof = dof_[static_cast<std::size_t>(k)]; dof >= 0) slip[k] = w[dof] - c.shift[k];
  if (update && last_force_.size() == force_.size()) {
    double sums[2] = {0, 0};
    for (std::size_t i = 0; i < stick_.size(); ++i) {
      if (stick_[i] || last_stick_[i] || !(scale_[i] > 0)) continue;  // rows that slip in both
      const auto e = static_cast<Eigen::Index>(i);
      const Vector df = force_.segment(e * t_, t_) - last_force_.segment(e * t_, t_);
      sums[0] += df.squaredNorm() / scale_[i];
      sums[1] -= df.dot(slip.segment(e * t_, t_) - last_slip_.segment(e * t_, t_));
    }
    comm.sum(sums, 2);
    if (sums[0] > 0 && sums[1] > 0) gamma_ = std::clamp(sums[0] / sums[1], 1e-3, 1.0);
  }
  last_force_ = force_;
  last_slip_ = slip;
  last_stick_ = stick_;
}

void PrimalFriction::rescale(const Vector& bound) {
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(stick_.size()); ++i) {
    auto f = force_.segment(i * t_, t_);
    if (const double norm = f.norm(); norm > 0) f *= bound[i] / norm;
  }
}

Vector AndersonMixing::next(const la::Comm& comm, const Vector& x, const Vector& g) {
  const Vector f = g - x;
  if (x_last_.size() == x.size()) {
    dx_.push_back(x - x_last_);
    df_.push_back(f - f_last_);
    if (static_cast<int>(df_.size()) > depth_) {
      dx_.erase(dx_.begin());
      df_.erase(df_.begin());
    }
  }
  x_last_ = x;
  f_last_ = f;
  const auto m = static_cast<Eigen::Index>(df_.size());
  if (m == 0) return g;
  // γ = argmin ‖f − ΔF γ‖ by its normal equations (m ≤ depth numbers, the same on every rank).
  std::vector<double> sums(static_cast<std::size_t>(m * (m + 1)));
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) sums[static_cast<std::size_t>(a * m + b)] = df_[a].dot(df_[b]);
    sums[static_cast<std::size_t>(m * m + a)] = df_[a].dot(f);
  }
  comm.sum(sums.data(), static_cast<int>(sums.size()));
  Eigen::MatrixXd A(m, m);
  Vector rhs(m);
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) A(a, b) = sums[static_cast<std::size_t>(a * m + b)];
    rhs[a] = sums[static_cast<std::size_t>(m * m + a)];
  }
  const Vector gamma = A.completeOrthogonalDecomposition().solve(rhs);
  Vector out = g;
  for (Eigen::Index a = 0; a < m; ++a) out -= gamma[a] * (dx_[a] + df_[a]);
  return comm.all(out.allFinite()) ? out : g;
}

std::vector<char> contact_sets(const std::vector<char>& active, const std::vector<char>& stick) {
  std::vector<char> s(active.size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = static_cast<char>(active[i] + 2 * (active[i] && stick[i]));
  return s;
}

}  // namespace vpc
