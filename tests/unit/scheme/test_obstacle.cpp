// Issue 13: rigid obstacles that move, [[obstacle]]: the gap of a contact node is
// the distance along its direction ν to the nearest obstacle's surface.
#include "io/case_file.hpp"
#include "io/run_output.hpp"
#include "contact/obstacle.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../error_of.hpp"
#include "../run_to_end.hpp"
#include "bar_case.hpp"

namespace vpc {
namespace {

Obstacle at(Obstacle::Shape shape, Point c, double radius = 0) {
  Obstacle o;
  o.shape = shape;
  o.position = [c](const Point&, double t) { return Point{c[0], c[1], c[2] - t}; };  // moves down at speed 1
  o.radius = radius;
  return o;
}

TEST(Obstacle, DistanceAlongTheDirectionForEachShape) {
  const Point up{0, 0, 1};
  // Plane z = 2 − t with normal −z (towards the body below it).
  Obstacle plane = at(Obstacle::Shape::Plane, {5, 7, 2});
  plane.normal = {0, 0, -1};
  EXPECT_DOUBLE_EQ(distance_along(plane, {0, 0, 0.5}, up, 0.0), 1.5);
  EXPECT_DOUBLE_EQ(distance_along(plane, {0, 0, 0.5}, up, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(distance_along(plane, {0, 0, 0.5}, up, 2.0), -0.5);  // the plane has passed the node
  EXPECT_NEAR(distance_along(plane, {0, 0, 0}, Point{0.6, 0, 0.8}, 0.0), 2.5, 1e-15);  // oblique ν
  EXPECT_TRUE(std::isinf(distance_along(plane, {0, 0, 0}, Point{0, 0, -1}, 0.0)));  // heading away
  // Sphere of radius 1 centred at (0, 0, 3 − t).
  const Obstacle sphere = at(Obstacle::Shape::Sphere, {0, 0, 3}, 1.0);
  EXPECT_NEAR(distance_along(sphere, {0, 0, 0}, up, 0.0), 2.0, 1e-15);
  EXPECT_NEAR(distance_along(sphere, {0.6, 0, 0}, up, 0.0), 3 - 0.8, 1e-15);
  EXPECT_NEAR(distance_along(sphere, {0, 0, 0}, up, 2.5), -0.5, 1e-15);  // the node is inside
  EXPECT_TRUE(std::isinf(distance_along(sphere, {1.5, 0, 0}, up, 0.0)));  // passes beside
  EXPECT_TRUE(std::isinf(distance_along(sphere, {0, 0, 5}, up, 0.0)));    // the sphere is behind
  // Cylinder of radius 1 along y through (0, ·, 3 − t): as the sphere in the x–z plane.
  Obstacle cylinder = at(Obstacle::Shape::Cylinder, {0, 0, 3}, 1.0);
  cylinder.axis = {0, 1, 0};
  EXPECT_NEAR(distance_along(cylinder, {0.6, 40, 0}, up, 0.0), 3 - 0.8, 1e-15);
  EXPECT_TRUE(std::isinf(distance_along(cylinder, {0, 0, 0}, Point{0, 1, 0}, 0.0)));  // along the axis
  // The nearest obstacle counts; no obstacle ahead: the miss value.
  EXPECT_NEAR(obstacle_gap({plane, sphere}, {0, 0, 0}, up, 0.0, 99), 2.0, 1e-15);
  EXPECT_EQ(obstacle_gap({sphere}, {1.5, 0, 0}, up, 0.0, 99), 99);
}

using test::bar_text;

// A plane moving at speed 1 towards the tip is the gap formula 0.6 − t.
TEST(Obstacle, AMovingPlaneIsTheEquivalentGapFormula) {
  const Case plane = parse_case(bar_text("[[obstacle]]\nshape = \"plane\"\npoint = [\"1.6 - t\"]\nnormal = [-1]\n"),
                                "plane.toml", ".", {});
  const Case formula = parse_case(bar_text("[contact]\ngap = \"0.6 - t\"\n"), "formula.toml", ".", {});
  TimeStepper a(plane.problem, plane.solvers), b(formula.problem, formula.solvers);
  while (!a.done()) {
    ASSERT_TRUE(a.step().ok);
    ASSERT_TRUE(b.step().ok);
    EXPECT_NEAR(a.state().u[8], b.state().u[8], 1e-14);
    EXPECT_NEAR(a.state().lambda[0], b.state().lambda[0], 1e-12);
  }
  EXPECT_NEAR(a.state().u[8], -0.4, 1e-12);
}

// The history's totals: each node's force goes to its nearest obstacle; the contact
// area is the measure of the active nodes (the bar's tip: 1 node, measure 1).
TEST(Obstacle, ForcePerObstacleAndContactArea) {
  const Case c = parse_case(bar_text("[[obstacle]]\nname = \"near\"\nshape = \"plane\"\npoint = [\"1.6 - t\"]\n"
                                     "normal = [-1]\n[[obstacle]]\nname = \"far\"\nshape = \"sphere\"\n"
                                     "center = [3]\nradius = 0.5\n"),
                            "two.toml", ".", {});
  TimeStepper s(c.problem, c.solvers);
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_EQ(r.obstacle_force.size(), 2u);
    EXPECT_DOUBLE_EQ(r.obstacle_force[0], r.contact.total_force);
    EXPECT_EQ(r.obstacle_force[1], 0.0);
    EXPECT_EQ(r.contact_area, r.contact.n_active > 0 ? 1.0 : 0.0);
  }
  const std::string header = history_header(*c.problem, s.part());
  EXPECT_NE(header.find(",ok,contact_area,dt,error_estimate,rejected,force_near,force_far,reaction_"), std::string::npos) << header;
}

TEST(Obstacle, BadObstaclesAreLocatedErrors) {
  auto error = [](const std::string& contact) { return error_of([&] { parse_case(bar_text(contact), "o.toml", ".", {}); }); };
  std::string m = error("[contact]\ngap = 0.1\n[[obstacle]]\nshape = \"plane\"\npoint = [2]\nnormal = [-1]\n");
  EXPECT_NE(m.find("either [contact] gap or [[obstacle]]"), std::string::npos) << m;
  m = error("[[obstacle]]\nshape = \"plane\"\npoint = [\"2 + x\"]\nnormal = [-1]\n");
  EXPECT_NE(m.find("obstacle[0].point"), std::string::npos) << m;
  EXPECT_NE(m.find("a formula in t only"), std::string::npos) << m;
  m = error("[[obstacle]]\nshape = \"sphere\"\ncenter = [3]\nradius = 0\n");
  EXPECT_NE(m.find("expected a radius > 0"), std::string::npos) << m;
  m = error("[[obstacle]]\nshape = \"cube\"\npoint = [3]\n");
  EXPECT_NE(m.find("obstacle[0].shape"), std::string::npos) << m;
  EXPECT_NE(m.find("cylinder"), std::string::npos) << m;
  m = error("[[obstacle]]\nshape = \"plane\"\npoint = [0.5]\nnormal = [-1]\n");  // already through the tip
  EXPECT_NE(m.find("o.toml:21:1: obstacle[0]"), std::string::npos) << m;
  EXPECT_NE(m.find("obstacle[0] ('obstacle1'): contact node 8 (1, 0, 0) lies inside the obstacle at t = 0"),
            std::string::npos) << m;
  // Issue 26: a normal pointing away from the body (the ray along ν misses the plane) is
  // the body inside the obstacle too, not an obstacle that is never met.
  m = error("[[obstacle]]\nshape = \"plane\"\npoint = [2]\nnormal = [1]\n");
  EXPECT_NE(m.find("lies inside the obstacle at t = 0: 1 behind the plane"), std::string::npos) << m;
  EXPECT_NE(m.find("the normal must point from the obstacle towards the body"), std::string::npos) << m;
  m = error("[[obstacle]]\nshape = \"sphere\"\ncenter = [1.2]\nradius = 5\n");  // the body inside a sphere
  EXPECT_NE(m.find("lies inside the sphere at t = 0, 0.2 from its centre (radius 5)"), std::string::npos) << m;
  m = error("[[obstacle]]\nshape = \"plane\"\npoint = [2]\nnormal = [0]\n");
  EXPECT_NE(m.find("non-zero vector"), std::string::npos) << m;
}

/// A block [-1, 1] × [0, 0.5] clamped at its top, its bottom the contact part, with `obstacle` (an
/// [[obstacle]] section) and Coulomb friction (issue 48: obstacle-normal-away-touching).
std::string block_text(const std::string& obstacle) {
  return R"(
[mesh]
generator = "rectangle"
lower = [-1.0, 0.0]
upper = [1.0, 0.5]
cells = [20, 5]
[boundary]
clamped = ["top"]
contact = ["bottom"]
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[contact]
friction = "coulomb"
mu = 0.3
[time]
T = 1.0
steps = 4
)" + obstacle;
}

// Issue 48: an obstacle started touching the contact face (every contact node at gap 0) with the body
// on the obstacle's side passed the nodes' check and was never met; the cells behind the contact
// facets are tested too. Started touching from outside, it passes and presses the body.
TEST(Obstacle, ABodyOnTheObstaclesSideIsRefusedWhereItsNodesTouch) {
  auto error = [](const std::string& text) { return error_of([&] { parse_case(text, "o.toml", ".", {}); }); };
  const std::string rising = "[[obstacle]]\nname = \"plane\"\nshape = \"plane\"\npoint = [0.0, \"0.005*t\"]\n";
  std::string m = error(block_text(rising + "normal = [0.0, -1.0]\n"));  // the plane on the face, flipped
  EXPECT_NE(m.find("o.toml:28:10: obstacle[0].normal ('plane'): the body lies inside the obstacle at t = 0: next to "
                   "contact node 0 (-1, 0, 0), 0 from the plane, the centroid (-0.933333, 0.0333333, 0) of its cell is "
                   "0.0333333 behind the plane"), std::string::npos) << m;
  EXPECT_NE(m.find("flip it to (0, 1, 0)"), std::string::npos) << m;
  // The same plane a little above the face: the nodes are outside, the body's cells inside.
  m = error(block_text("[[obstacle]]\nshape = \"plane\"\npoint = [0.0, 0.01]\nnormal = [0.0, -1.0]\n"));
  EXPECT_NE(m.find("the body lies inside the obstacle at t = 0"), std::string::npos) << m;
  // A circle touching the face at (0, 0) from inside the body, and in 1D the plane on the bar's tip.
  m = error(block_text("[[obstacle]]\nshape = \"cylinder\"\ncenter = [0.0, 10.0]\nradius = 10.0\n"));
  EXPECT_NE(m.find("the body lies inside the cylinder at t = 0: next to contact node"), std::string::npos) << m;
  m = error(bar_text("[[obstacle]]\nshape = \"plane\"\npoint = [1]\nnormal = [1]\n"));
  EXPECT_NE(m.find("obstacle[0].normal ('obstacle1'): the body lies inside the obstacle at t = 0"), std::string::npos)
      << m;
  EXPECT_NE(m.find("flip it to (-1, 0, 0)"), std::string::npos) << m;
  // Started touching from outside: accepted, and the rising plane presses 21 nodes.
  for (const std::string& touching :
       {rising + "normal = [0.0, 1.0]\n",
        std::string("[[obstacle]]\nshape = \"cylinder\"\ncenter = [0.0, \"-10.0 + 0.005*t\"]\nradius = 10.0\n")}) {
    StepReport r;
    run_to_end(parse_case(block_text(touching), "o.toml", ".", {}), &r);
    EXPECT_GT(r.contact.n_active, 0) << touching;
    EXPECT_GT(r.obstacle_force[0], 0.0) << touching;
  }
}

}  // namespace
}  // namespace vpc
