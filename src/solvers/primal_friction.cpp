#include "solvers/primal_friction.hpp"

#include "core/error.hpp"
#include "solvers/primal_tuning.hpp"

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
  spring_.assign(rows, 0.0);
  force_ = Vector::Zero(static_cast<Eigen::Index>(dof_.size()));
  direction_ = force_;
}

void PrimalFriction::start(const ContactConstraints& c, const std::vector<char>& active, const Vector& normal,
                           const Vector& tangential) {
  force_.setZero();
  direction_.setZero();
  gamma_ = 1;
  have_last_ = false;
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    const bool slipped = !stick_[i] && spring_[i] > 0;
    stick_[i] = 0;
    if (active[i] && tangential.size() == force_.size() && normal[e] > 0) {
      const auto l = tangential.segment(e * t_, t_);
      const double bound = c.bound(e, normal[e]), norm = l.norm();
      if (contact_status(normal[e], norm, bound) == ContactStatus::Slip) {
        if (norm > 0) force_.segment(e * t_, t_) = bound / norm * l, direction_.segment(e * t_, t_) = l / norm;
        if (!slipped) spring_[i] = 0;  // else the last solve's spring: Newton's from the first iterate
        continue;
      }
    }
    spring_[i] = 0;
    stick_[i] = active[i] && (c.tresca[e] > 0 || c.mu[e] > 0);
  }
}

void PrimalFriction::fix(std::vector<char>& fixed) const {
  for (std::size_t i = 0; i < stick_.size(); ++i)
    if (stick_[i])
      for (int j = 0; j < t_; ++j)
        if (const int dof = dof_[i * t_ + j]; dof >= 0) fixed[dof] = 1;
}

Eigen::MatrixXd PrimalFriction::across(std::size_t i) const { return across(i, spring_[i], force_); }

Eigen::MatrixXd PrimalFriction::across(std::size_t i, double k, const Vector& force) const {
  // k (I − nnᵀ) over the row's tangents that have a dof (n = the slip force's direction).
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(t_, t_);
  const auto f = force.segment(static_cast<Eigen::Index>(i) * t_, t_);
  if (stick_[i] || !(k > 0) || !(f.norm() > 0)) return P;
  const Vector n = f / f.norm();
  P = k * (Eigen::MatrixXd::Identity(t_, t_) - n * n.transpose());
  for (int j = 0; j < t_; ++j)
    if (dof_[i * t_ + j] < 0) P.row(j).setZero(), P.col(j).setZero();
  return P;
}

void PrimalFriction::springs(std::vector<Eigen::Triplet<double>>& out) const { add_springs(spring_, force_, out); }

void PrimalFriction::spring_pattern(std::vector<Eigen::Triplet<double>>& out) const {
  for (std::size_t i = 0; i < stick_.size(); ++i)
    for (int a = 0; a < t_; ++a)
      for (int b = 0; b < t_; ++b)
        if (dof_[i * t_ + a] >= 0 && dof_[i * t_ + b] >= 0) out.emplace_back(dof_[i * t_ + a], dof_[i * t_ + b], 0.0);
}

void PrimalFriction::add_springs(const std::vector<double>& spring, const Vector& force,
                                 std::vector<Eigen::Triplet<double>>& out) const {
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    if (stick_[i] || !(spring[i] > 0)) continue;
    const Eigen::MatrixXd P = across(i, spring[i], force);
    for (int a = 0; a < t_; ++a)
      for (int b = 0; b < t_; ++b)
        if (P(a, b) != 0) out.emplace_back(dof_[i * t_ + a], dof_[i * t_ + b], P(a, b));
  }
}

void PrimalFriction::load(const ContactConstraints& c, const std::vector<char>& coupled, Vector& rhs,
                          Vector& fixed_values) const {
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    const Vector force = coupled[i] ? Vector(c.tresca[e] * direction(i)) : Vector(force_.segment(e * t_, t_));
    // The body gets −λ_τ = −s n − k(I − nnᵀ)(w − h): the spring is in the matrix, the rest here.
    const Vector pull = stick_[i] ? Vector() : Vector(across(i) * c.shift.segment(e * t_, t_));
    for (int j = 0; j < t_; ++j) {
      const auto k = e * t_ + j;
      const int dof = dof_[static_cast<std::size_t>(k)];
      if (dof < 0) continue;
      if (stick_[i])
        fixed_values[dof] = c.shift[k];
      else
        rhs[dof] += pull[j] - force[j];
    }
  }
}

Vector PrimalFriction::forces(const Vector& r) const {
  // The reaction r = b − K_rot w at every row's tangent dofs: at a slip row that is s n + k (I − nnᵀ)Δ
  // up to the solver's error: the force
  // the body's equilibrium holds, whatever the iteration did.
  // A row with no force (no friction law, or out of contact) carries exactly none: its free dofs'
  // reaction is round-off.
  Vector l = Vector::Zero(force_.size());
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    if (!stick_[i] && !(spring_[i] > 0) && direction(i).isZero(0.0)) continue;
    for (int j = 0; j < t_; ++j)
      if (const int dof = dof_[i * t_ + j]; dof >= 0) l[e * t_ + j] = r[dof];
  }
  return l;
}

PrimalFriction::Next PrimalFriction::next(const ContactConstraints& c, const Vector& w, const Vector& tangential,
                                          const Vector& bound_of) const {
  Next n;
  n.stick.assign(stick_.size(), 0);
  n.force = Vector::Zero(force_.size());
  n.direction = n.force;
  n.spring.assign(stick_.size(), 0.0);
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
    // Newton's spring across it holds the turn.
    const auto used = force_.segment(e * t_, t_);
    const bool reversed = t_ == 1 && !stick_[i] && (q - used).dot(used) < 0;
    n.stick[i] = bound > 0 && (norm <= bound || reversed);
    if (n.stick[i]) continue;
    // (A direction only where the bound acts: a frictionless row, or one out of contact, has none.)
    if (norm > 0 && bound > 0) n.force.segment(e * t_, t_) = bound / norm * q, n.direction.segment(e * t_, t_) = q / norm;
    // k = s c/(|q| − s), at most kMostSpring c: a row that only just slips is nearly stuck across
    // its direction; beyond that bound the spring only slows the operator's conditioning.
    if (t_ > 1 && bound > 0)
      n.spring[i] = std::min(bound * gamma_ * scale_[i] / (norm - bound), primal_tuning::kMostSpring * scale_[i]);
    if (stick_[i]) n.excess[i] = norm - bound;
    else n.change = std::max(n.change, (n.force.segment(e * t_, t_) - tangential.segment(e * t_, t_)).cwiseAbs().maxCoeff());
  }
  return n;
}

void PrimalFriction::slip_before_leaving(const ContactConstraints& c, const std::vector<char>& was_active,
                                         const Vector& tangential, const Vector& bound, std::vector<char>& in_contact,
                                         Next& next) const {
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    if (!was_active[i] || !stick_[i] || in_contact[i] || next.stick[i] || !(c.mu[e] > 0)) continue;
    const auto l = tangential.segment(e * t_, t_);
    const double norm = l.norm();
    if (!(norm > 0)) continue;  // no reaction: nothing pulls it off but its normal force, free is right
    in_contact[i] = 1;
    next.direction.segment(e * t_, t_) = l / norm;
    next.force.segment(e * t_, t_) = bound[e] / norm * l;
    next.spring[i] = 0;  // Newton's spring: s γ c / (|q| − s) with s = 0
  }
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
      next.direction.segment(static_cast<Eigen::Index>(i) * t_, t_).setZero();
      next.spring[i] = 0;
    }
}

void PrimalFriction::secant(const ContactConstraints& c, const Vector& w, const Vector& tangential, const la::Comm& comm,
                            bool update) {
  Vector slip = Vector::Zero(force_.size());
  for (Eigen::Index k = 0; k < slip.size(); ++k)
    if (const int dof = dof_[static_cast<std::size_t>(k)]; dof >= 0) slip[k] = w[dof] - c.shift[k];
  // have_last_, not a size test: a rank without contact rows has empty vectors from the start, and a
  // collective sum on some ranks only hung foundation-3d on 2 ranks (its face on one of them).
  if (update && have_last_) {
    double sums[2] = {0, 0};
    for (std::size_t i = 0; i < stick_.size(); ++i) {
      if (stick_[i] || last_stick_[i] || !(scale_[i] > 0)) continue;  // rows that slip in both
      const auto e = static_cast<Eigen::Index>(i);
      const Vector df = tangential.segment(e * t_, t_) - last_force_.segment(e * t_, t_);
      sums[0] += df.squaredNorm() / scale_[i];
      sums[1] -= df.dot(slip.segment(e * t_, t_) - last_slip_.segment(e * t_, t_));
    }
    comm.sum(sums, 2);
    if (sums[0] > 0 && sums[1] > 0) gamma_ = std::clamp(sums[0] / sums[1], 1e-3, 1.0);
  }
  last_force_ = tangential;
  have_last_ = true;
  last_slip_ = slip;
  last_stick_ = stick_;
}

void PrimalFriction::rescale(const Vector& bound) {
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(stick_.size()); ++i) {
    auto f = force_.segment(i * t_, t_);
    if (const double norm = f.norm(); norm > 0) f *= bound[i] / norm;
  }
}

void PrimalFriction::take(Next&& next) {
  stick_ = std::move(next.stick);
  force_ = std::move(next.force);
  direction_ = std::move(next.direction);
  spring_ = std::move(next.spring);
}

std::vector<char> contact_sets(const std::vector<char>& active, const std::vector<char>& stick) {
  std::vector<char> s(active.size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = static_cast<char>(active[i] + 2 * (active[i] && stick[i]));
  return s;
}

}  // namespace vpc
