#include "solvers/bond_dual.hpp"

#include "core/error.hpp"
#include "solvers/active_set_history.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <vector>

namespace vpc {

namespace {

enum State : signed char { kOff = 0, kOn = 1, kSpring = 2 };

/// The next state of row j at λ_j with the penetration d_j (b − Sλ, S without the springs 1/k).
State state_of(const Eigen::MatrixXd& S, const Vector& spring, const Vector& lower, const Vector& length,
               Eigen::Index j, double a, double lambda, double d) {
  if (!(a > 0)) return lambda - lower[j] + (d - spring[j] * lambda) / S(j, j) > 0 ? kOn : kOff;
  const double L = length[j];
  if (spring[j] > 0) return d > 0 ? kOn : d > -L ? kSpring : kOff;  // λ a function of d
  const double rho = 1 / S(j, j), z = lambda - lower[j] + rho * d;  // the resolvent's argument
  return z > 0 ? kOn : z > -(a + rho) * L ? kSpring : kOff;
}

constexpr int kBondIterations = 100;

}  // namespace

std::optional<BoxQpResult> solve_bond_states(const Eigen::MatrixXd& S, const Vector& spring, const Vector& lower,
                                             const Vector& bond, const Vector& bond_length, const Vector& b,
                                             Vector& lambda) {
  const Eigen::Index m = S.rows();
  require(S.cols() == m && spring.size() == m && lower.size() == m && bond.size() == m && bond_length.size() == m &&
              b.size() == m,
          "internal: bonded dual of {} rows with S {} x {}", m, S.rows(), S.cols());
  if (lambda.size() != m) lambda = Vector::Zero(m);
  BoxQpResult r;
  auto penetration = [&] { return Vector(b - S * lambda + spring.cwiseProduct(lambda)); };
  std::vector<signed char> state(static_cast<std::size_t>(m)), next(state.size());
  Vector d = penetration();
  for (Eigen::Index j = 0; j < m; ++j)
    state[static_cast<std::size_t>(j)] = state_of(S, spring, lower, bond_length, j, bond[j], lambda[j], d[j]);
  ActiveSetHistory history;
  for (r.iterations = 1; r.iterations <= kBondIterations; ++r.iterations) {
    std::vector<Eigen::Index> on;
    for (Eigen::Index j = 0; j < m; ++j) {
      if (state[static_cast<std::size_t>(j)] == kOff)
        lambda[j] = lower[j] - bond[j] * bond_length[j];
      else
        on.push_back(j);
    }
    const auto n = static_cast<Eigen::Index>(on.size());
    if (n > 0) {  // (S + diag(1/a − 1/k) on the springs) λ_on = b_on − S_on,off λ_off
      Eigen::MatrixXd M(n, n);
      Vector rhs(n);
      for (Eigen::Index x = 0; x < n; ++x) {
        const Eigen::Index j = on[static_cast<std::size_t>(x)];
        rhs[x] = b[j];
        for (Eigen::Index y = 0; y < n; ++y) M(x, y) = S(j, on[static_cast<std::size_t>(y)]);
        if (state[static_cast<std::size_t>(j)] == kSpring) M(x, x) += 1 / bond[j] - spring[j];
      }
      for (Eigen::Index k = 0; k < m; ++k)
        if (state[static_cast<std::size_t>(k)] == kOff)
          for (Eigen::Index x = 0; x < n; ++x) rhs[x] -= S(on[static_cast<std::size_t>(x)], k) * lambda[k];
      const Eigen::LLT<Eigen::MatrixXd> llt(M);
      if (llt.info() != Eigen::Success) return std::nullopt;
      const Vector on_lambda = llt.solve(rhs);
      for (Eigen::Index x = 0; x < n; ++x) lambda[on[static_cast<std::size_t>(x)]] = on_lambda[x];
    }
    d = penetration();
    for (Eigen::Index j = 0; j < m; ++j)
      next[static_cast<std::size_t>(j)] = state_of(S, spring, lower, bond_length, j, bond[j], lambda[j], d[j]);
    if (next == state) {
      r.converged = true;
      r.n_lower = static_cast<int>(std::count(state.begin(), state.end(), kOff));
      return r;
    }
    if (history.came_back(next, la::Comm())) return std::nullopt;
    state = next;
  }
  return std::nullopt;
}

BoxQpResult solve_bond_split(const Eigen::MatrixXd& S, const Vector& spring, const Vector& lower, const Vector& upper,
                             const Vector& bond, const Vector& bond_length, const Vector& b, Vector& lambda) {
  const Eigen::Index m = S.rows();
  if (lambda.size() != m) lambda = Vector::Zero(m);
  std::vector<Eigen::Index> bonded;
  for (Eigen::Index j = 0; j < m; ++j)
    if (bond[j] > 0) bonded.push_back(j);
  const auto nb = static_cast<Eigen::Index>(bonded.size());
  Eigen::MatrixXd H(m + nb, m + nb);
  H.topLeftCorner(m, m) = S;
  Vector rhs(m + nb), lo(m + nb), hi(m + nb), x(m + nb);
  rhs.head(m) = b;
  lo.head(m) = lower;
  hi.head(m) = upper;
  x.head(m) = lambda;
  for (Eigen::Index k = 0; k < nb; ++k) {
    const Eigen::Index j = bonded[static_cast<std::size_t>(k)];
    // The pull couples through S without the springs 1/k, which are the pressing part's alone.
    H.col(m + k).head(m) = -S.col(j);
    H(j, m + k) += spring[j];
    H.row(m + k).head(m) = H.col(m + k).head(m).transpose();
    for (Eigen::Index l = 0; l < nb; ++l) H(m + k, m + l) = S(j, bonded[static_cast<std::size_t>(l)]);
    H(m + k, m + k) += 1 / bond[j] - spring[j];
    rhs[m + k] = -b[j];
    lo[m + k] = 0;
    hi[m + k] = bond[j] * bond_length[j];
    x[m + k] = std::max(-lambda[j], 0.0);  // the warm start split: its pull, and its pressing part
    x[j] = std::max(lambda[j], lower[j]);
  }
  DenseBoxQpOperator H_op(std::move(H));
  const BoxQpResult r = solve_box_qp(H_op, rhs, lo, hi, x);
  lambda = x.head(m);
  for (Eigen::Index k = 0; k < nb; ++k) lambda[bonded[static_cast<std::size_t>(k)]] -= x[m + k];
  return r;
}

}  // namespace vpc
