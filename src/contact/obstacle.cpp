#include "contact/obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

namespace {

constexpr double kMiss = std::numeric_limits<double>::infinity();

double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point minus(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point without(const Point& a, const Point& e) {  // a less its component along the unit e
  const double c = dot(a, e);
  return {a[0] - c * e[0], a[1] - c * e[1], a[2] - c * e[2]};
}

/// The entry point of the ray x + sν, s ∈ ℝ, into {|w + sv|² ≤ R²} (w, v the
/// offsets of x and ν from the centre, across the axis for a cylinder): the least
/// root s of |w + sv|² = R² if the exit root is ahead (s₂ ≥ 0), else +∞.
double entry(const Point& w, const Point& v, double radius) {
  const double a = dot(v, v), b = dot(w, v), c = dot(w, w) - radius * radius;
  if (a == 0) return kMiss;  // moving along the axis of a cylinder
  const double disc = b * b - a * c;
  if (disc < 0) return kMiss;
  const double root = std::sqrt(disc);
  // Both roots without cancellation: q = −(b + sign(b)·root), s = q / a and c / q.
  const double q = -(b + std::copysign(root, b));
  double s1 = q / a, s2 = q != 0 ? c / q : s1;
  if (s1 > s2) std::swap(s1, s2);
  return s2 >= 0 ? s1 : kMiss;
}

}  // namespace

double distance_along(const Obstacle& o, const Point& x, const Point& nu, double t) {
  const Point p = o.position(x, t);
  switch (o.shape) {
    case Obstacle::Shape::Plane: {
      const double approach = dot(nu, o.normal);  // < 0: ν heads into the plane
      if (approach >= 0) return kMiss;
      return dot(minus(p, x), o.normal) / approach;
    }
    case Obstacle::Shape::Sphere: return entry(minus(x, p), nu, o.radius);
    case Obstacle::Shape::Cylinder: return entry(without(minus(x, p), o.axis), without(nu, o.axis), o.radius);
  }
  return kMiss;
}

double depth(const Obstacle& o, const Point& x, double t) {
  const Point p = o.position(x, t);
  switch (o.shape) {
    case Obstacle::Shape::Plane: return dot(minus(p, x), o.normal);
    case Obstacle::Shape::Sphere: return o.radius - std::sqrt(dot(minus(x, p), minus(x, p)));
    case Obstacle::Shape::Cylinder: {
      const Point w = without(minus(x, p), o.axis);
      return o.radius - std::sqrt(dot(w, w));
    }
  }
  return 0;
}

double obstacle_gap(const std::vector<Obstacle>& obstacles, const Point& x, const Point& nu, double t, double miss,
                    ObstacleMask mask) {
  const int k = nearest_obstacle(obstacles, x, nu, t, mask);
  const double g = k < 0 ? kMiss : distance_along(obstacles[k], x, nu, t);
  return g == kMiss ? miss : g;
}

int nearest_obstacle(const std::vector<Obstacle>& obstacles, const Point& x, const Point& nu, double t,
                     ObstacleMask mask) {
  int nearest = -1;
  double g = kMiss;
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    if (!(mask >> k & 1)) continue;
    const double s = distance_along(obstacles[k], x, nu, t);
    if (nearest < 0 || s < g) {
      nearest = static_cast<int>(k);
      g = s;
    }
  }
  return nearest;
}

}  // namespace vpc
