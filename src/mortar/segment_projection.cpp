#include "mortar/segment_projection.hpp"

#include "core/error.hpp"
#include "mortar/dual_basis.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace vpc::mortar {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a[0] * b[1] - a[1] * b[0]; }

// Gauss–Legendre on [−1, 1], 4 points (exact to degree 7).
constexpr double kGaussX[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
constexpr double kGaussW[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};

}  // namespace

std::optional<double> project_to_slave(const SlaveSegment& s, const Eigen::Vector2d& y) {
  // F(ξ) = (x(ξ) − y) × n(ξ) = a ξ² + b ξ + c with x(ξ) = x0 + ξ dx, n(ξ) = n0 + ξ dn.
  const Eigen::Vector2d x0 = (s.x1 + s.x2) / 2, n0 = (s.n1 + s.n2) / 2;
  const Eigen::Vector2d dx = (s.x2 - s.x1) / 2, dn = (s.n2 - s.n1) / 2;
  const double a = cross(dx, dn), b = cross(dx, n0) + cross(x0 - y, dn), c = cross(x0 - y, n0);
  if ((a != 0 && b * b - 4 * a * c < 0) || (a == 0 && b == 0 && c != 0)) return std::nullopt;
  double xi = b != 0 ? 0.0 : 0.5;
  for (int it = 0; it < 60; ++it) {
    const double F = (a * xi + b) * xi + c, dF = 2 * a * xi + b;
    if (!(dF != 0) || !std::isfinite(F / dF))
      fail(
          "mortar: projecting the point ({}, {}) onto the slave segment ({}, {})-({}, {}) along its nodal normals "
          "met a zero or non-finite derivative at xi = {}",
          y[0], y[1], s.x1[0], s.x1[1], s.x2[0], s.x2[1], xi);
    const double step = F / dF;
    xi -= step;
    if (std::abs(step) <= 1e-13) return xi;
  }
  fail(
      "mortar: projecting the point ({}, {}) onto the slave segment ({}, {})-({}, {}) along its nodal normals did "
      "not converge in 60 Newton steps (xi = {})",
      y[0], y[1], s.x1[0], s.x1[1], s.x2[0], s.x2[1], xi);
}

std::optional<double> project_to_master(const Eigen::Vector2d& x, const Eigen::Vector2d& n, const Eigen::Vector2d& y1,
                                        const Eigen::Vector2d& y2) {
  // (y(η) − x) × n = 0 with y(η) = c + η t: η = −(c − x) × n / (t × n).
  const Eigen::Vector2d c = (y1 + y2) / 2, t = (y2 - y1) / 2;
  const double den = cross(t, n);
  if (!(std::abs(den) > 1e-12 * t.norm() * n.norm())) return std::nullopt;
  return -cross(c - x, n) / den;
}

std::optional<std::array<double, 2>> segment_overlap(const SlaveSegment& s, const Eigen::Vector2d& y1,
                                                     const Eigen::Vector2d& y2, double tol) {
  double lo = 1, hi = -1;
  int n_bounds = 0;
  const auto bound = [&](double xi) {
    lo = std::min(lo, xi);
    hi = std::max(hi, xi);
    ++n_bounds;
  };
  // The slave's ends whose nodal normal line meets the master segment...
  for (const auto& [xi, x, n] : {std::tuple{-1.0, s.x1, s.n1}, std::tuple{1.0, s.x2, s.n2}}) {
    const auto eta = project_to_master(x, n, y1, y2);
    if (eta && std::abs(*eta) <= 1 + tol) bound(xi);
  }
  // ...and the master nodes that project into the slave.
  for (const Eigen::Vector2d& y : {y1, y2}) {
    const auto xi = project_to_slave(s, y);
    if (xi && std::abs(*xi) <= 1 + tol) bound(std::clamp(*xi, -1.0, 1.0));
  }
  if (n_bounds < 2 || !(hi - lo > tol)) return std::nullopt;
  return std::array<double, 2>{lo, hi};
}

std::vector<MortarPoint> segment_pair_points(const SlaveSegment& s, const Eigen::Vector2d& y1,
                                             const Eigen::Vector2d& y2, double tol) {
  const auto overlap = segment_overlap(s, y1, y2, tol);
  if (!overlap) return {};
  const auto [lo, hi] = *overlap;
  const double jacobian = (s.x2 - s.x1).norm() / 2 * (hi - lo) / 2;
  std::vector<MortarPoint> points(4);
  for (int q = 0; q < 4; ++q) {
    const double xi = (lo + hi) / 2 + kGaussX[q] * (hi - lo) / 2;
    const auto N = segment_shape(xi);
    const Eigen::Vector2d x = N[0] * s.x1 + N[1] * s.x2, n = N[0] * s.n1 + N[1] * s.n2;
    const auto eta = project_to_master(x, n, y1, y2);
    if (!eta) return {};
    // Between the master's projected nodes η lies in [−1, 1]; clamp away the roundoff.
    points[q] = {N, segment_shape(std::clamp(*eta, -1.0, 1.0)), kGaussW[q] * jacobian};
  }
  return points;
}

}  // namespace vpc::mortar
