#include "solvers/primal_friction.hpp"

#include "core/error.hpp"
#include "solvers/primal_tuning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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
  bond_.assign(rows, 0);
  spring_.assign(rows, 0.0);
  force_ = Vector::Zero(static_cast<Eigen::Index>(dof_.size()));
  direction_ = force_;
  normal_ = force_;
  for (std::size_t i = 0; i < rows; ++i) disc_.push_back(c.friction_of(static_cast<Eigen::Index>(i)).disc());
}

namespace {

/// ν̂ at a point p of ∂C_1 of a law with two tangents: the unit ν whose support point (∂P/∂s at s = 0,
/// the point of C_1 where ν·x is largest) lies along p, by the secant method on its angle from `guess`'s
/// (on the disc, and an ellipse of equal axes, one step gives p/|p|).
Vector normal_at(const FrictionLaw& law, const Vector& p, const Vector& guess) {
  auto off = [&](double phi) {  // the angle from the support point of ν(φ) to p
    const double nu[2] = {std::cos(phi), std::sin(phi)};
    double D[4], g[2];
    law.project_derivative(nu, 2, 0.0, D, g);
    return std::atan2(g[0] * p[1] - g[1] * p[0], g[0] * p[0] + g[1] * p[1]);
  };
  double a = std::atan2(guess[1], guess[0]), fa = off(a), b = a + fa, fb = off(b);
  for (int it = 0; it < 50 && fb != 0 && fb != fa && std::abs(b - a) > 1e-15; ++it) {
    const double c = b - fb * (b - a) / (fb - fa);
    a = b, fa = fb, b = c, fb = off(b);
  }
  Vector nu(2);
  nu << std::cos(b), std::sin(b);
  return nu;
}

}  // namespace

double force_size(const FrictionLaw& law, Eigen::Ref<const Vector> l) {
  return law.disc() ? l.norm() : law.gauge(l.data(), static_cast<int>(l.size()));
}

PrimalFriction::Slip PrimalFriction::slip(const FrictionLaw& law, std::size_t i, const Vector& z, double s) const {
  Slip out;
  if (law.disc()) {  // n = ν̂ = z/|z|, k = s γ c/(|z| − s), as the disc's rows were computed before the laws
    const double norm = z.norm();
    out.force = s / norm * z;
    out.direction = z / norm;
    out.normal = out.direction;
    out.spring = s * gamma_ * scale_[i] / (norm - s);
    return out;
  }
  // The law's P, D = ∂P/∂z and p_s = ∂P/∂s at (z, s): n = (I − D)⁻¹ p_s, ν̂ ∥ z − P, k = γ c d/(1 − d).
  const int t = t_;
  Vector p(t), dp_ds(t);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> D(t, t);
  law.project(z.data(), t, s, p.data());
  law.project_derivative(z.data(), t, s, D.data(), dp_ds.data());
  out.direction = (Eigen::MatrixXd::Identity(t, t) - D).partialPivLu().solve(dp_ds);
  out.force = s * out.direction;
  out.normal = z - p;
  out.normal /= out.normal.norm();  // z outside C_s: z ≠ P(z)
  if (t == 2) {
    const Eigen::Vector2d across(-out.normal[1], out.normal[0]);
    const double d = across.dot(D * across);  // D's eigenvalue across ν̂, in [0, 1) outside C_s
    out.spring = d <= 0 ? 0.0 : d < 1 ? gamma_ * scale_[i] * d / (1 - d) : std::numeric_limits<double>::infinity();
  }
  return out;
}

Vector PrimalFriction::along(std::size_t i) const {
  if (disc_[i]) return direction(i);
  const auto seg = normal_.segment(static_cast<Eigen::Index>(i) * t_, t_);
  const double dot = seg.dot(direction(i));
  return dot != 0 ? Vector(seg / dot) : Vector(Vector::Zero(t_));
}

void PrimalFriction::start(const ContactConstraints& c, const std::vector<char>& active, const Vector& normal,
                           const Vector& tangential) {
  force_.setZero();
  direction_.setZero();
  gamma_ = 1;
  have_last_ = false;
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    const bool slipped = !stick_[i] && spring_[i] > 0 && !bond_[i];
    stick_[i] = 0;
    if (const double a = c.shear_bond_of(e); a > 0) {  // a tangential bond: its state from the warm start's force
      const double L = c.bond_length_of(e);
      const Vector l = tangential.size() == force_.size() ? Vector(tangential.segment(e * t_, t_)) : Vector(Vector::Zero(t_));
      const BondState b = bond_state(l / a, a, L);  // v = λ_τ/a within L: the warm start's stretch, or beyond by its force
      bond_[i] = b.state, spring_[i] = b.spring;
      force_.segment(e * t_, t_) = b.force;
      direction_.segment(e * t_, t_) = b.direction;
      continue;
    }
    bond_[i] = 0;
    if (active[i] && tangential.size() == force_.size() && normal[e] > 0) {
      const auto l = tangential.segment(e * t_, t_);
      const FrictionLaw& law = c.friction_of(e);
      const double bound = c.bound(e, normal[e]), norm = force_size(law, l);
      if (contact_status(normal[e], norm, bound) == ContactStatus::Slip) {
        if (norm > 0) force_.segment(e * t_, t_) = bound / norm * l, direction_.segment(e * t_, t_) = l / norm;
        // (Another set's: l/|l|_C on ∂C_1, its spring across the set's normal there, as the disc's.)
        if (!disc_[i] && norm > 0) {
          auto nu = normal_.segment(e * t_, t_);
          const Vector n = l / norm;
          nu = t_ == 1 ? Vector(n.cwiseSign()) : normal_at(law, n, nu.isZero(0.0) ? n : Vector(nu));
        }
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

Eigen::MatrixXd PrimalFriction::across(std::size_t i) const {
  // k (I − ν̂ν̂ᵀ) over the row's tangents that have a dof (on the disc ν̂ = the slip force's direction).
  const double k = spring_[i];
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(t_, t_);
  const auto f = force_.segment(static_cast<Eigen::Index>(i) * t_, t_);
  if (bond_[i] == kBondSpring) {  // the bond's spring a_τ on every tangent
    P = k * Eigen::MatrixXd::Identity(t_, t_);
    for (int j = 0; j < t_; ++j)
      if (dof_[i * t_ + j] < 0) P.row(j).setZero(), P.col(j).setZero();
    return P;
  }
  if (stick_[i] || !(k > 0) || !(f.norm() > 0)) return P;
  const Vector n = disc_[i] ? Vector(f / f.norm()) : Vector(normal_.segment(static_cast<Eigen::Index>(i) * t_, t_));
  P = k * (Eigen::MatrixXd::Identity(t_, t_) - n * n.transpose());
  for (int j = 0; j < t_; ++j)
    if (dof_[i * t_ + j] < 0) P.row(j).setZero(), P.col(j).setZero();
  return P;
}

void PrimalFriction::springs(std::vector<Eigen::Triplet<double>>& out) const {
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    if (stick_[i] || !(spring_[i] > 0)) continue;
    const Eigen::MatrixXd P = across(i);
    for (int a = 0; a < t_; ++a)
      for (int b = 0; b < t_; ++b)
        if (P(a, b) != 0) out.emplace_back(dof_[i * t_ + a], dof_[i * t_ + b], P(a, b));
  }
}

void PrimalFriction::spring_pattern(std::vector<Eigen::Triplet<double>>& out) const {
  for (std::size_t i = 0; i < stick_.size(); ++i)
    for (int a = 0; a < t_; ++a)
      for (int b = 0; b < t_; ++b)
        if (dof_[i * t_ + a] >= 0 && dof_[i * t_ + b] >= 0) out.emplace_back(dof_[i * t_ + a], dof_[i * t_ + b], 0.0);
}

void PrimalFriction::load(const ContactConstraints& c, const std::vector<char>& coupled, Vector& rhs,
                          Vector& fixed_values) const {
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    const Vector force = coupled[i] ? Vector(c.tresca[e] * direction(i)) : Vector(force_.segment(e * t_, t_));
    // The body gets −λ_τ = −s n − k(I − nnᵀ)(w − h): the spring is in the matrix, the rest here.
    const Vector pull = stick_[i] ? Vector() : Vector(across(i) * rest(c, i));
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
  n.normal = n.force;
  n.spring.assign(stick_.size(), 0.0);
  n.excess.assign(stick_.size(), -1.0);
  n.bond.assign(stick_.size(), 0);
  Vector q(t_);
  for (std::size_t i = 0; i < stick_.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    if (const double a = c.shear_bond_of(e); a > 0) {  // a tangential bond: its state at the iterate's stretch
      Vector v = Vector::Zero(t_);
      const Vector h = rest(c, i);
      for (int j = 0; j < t_; ++j)
        if (const int dof = dof_[i * t_ + j]; dof >= 0) v[j] = w[dof] - h[j];
      const BondState b = bond_state(v, a, c.bond_length_of(e));
      n.bond[i] = b.state, n.spring[i] = b.spring;
      n.force.segment(e * t_, t_) = b.force;
      n.direction.segment(e * t_, t_) = b.direction;
      const Vector now = b.state == kBondSpring ? Vector(a * v) : b.force;
      n.change = std::max(n.change, (now - tangential.segment(e * t_, t_)).cwiseAbs().maxCoeff());
      continue;
    }
    q.setZero();
    for (int j = 0; j < t_; ++j) {
      const auto k = static_cast<Eigen::Index>(i * t_ + j);
      if (const int dof = dof_[static_cast<std::size_t>(k)]; dof >= 0)
        q[j] = tangential[k] + gamma_ * scale_[i] * (w[dof] - c.shift[k]);
    }
    const FrictionLaw& law = c.friction_of(e);
    const double bound = bound_of[e], norm = force_size(law, q);
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
    // (A direction only where the bound acts: a frictionless row, or one out of contact, has none;
    // not stick, a row with a bound has |q|_C > s > 0.)
    if (norm > 0 && bound > 0) {
      const Slip at = slip(law, i, q, bound);
      n.force.segment(e * t_, t_) = at.force, n.direction.segment(e * t_, t_) = at.direction;
      if (!disc_[i]) n.normal.segment(e * t_, t_) = at.normal;
      // k = s γ c/(|q| − s) on the disc, at most kMostSpring c: a row that only just slips is nearly
      // stuck across its direction; beyond that bound the spring only slows the operator's conditioning.
      if (t_ > 1) n.spring[i] = std::min(at.spring, primal_tuning::kMostSpring * scale_[i]);
    }
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
    const Vector l = tangential.segment(e * t_, t_);
    if (l.isZero(0.0)) continue;  // no reaction: nothing pulls it off but its normal force, free is right
    in_contact[i] = 1;
    const Slip at = slip(c.friction_of(e), i, l, bound[e]);  // (its q is l: a stick row's Δ is 0)
    next.direction.segment(e * t_, t_) = at.direction;
    next.force.segment(e * t_, t_) = at.force;
    if (!disc_[i]) next.normal.segment(e * t_, t_) = at.normal;
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
      if (stick_[i] || last_stick_[i] || bond_[i] || !(scale_[i] > 0)) continue;  // rows that slip in both (not bonds)
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
    if (!disc_[static_cast<std::size_t>(i)]) {
      if (!f.isZero(0.0)) f = bound[i] * direction(static_cast<std::size_t>(i));  // s n, n on ∂C_1
    } else if (const double norm = f.norm(); norm > 0) {
      f *= bound[i] / norm;
    }
  }
}

void PrimalFriction::take(Next&& next) {
  stick_ = std::move(next.stick);
  bond_ = std::move(next.bond);
  force_ = std::move(next.force);
  direction_ = std::move(next.direction);
  normal_ = std::move(next.normal);
  spring_ = std::move(next.spring);
}

PrimalFriction::BondState PrimalFriction::bond_state(const Vector& v, double a, double L) const {
  BondState b{kBondSpring, Vector::Zero(t_), Vector::Zero(t_), a};
  const double size = v.norm();
  if (size <= L) return b;  // λ_τ = a v: the spring on the tangent dofs, no constant force
  b.state = kBondPulled;    // λ_τ = a L n: a constant force along n and Newton's spring across it
  b.direction = v / size;
  b.force = a * L / size * v;
  b.spring = t_ > 1 ? a * L / size : 0.0;
  return b;
}

Vector PrimalFriction::rest(const ContactConstraints& c, std::size_t i) const {
  const auto e = static_cast<Eigen::Index>(i);
  Vector h = c.shift.segment(e * t_, t_);
  if (c.shear_bond_of(e) > 0) h -= c.bond_stretch.segment(e * t_, t_);  // (set with the bond: set_bond_data)
  return h;
}

std::vector<char> contact_sets(const std::vector<char>& active, const std::vector<char>& stick,
                               const std::vector<char>& bond) {
  std::vector<char> s(active.size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = static_cast<char>(active[i] + 2 * (active[i] && stick[i]) + 4 * bond[i]);
  return s;
}

}  // namespace vpc
