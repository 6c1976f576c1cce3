#include "problem/rigid_motions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vpc {

RigidMotions::RigidMotions(int dim, const Point& lo, const Point& hi) : dim_(dim) {
  for (int j = 0; j < 3; ++j) centre_[j] = (lo[j] + hi[j]) / 2;
  scale_ = 1e-300;
  for (int j = 0; j < dim; ++j) scale_ = std::max(scale_, hi[j] - lo[j]);
}

Eigen::VectorXd RigidMotions::along(const Point& x, const Point& v) const {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(count());
  double y[3];
  for (int j = 0; j < 3; ++j) y[j] = (x[j] - centre_[j]) / scale_;
  for (int c = 0; c < dim_; ++c) {
    if (v[c] == 0) continue;
    r[c] += v[c];
    if (dim_ == 2) r[2] += v[c] * (c == 0 ? -y[1] : y[0]);  // ω e_z × y
    if (dim_ == 3) {                                        // e_i × y, i = x, y, z
      const double cross[3][3] = {{0, -y[2], y[1]}, {y[2], 0, -y[0]}, {-y[1], y[0], 0}};
      for (int i = 0; i < 3; ++i) r[3 + i] += v[c] * cross[i][c];
    }
  }
  return r;
}

std::string RigidMotions::describe(const Eigen::VectorXd& a) const {
  Eigen::VectorXd v = a;
  Eigen::Index big = 0;
  v.cwiseAbs().maxCoeff(&big);
  if (v[big] < 0) v = -v;  // the same motion, named with its larger component positive
  v = v.unaryExpr([](double c) { return std::abs(c) < 1e-12 ? 0.0 : c; });  // no "-0"
  const int d = dim_;
  const double w = d == 2 ? std::abs(v[2]) : d == 3 ? v.tail(3).norm() : 0.0;
  if (w <= 1e-6 * v.norm())
    return fmt::format("a translation along ({:.3g}{})", v[0],
                       d == 1 ? std::string() : fmt::format(", {:.3g}", v[1]) + (d == 3 ? fmt::format(", {:.3g}", v[2]) : ""));
  if (d == 2)  // a + ω e_z × y vanishes at y = (−a_y, a_x) / ω
    return fmt::format("a rotation about the point ({:.6g}, {:.6g})", centre_[0] - scale_ * v[1] / v[2],
                       centre_[1] + scale_ * v[0] / v[2]);
  // a + w × y: its axis along w through (w × a) / |w|²
  const Eigen::Vector3d t = v.head(3), axis = v.tail(3);
  const Eigen::Vector3d y = axis.cross(t) / axis.squaredNorm();
  const Eigen::Vector3d u = axis.normalized();
  return fmt::format("a rotation about the axis along ({:.3g}, {:.3g}, {:.3g}) through ({:.6g}, {:.6g}, {:.6g})", u[0],
                     u[1], u[2], centre_[0] + scale_ * y[0], centre_[1] + scale_ * y[1], centre_[2] + scale_ * y[2]);
}

RigidHold::RigidHold(const RigidMotions& motions)
    : motions_(motions), G_(Eigen::MatrixXd::Zero(motions.count(), motions.count())) {}

void RigidHold::add(const Point& x, const Point& v) {
  const Eigen::VectorXd r = motions_.along(x, v);
  G_ += r * r.transpose();
}

void RigidHold::add_axis(const Point& x, int c) {
  Point axis{0, 0, 0};
  axis[c] = 1;
  add(x, axis);
}

Eigen::MatrixXd RigidHold::free_motions(const std::function<void(double*, int)>& sum) const {
  const int m = motions_.count();
  Eigen::MatrixXd G = G_;
  if (sum) sum(G.data(), m * m);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G);
  const Eigen::VectorXd& lambda = eig.eigenvalues();  // increasing
  const double floor = 1e-12 * std::max(lambda[m - 1], 1.0);
  int k = 0;
  while (k < m && lambda[k] <= floor) ++k;
  return eig.eigenvectors().leftCols(k);
}

}  // namespace vpc
