#include "solvers/compliance_dual.hpp"

#include "core/error.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace vpc {

namespace {

/// Φ(λ) and, when J is given, its generalized Jacobian (rows as in the header).
Vector residual(const Eigen::MatrixXd& S, const Vector& b, const std::vector<const ContactLaw*>& laws,
                const Vector& compliance, const Vector& lower, const Vector& bond, const Vector& length,
                const Vector& lambda, Eigen::MatrixXd* J) {
  const Eigen::Index m = lambda.size();
  const Vector d = b - S * lambda;
  Vector phi(m);
  if (J) J->setZero(m, m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const ContactLaw& law = *laws[static_cast<std::size_t>(i)];
    const double a = bond.size() ? bond[i] : 0.0;
    if (law.rigid() && !(a > 0)) {  // Signorini (λ above its lower bound), −d scaled to a force by S_ii
      const double gap = -d[i] / S(i, i), above = lambda[i] - lower[i];
      if (above <= gap) {
        phi[i] = above;
        if (J) (*J)(i, i) = 1;
      } else {
        phi[i] = gap;
        if (J) J->row(i) = S.row(i) / S(i, i);  // ∂(−d_i)/∂λ = S_i
      }
      continue;
    }
    if (law.rigid()) {
      // A bonded Signorini row: λ − P(z) with z = λ − λ_0 + ρ d, ρ = 1/S_ii, P the resolvent of the row's
      // graph (closed: λ ≥ λ_0 at d = 0; the bond's spring λ = λ_0 + a d for −L < d ≤ 0; λ_0 − a L below;
      // λ_0 the law's own bound): z itself where z > 0, a z/(a + ρ) on the spring, −a L below −(a + ρ) L.
      // With a = 0 it is the row above, min(λ − λ_0, −d/S_ii); unlike a gap left −d + (λ − λ_0)/a it stays
      // well scaled as the bond weakens to 0.
      const double rho = 1 / S(i, i), L = length[i], base = lower[i] + a * L;
      const double z = lambda[i] - base + rho * d[i];
      const double slope = z > 0 ? 1.0 : z > -(a + rho) * L ? a / (a + rho) : 0.0;
      phi[i] = lambda[i] - base - (z > 0 ? z : z > -(a + rho) * L ? slope * z : -a * L);
      if (J) {  // ∂z/∂λ = e_i − ρ S_i
        J->row(i) = slope * rho * S.row(i);
        (*J)(i, i) += 1 - slope;
      }
      continue;
    }
    // A compliant row: λ = λ(d) where the node presses (d > 0), the bond's −a min(−d, L) where it does not.
    double force = 0, slope = 0;
    if (d[i] > 0 || !(a > 0)) {
      force = law.force(d[i], compliance[i]);
      slope = law.force_slope(d[i], compliance[i]);
    } else if (d[i] > -length[i]) {
      force = a * d[i];
      slope = a;
    } else {
      force = -a * length[i];
    }
    phi[i] = lambda[i] - force;
    if (J) {
      J->row(i) = slope * S.row(i);  // −∂λ(d)/∂λ = λ'(d) S_i
      (*J)(i, i) += 1;
    }
  }
  return phi;
}

}  // namespace

BoxQpResult solve_compliance_dual(const Eigen::MatrixXd& S, const Vector& b, const std::vector<const ContactLaw*>& laws,
                                  const Vector& compliance, Vector& lambda, int max_iterations,
                                  const Vector& lower_or_empty, const Vector& bond, const Vector& bond_length) {
  const Eigen::Index m = b.size();
  require(S.rows() == m && S.cols() == m && compliance.size() == m && static_cast<Eigen::Index>(laws.size()) == m,
          "internal: compliance dual of size {} with S {} x {}, {} compliances, {} laws", m, S.rows(), S.cols(),
          compliance.size(), laws.size());
  const Vector lower = lower_or_empty.size() ? lower_or_empty : Vector(Vector::Zero(m));
  require(bond.size() == 0 || (bond.size() == m && bond_length.size() == m), "internal: {} bonds and {} lengths for {} rows",
          bond.size(), bond_length.size(), m);
  if (lambda.size() != m) lambda = Vector::Zero(m);
  lambda = lambda.cwiseMax(lower);
  BoxQpResult r;
  if (m == 0) {
    r.converged = true;
    return r;
  }
  const double b_scale = (b.array() / S.diagonal().array()).abs().maxCoeff();
  auto scale = [&] { return std::max({lambda.cwiseAbs().maxCoeff(), b_scale, 1e-300}); };
  // Rows are weighted by 1/J_ii: a stiff law's row λ − k d₊^e carries round-off of d
  // times k e d^{e−1}, which the weight brings back to a force of the size of λ's error.
  Eigen::MatrixXd J;
  Vector phi = residual(S, b, laws, compliance, lower, bond, bond_length, lambda, &J);
  Vector w = J.diagonal().cwiseInverse();
  for (r.iterations = 0; r.iterations < max_iterations; ++r.iterations) {
    if (w.cwiseProduct(phi).cwiseAbs().maxCoeff() <= 1e-13 * scale()) {
      r.converged = true;
      break;
    }
    const Vector step = J.partialPivLu().solve(-phi);
    // Backtracking on ½‖WΦ‖² (Armijo along the Newton direction, where its slope is −‖WΦ‖²).
    const double merit = w.cwiseProduct(phi).squaredNorm();
    double alpha = 1, trial_merit = merit;
    Vector trial;
    for (int halving = 0; halving < 40; ++halving, alpha *= 0.5) {
      trial = lambda + alpha * step;
      trial_merit = w.cwiseProduct(residual(S, b, laws, compliance, lower, bond, bond_length, trial, nullptr)).squaredNorm();
      if (trial_merit <= (1 - 1e-4 * alpha) * merit) break;
    }
    if (!(trial_merit < merit)) break;  // no decrease at all: round-off, or a stall
    lambda = trial;
    phi = residual(S, b, laws, compliance, lower, bond, bond_length, lambda, &J);
    w = J.diagonal().cwiseInverse();
  }
  r.kkt_residual = w.cwiseProduct(phi).cwiseAbs().maxCoeff() / scale();
  r.converged = r.converged || r.kkt_residual <= 1e-13;
  lambda = lambda.cwiseMax(lower);  // a round-off below it (λ_i = k d₊^e and min(λ − lower, ·) = 0 give λ ≥ lower)
  r.n_lower = static_cast<int>((lambda.array() == lower.array()).count());
  return r;
}

}  // namespace vpc
