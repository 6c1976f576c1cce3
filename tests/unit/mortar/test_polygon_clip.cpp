// 3D mortar segments (mortar/polygon_clip): Sutherland–Hodgman clipping with its
// tolerance, and the integration points of a slave triangle covered by a master one.
#include "mortar/polygon_clip.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace vpc::mortar {
namespace {

using V = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

std::vector<V> square(double x0, double y0, double side, double angle = 0) {
  const V c(x0 + side / 2, y0 + side / 2);
  std::vector<V> p;
  for (const V& corner : {V(-1, -1), V(1, -1), V(1, 1), V(-1, 1)})
    p.push_back(c + Eigen::Rotation2Dd(angle) * (corner * side / 2));
  return p;
}

TEST(MortarPolygonClip, SquareAndItsQuarterTurnMakeAnOctagon) {
  const auto p = clip_convex(square(0, 0, 1, std::numbers::pi / 4), square(0, 0, 1), 1e-12);
  EXPECT_EQ(p.size(), 8u);
  EXPECT_NEAR(polygon_area(p), 2 * (std::sqrt(2.0) - 1), 1e-15);
}

TEST(MortarPolygonClip, CollinearEdgesNeitherDuplicateNorLoseVertices) {
  // Half overlapping, two edges on common lines.
  const auto half = clip_convex(square(0.5, 0, 1), square(0, 0, 1), 1e-12);
  EXPECT_EQ(half.size(), 4u);
  EXPECT_NEAR(polygon_area(half), 0.5, 1e-15);
  // Identical squares: the square itself.
  const auto same = clip_convex(square(0, 0, 1), square(0, 0, 1), 1e-12);
  EXPECT_EQ(same.size(), 4u);
  EXPECT_NEAR(polygon_area(same), 1, 1e-15);
  // Sharing only an edge, or a corner: nothing.
  EXPECT_TRUE(clip_convex(square(1, 0, 1), square(0, 0, 1), 1e-12).empty());
  EXPECT_TRUE(clip_convex(square(1, 1, 1), square(0, 0, 1), 1e-12).empty());
}

TEST(MortarPolygonClip, NearlyParallelEdgesStayFinite) {
  // Turned by angles far below and near the tolerance: no division by a vanishing
  // difference, the area is the square's to the tolerance's order.
  for (const double angle : {1e-16, 1e-13, 1e-11, 1e-9, 1e-6}) {
    SCOPED_TRACE(testing::Message() << "angle " << angle);
    const auto p = clip_convex(square(0, 0, 1, angle), square(0, 0, 1), 1e-12);
    ASSERT_GE(p.size(), 4u);
    for (const V& v : p) {
      ASSERT_TRUE(v.allFinite());
      EXPECT_LT((v - V(0.5, 0.5)).cwiseAbs().maxCoeff(), 0.5 + 1e-12);
    }
    EXPECT_NEAR(polygon_area(p), 1, 2 * angle + 1e-12);
  }
}

TEST(MortarPolygonClip, DisjointAndContained) {
  EXPECT_TRUE(clip_convex(square(2, 0, 1), square(0, 0, 1), 1e-12).empty());
  const auto inner = clip_convex(square(0.2, 0.3, 0.4, 0.3), square(0, 0, 1), 1e-12);
  EXPECT_EQ(inner.size(), 4u);
  EXPECT_NEAR(polygon_area(inner), 0.16, 1e-15);
  const auto outer = clip_convex(square(-1, -1, 3), square(0, 0, 1), 1e-12);
  EXPECT_NEAR(polygon_area(outer), 1, 1e-15);
}

TEST(MortarTrianglePair, PointsCoverTheProjectedOverlapAndLocateTheMasterAlongTheNormal) {
  // A slave triangle in a tilted plane and a master triangle above it in another plane.
  const V3 n = V3(0.2, -0.1, 1).normalized();
  const V3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
  const auto in_plane = [&](double a, double b, double h) { return V3(a * t1 + b * t2 + h * n); };
  const std::array<V3, 3> s{in_plane(0, 0, 0), in_plane(1, 0, 0), in_plane(0, 1, 0)};
  // The master's projection is the triangle (0.2, −0.3), (0.2, 0.9), (1.1, 0.3) (clockwise
  // seen from n, as a facing master is); its heights above the slave plane vary.
  const std::array<V3, 3> m{in_plane(0.2, -0.3, 0.3), in_plane(0.2, 0.9, 0.1), in_plane(1.1, 0.3, 0.5)};
  const auto p = triangle_pair_points(s, n, m, 1e-10);
  ASSERT_FALSE(p.empty());
  // The overlap in (a, b): the master's projection clipped by the slave (a, b ≥ 0, a + b ≤ 1).
  const auto clip = clip_convex({V(0.2, -0.3), V(1.1, 0.3), V(0.2, 0.9)}, {V(0, 0), V(1, 0), V(0, 1)}, 1e-12);
  double area = 0;
  for (const auto& q : p) {
    area += q.weight;
    const V3 xs = q.slave[0] * s[0] + q.slave[1] * s[1] + q.slave[2] * s[2];
    const V3 xm = q.master[0] * m[0] + q.master[1] * m[1] + q.master[2] * m[2];
    EXPECT_NEAR((xm - xs).cross(n).norm(), 0, 1e-15);  // xm lies on the normal through xs
    for (int k = 0; k < 3; ++k) EXPECT_GT(q.master[k], -1e-15);
    EXPECT_NEAR(q.master[0] + q.master[1] + q.master[2], 1, 1e-15);
  }
  EXPECT_NEAR(area, polygon_area(clip), 1e-15);
  // The degree-2 rule on the fan: ∫_C a² over the clip, against the same integral by
  // the fan of clip_convex's own polygon computed here with the shoelace moments.
  double second = 0;
  for (const auto& q : p) second += q.weight * q.slave[1] * q.slave[1];
  double exact = 0;  // ∫ x² over a polygon: Σ (x_i² + x_i x_j + x_j²)(x_i y_j − x_j y_i)/12
  for (size_t i = 0; i < clip.size(); ++i) {
    const V& a = clip[i];
    const V& b = clip[(i + 1) % clip.size()];
    exact += (a[0] * a[0] + a[0] * b[0] + b[0] * b[0]) * (a[0] * b[1] - b[0] * a[1]) / 12;
  }
  EXPECT_NEAR(second, exact, 1e-15);
}

TEST(MortarTrianglePair, EdgeOnAndDisjointMastersGiveNothing) {
  const std::array<V3, 3> s{V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0)};
  const V3 n(0, 0, 1);
  EXPECT_TRUE(triangle_pair_points(s, n, {V3(0, 0, 1), V3(1, 0, 1), V3(0, 0, 2)}, 1e-10).empty());  // edge-on
  EXPECT_TRUE(triangle_pair_points(s, n, {V3(2, 0, 1), V3(2, 1, 1), V3(3, 0, 1)}, 1e-10).empty());
  // The same triangle, either orientation of the slave's normal: the whole triangle.
  for (const V3& normal : {n, V3(-n)}) {
    double area = 0;
    for (const auto& q : triangle_pair_points(s, normal, {s[0], s[2], s[1]}, 1e-10)) area += q.weight;
    EXPECT_NEAR(area, 0.5, 1e-15);
  }
}

}  // namespace
}  // namespace vpc::mortar
