#pragma once
// Rigid obstacles that move (SPEC §6, issue 13): a plane, a sphere or a cylinder
// (a circle in 2D) whose position is a function of t. The gap of a contact node
// is the distance from the node along its contact direction ν to the obstacle's
// surface, exact for these shapes; with several obstacles the nearest counts.
#include "fem/assembly.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace vpc {

struct Obstacle {
  enum class Shape { Plane, Sphere, Cylinder };
  std::string name;
  Shape shape = Shape::Plane;
  VectorField position;       // a point of the plane / the centre / a point of the axis, at time t
  Point normal{0, 0, 1};      // plane: unit normal pointing out of the obstacle (towards the body)
  Point axis{0, 0, 1};        // cylinder: unit axis direction
  double radius = 0;          // sphere, cylinder
  std::vector<std::string> parts;  // the contact parts it acts on; empty: all of Γ3
};

/// Bit k set: obstacle k acts at a node (at most 64 obstacles: Problem::validate).
using ObstacleMask = std::uint64_t;
inline constexpr ObstacleMask kAllObstacles = ~ObstacleMask{0};

/// The distance s along the unit direction ν from x to the obstacle's surface at
/// time t (x + sν on it): s < 0 when x is inside the obstacle; +∞ when the ray
/// does not meet it (ν points away from a plane, passes beside a sphere).
double distance_along(const Obstacle& o, const Point& x, const Point& nu, double t);

/// How deep x lies inside the obstacle at time t: > 0 inside (the distance from x to
/// the plane, or the radius less x's distance to the centre or axis), ≤ 0 outside or
/// on the surface.
double depth(const Obstacle& o, const Point& x, double t);

/// The least distance_along over the obstacles of `mask`, or `miss` when every ray misses.
double obstacle_gap(const std::vector<Obstacle>& obstacles, const Point& x, const Point& nu, double t, double miss,
                    ObstacleMask mask = kAllObstacles);
/// The obstacle of `mask` nearest along ν (the one obstacle_gap takes), −1 if there is none.
int nearest_obstacle(const std::vector<Obstacle>& obstacles, const Point& x, const Point& nu, double t,
                     ObstacleMask mask = kAllObstacles);

}  // namespace vpc
