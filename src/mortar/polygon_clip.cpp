#include "mortar/polygon_clip.hpp"

#include "fem/quadrature.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace vpc::mortar {

namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; }

/// Barycentric coordinates of p in triangle t (any orientation, non-degenerate).
std::array<double, 3> barycentric(const std::array<Vec2, 3>& t, const Vec2& p) {
  const double det = cross(t[1] - t[0], t[2] - t[0]);
  const double l1 = cross(p - t[0], t[2] - t[0]) / det, l2 = cross(t[1] - t[0], p - t[0]) / det;
  return {1 - l1 - l2, l1, l2};
}

}  // namespace

double polygon_area(const std::vector<Vec2>& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) a += cross(p[i], p[(i + 1) % p.size()]);
  return a / 2;
}

std::vector<Vec2> clip_convex(const std::vector<Vec2>& subject, const std::vector<Vec2>& clip, double tol) {
  std::vector<Vec2> out = subject, in;
  for (size_t e = 0; e < clip.size() && !out.empty(); ++e) {
    const Vec2 a = clip[e], b = clip[(e + 1) % clip.size()];
    const Vec2 u = (b - a).normalized();
    const auto dist = [&](const Vec2& p) { return cross(u, p - a); };  // > 0: inside (left of a -> b)
    in.swap(out);
    out.clear();
    for (size_t i = 0; i < in.size(); ++i) {
      const Vec2& P = in[i];
      const Vec2& Q = in[(i + 1) % in.size()];
      const double dP = dist(P), dQ = dist(Q);
      // Strictly inside (> tol), on the line (|d| ≤ tol, kept) or strictly outside (< −tol).
      if ((dP > tol && dQ < -tol) || (dP < -tol && dQ > tol)) out.push_back(P + dP / (dP - dQ) * (Q - P));
      if (dQ >= -tol) out.push_back(Q);
    }
  }
  // Merge vertices closer than tol (the clip edges' corners can repeat a vertex).
  std::vector<Vec2> merged;
  for (const Vec2& p : out)
    if (merged.empty() || (p - merged.back()).norm() > tol) merged.push_back(p);
  while (merged.size() > 1 && (merged.front() - merged.back()).norm() <= tol) merged.pop_back();
  if (merged.size() < 3) merged.clear();
  return merged;
}

std::vector<MortarPoint> triangle_pair_points(const std::array<Eigen::Vector3d, 3>& s, const Eigen::Vector3d& n_s,
                                              const std::array<Eigen::Vector3d, 3>& m, double tol) {
  // An orthonormal frame (e1, e2) of the slave plane; dotting with it projects along n_s.
  const Eigen::Vector3d e1 = (s[1] - s[0]).normalized(), e2 = n_s.cross(e1);
  const auto plane = [&](const Eigen::Vector3d& p) { return Vec2((p - s[0]).dot(e1), (p - s[0]).dot(e2)); };
  const std::array<Vec2, 3> s2{plane(s[0]), plane(s[1]), plane(s[2])}, m2{plane(m[0]), plane(m[1]), plane(m[2])};
  const double h = std::max({(s[1] - s[0]).norm(), (s[2] - s[1]).norm(), (s[0] - s[2]).norm()});
  const double area_s = std::abs(cross(s2[1] - s2[0], s2[2] - s2[0])) / 2;
  const double area_m = cross(m2[1] - m2[0], m2[2] - m2[0]) / 2;
  if (!(std::abs(area_m) > tol * area_s)) return {};  // master edge-on to the slave plane

  std::vector<Vec2> slave_poly(s2.begin(), s2.end()), master_poly(m2.begin(), m2.end());
  if (polygon_area(slave_poly) < 0) std::reverse(slave_poly.begin(), slave_poly.end());
  if (area_m < 0) std::reverse(master_poly.begin(), master_poly.end());
  const std::vector<Vec2> poly = clip_convex(master_poly, slave_poly, tol * h);
  if (poly.empty() || !(polygon_area(poly) > tol * area_s)) return {};

  // A fan about the vertex centroid (inside the convex polygon): one triangle per edge.
  Vec2 c = Vec2::Zero();
  for (const Vec2& p : poly) c += p;
  c /= static_cast<double>(poly.size());
  const auto& rule = simplex_rule(2);
  std::vector<MortarPoint> points;
  points.reserve(poly.size() * rule.size());
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    const double area = cross(p - c, q - c) / 2;
    if (!(area > 0)) continue;  // a vertex pair on a line through the centroid (roundoff)
    for (const QuadraturePoint& g : rule) {
      const Vec2 x = g.lambda[0] * c + g.lambda[1] * p + g.lambda[2] * q;
      points.push_back({barycentric(s2, x), barycentric(m2, x), g.weight * area});
    }
  }
  return points;
}

}  // namespace vpc::mortar
