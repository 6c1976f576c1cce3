#include "verification/norms.hpp"

#include "core/error.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace vpc {

DiscreteNorms::DiscreteNorms(const Mesh& mesh, const Elasticity& elasticity)
    : mesh_(mesh), elasticity_(elasticity), geo_(compute_geometry(mesh)) {
  M_ = assemble_mass(mesh, geo_);
  A_ = assemble_laplacian(mesh, geo_);
}

double DiscreteNorms::energy(const Vector& e) const {
  std::vector<SymTensor> eps;
  compute_strain(mesh_, geo_, e, eps);
  double s = 0;
  for (int c = 0; c < mesh_.n_cells(); ++c) s += geo_[c].volume * elasticity_.apply(eps[c]).dot(eps[c]);
  return std::sqrt(std::max(s, 0.0));
}

double DiscreteNorms::l2_vector(const Vector& e) const {
  const int d = mesh_.dim();
  double s = 0;
  for (int i = 0; i < d; ++i) {
    const Vector ei = Eigen::Map<const Vector, 0, Eigen::InnerStride<>>(e.data() + i, mesh_.n_nodes(),
                                                                         Eigen::InnerStride<>(d));
    s += ei.dot(M_ * ei);
  }
  return std::sqrt(std::max(s, 0.0));
}

double DiscreteNorms::l2(const std::vector<SymTensor>& tau) const {
  double s = 0;
  for (int c = 0; c < mesh_.n_cells(); ++c) s += geo_[c].volume * tau[c].dot(tau[c]);
  return std::sqrt(s);
}

double DiscreteNorms::l2(const Vector& e) const { return std::sqrt(std::max(e.dot(M_ * e), 0.0)); }

double DiscreteNorms::h1_seminorm(const Vector& e) const { return std::sqrt(std::max(e.dot(A_ * e), 0.0)); }

namespace {

/// Gauss–Jacobi rule on [0, 1] for the weight (1 − s)^alpha, m points (Golub–Welsch).
void gauss_jacobi01(int m, int alpha, std::vector<double>& nodes, std::vector<double>& weights) {
  // Monic Jacobi recurrence on [−1, 1] with weight (1 − x)^α (1 + x)^0.
  const double a = alpha, b = 0;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, m);
  for (int n = 0; n < m; ++n) {
    const double s = 2 * n + a + b;
    J(n, n) = n == 0 ? (b - a) / (a + b + 2) : (b * b - a * a) / (s * (s + 2));
    if (n + 1 < m) {
      const double k = n + 1, t = 2 * k + a + b;
      const double beta = 4 * k * (k + a) * (k + b) * (k + a + b) / (t * t * (t + 1) * (t - 1));
      J(n, n + 1) = J(n + 1, n) = std::sqrt(beta);
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(J);
  // μ0 = ∫_{−1}^{1} (1 − x)^α dx = 2^{α+1} / (α + 1); mapping x = 2s − 1 divides by 2^{α+1}.
  const double mu0 = std::pow(2.0, a + 1) / (a + 1);
  nodes.resize(m);
  weights.resize(m);
  for (int i = 0; i < m; ++i) {
    nodes[i] = 0.5 * (es.eigenvalues()[i] + 1);
    const double v0 = es.eigenvectors()(0, i);
    weights[i] = mu0 * v0 * v0 / std::pow(2.0, a + 1);
  }
}

}  // namespace

std::vector<QuadraturePoint> conical_product_rule(int d, int m) {
  require(d >= 1 && d <= 3 && m >= 1, "conical_product_rule: need 1 <= d <= 3 and m >= 1 (got d = {}, m = {})", d, m);
  // Collapsed coordinates: x1 = s1, x2 = (1 − s1) s2, x3 = (1 − s1)(1 − s2) s3, with
  // Jacobian (1 − s1)^{d−1} (1 − s2)^{d−2}: Gauss–Jacobi in s1 (α = d − 1), s2 (α = d − 2), ...
  std::vector<double> s[3], w[3];
  for (int j = 0; j < d; ++j) gauss_jacobi01(m, d - 1 - j, s[j], w[j]);
  static const double factorial[4] = {1, 1, 2, 6};
  std::vector<QuadraturePoint> rule;
  const int n = static_cast<int>(std::pow(m, d));
  for (int p = 0; p < n; ++p) {
    int idx[3] = {0, 0, 0};
    for (int j = 0, q = p; j < d; ++j, q /= m) idx[j] = q % m;
    double x[3] = {0, 0, 0}, weight = factorial[d], rest = 1;
    for (int j = 0; j < d; ++j) {
      const double sj = s[j][idx[j]];
      x[j] = rest * sj;
      rest *= 1 - sj;
      weight *= w[j][idx[j]];
    }
    QuadraturePoint qp;
    qp.lambda = {1 - x[0] - x[1] - x[2], x[0], x[1], x[2]};
    qp.weight = weight;
    rule.push_back(qp);
  }
  return rule;
}

ExactSolution::Values ExactSolution::values(const Point& x, double t) const {
  Values v;
  v.u = u(x, t);
  v.grad_u = grad_u(x, t);
  v.sigma = sigma(x, t);
  v.beta = beta(x, t);
  v.grad_beta = grad_beta(x, t);
  return v;
}

FieldErrors errors_against_exact(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                 const Elasticity& elasticity, const State& state, const ExactSolution& exact,
                                 double t, const std::vector<QuadraturePoint>& rule) {
  const int d = mesh.dim();
  double eu = 0, ul2 = 0, es = 0, eb = 0, eg = 0;
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const int* v = mesh.cell(c);
    const CellGeometry& g = geo[c];
    // Constant parts of the discrete fields on this cell.
    const SymTensor& eps_h = state.eps[c];
    const SymTensor& sigma_h = state.sigma[c];
    Point grad_beta_h{0, 0, 0};
    for (int a = 0; a <= d; ++a)
      for (int j = 0; j < d; ++j) grad_beta_h[j] += state.beta[v[a]] * g.grad[a][j];
    for (const auto& q : rule) {
      Point x{0, 0, 0}, u_h{0, 0, 0};
      double beta_h = 0;
      for (int a = 0; a <= d; ++a) {
        for (int j = 0; j < 3; ++j) x[j] += q.lambda[a] * mesh.node(v[a])[j];
        for (int i = 0; i < d; ++i) u_h[i] += q.lambda[a] * state.u[v[a] * d + i];
        beta_h += q.lambda[a] * state.beta[v[a]];
      }
      const double w = q.weight * g.volume;
      const ExactSolution::Values ev = exact.values(x, t);
      const Point& u = ev.u;
      const auto& gu = ev.grad_u;
      SymTensor e;
      for (int i = 0; i < d; ++i) e[i] = gu[i][i];
      if (d >= 2) e[5] = 0.5 * (gu[0][1] + gu[1][0]);
      if (d == 3) {
        e[3] = 0.5 * (gu[1][2] + gu[2][1]);
        e[4] = 0.5 * (gu[0][2] + gu[2][0]);
      }
      e -= eps_h;
      eu += w * elasticity.apply(e).dot(e);
      for (int i = 0; i < d; ++i) ul2 += w * (u[i] - u_h[i]) * (u[i] - u_h[i]);
      const SymTensor ds = ev.sigma - sigma_h;
      es += w * ds.dot(ds);
      const double db = ev.beta - beta_h;
      eb += w * db * db;
      const Point& gb = ev.grad_beta;
      for (int j = 0; j < d; ++j) eg += w * (gb[j] - grad_beta_h[j]) * (gb[j] - grad_beta_h[j]);
    }
  }
  FieldErrors out;
  out.u_energy = std::sqrt(std::max(eu, 0.0));
  out.u_l2 = std::sqrt(ul2);
  out.sigma_l2 = std::sqrt(es);
  out.beta_l2 = std::sqrt(eb);
  out.beta_grad = std::sqrt(eg);
  return out;
}

}  // namespace vpc
