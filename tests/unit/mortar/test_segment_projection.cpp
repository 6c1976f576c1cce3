// 2D mortar segments (mortar/segment_projection): projections along the slave's
// interpolated nodal normals, their Newton failure, the overlap and its points.
#include "../error_of.hpp"
#include "mortar/segment_projection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace vpc::mortar {
namespace {

using V = Eigen::Vector2d;

double cross(const V& a, const V& b) { return a[0] * b[1] - a[1] * b[0]; }

TEST(MortarSegmentProjection, StraightNormalsGiveTheFoot) {
  const SlaveSegment s{V(0, 0), V(2, 0), V(0, 1), V(0, 1)};
  EXPECT_NEAR(*project_to_slave(s, V(1.5, 0.3)), 0.5, 1e-15);
  EXPECT_NEAR(*project_to_slave(s, V(-1, -0.2)), -2, 1e-15);  // beyond the node, behind: any real ξ
}

TEST(MortarSegmentProjection, CurvedNormalsSolveTheQuadratic) {
  // Nodal normals of an arc: the field lines are not parallel, so (x(ξ) − y) × n(ξ) = 0
  // is quadratic in ξ.
  const SlaveSegment s{V(-1, 0.1), V(1, 0), V(-0.3, 1).normalized(), V(0.4, 1).normalized()};
  for (const V& y : {V(0.3, 0.2), V(-0.9, 0.5), V(1.2, -0.1), V(0.0, -0.3)}) {
    const double xi = project_to_slave(s, y).value();
    const double N1 = (1 - xi) / 2, N2 = (1 + xi) / 2;
    const V x = N1 * s.x1 + N2 * s.x2, n = N1 * s.n1 + N2 * s.n2;
    EXPECT_NEAR(cross(x - y, n), 0, 1e-14) << y.transpose();
    // Not the straight foot of y on the segment (which would ignore the normals' turn).
    EXPECT_GT(std::abs(xi - (y[0] - 0)), 1e-3);
  }
}

TEST(MortarSegmentProjection, PointsNoNormalLineReachesDoNotProject) {
  // Normals turning towards each other: their field lines all pass through (0, 1), and
  // F(ξ) = ξ(1 − y_2) − y_1 has no root for y_2 = 1, y_1 ≠ 0.
  const SlaveSegment focus{V(-1, 0), V(1, 0), V(1, 1).normalized(), V(-1, 1).normalized()};
  EXPECT_FALSE(project_to_slave(focus, V(0.5, 1)).has_value());
  EXPECT_NEAR(*project_to_slave(focus, V(0.5, 0.5)), 1, 1e-15);  // below the focus: ξ = y_1/(1 − y_2)
  // A quadratic with no real root (checked by its discriminant from three values).
  const SlaveSegment s{V(-1, 0), V(1, 0), V(1, 1).normalized(), V(-1, 0.5).normalized()};
  const V y(1, 1);
  const auto F = [&](double xi) {
    const double N1 = (1 - xi) / 2, N2 = (1 + xi) / 2;
    return cross(N1 * s.x1 + N2 * s.x2 - y, N1 * s.n1 + N2 * s.n2);
  };
  const double c = F(0), a = (F(1) + F(-1)) / 2 - c, b = (F(1) - F(-1)) / 2;
  ASSERT_LT(b * b - 4 * a * c, 0);
  EXPECT_FALSE(project_to_slave(s, y).has_value());
}

TEST(MortarSegmentProjection, FailsClearlyOnNonFiniteInput) {
  const SlaveSegment s{V(0, 0), V(1, 0), V(0, 1), V(0, 1)};
  expect_error([&] { project_to_slave(s, V(std::nan(""), 1)); }, "non-finite derivative");
}

TEST(MortarSegmentProjection, ProjectsOntoTheMasterAlongAGivenNormal) {
  const V y1(3, 1), y2(1, 1);  // η = −1 at y1
  EXPECT_NEAR(*project_to_master(V(2.5, 0), V(0, 1), y1, y2), -0.5, 1e-15);
  EXPECT_NEAR(*project_to_master(V(2, 0), V(1, 1), y1, y2), -1, 1e-15);   // along (1, 1) to (3, 1)
  EXPECT_FALSE(project_to_master(V(2, 0), V(1, 0), y1, y2).has_value());  // parallel
}

TEST(MortarSegmentProjection, OverlapIsTheProjectedMasterWithinTheSlave) {
  const SlaveSegment s{V(0, 0), V(4, 0), V(0, 1), V(0, 1)};
  const auto a = segment_overlap(s, V(3, 0.5), V(1, 0.5), 1e-10);  // reversed master: sorted
  ASSERT_TRUE(a);
  EXPECT_NEAR((*a)[0], -0.5, 1e-15);
  EXPECT_NEAR((*a)[1], 0.5, 1e-15);
  const auto b = segment_overlap(s, V(5, 0.5), V(3, 0.5), 1e-10);
  ASSERT_TRUE(b);
  EXPECT_NEAR((*b)[0], 0.5, 1e-15);
  EXPECT_EQ((*b)[1], 1);
  EXPECT_FALSE(segment_overlap(s, V(6, 0.5), V(4, 0.5), 1e-10));  // touching at the end only
  EXPECT_FALSE(segment_overlap(s, V(-2, 0.5), V(-1, 0.5), 1e-10));
}

TEST(MortarSegmentProjection, PairPointsIntegrateTheOverlapAndLocateTheMaster) {
  // Slave (0,0)-(4,0); master (5,1)-(1,1) tilted a little: covers x ∈ [1, 4] of the slave.
  const SlaveSegment s{V(0, 0), V(4, 0), V(0, 1), V(0, 1)};
  const V y1(5, 1.2), y2(1, 0.8);
  const auto p = segment_pair_points(s, y1, y2, 1e-10);
  ASSERT_EQ(p.size(), 4u);
  double length = 0, moment = 0;
  for (const auto& q : p) {
    length += q.weight;
    const double x = q.slave[0] * 0 + q.slave[1] * 4;
    moment += q.weight * x;
    // The master point is straight above the slave point (the normals are (0, 1)).
    EXPECT_NEAR(q.master[0] * y1[0] + q.master[1] * y2[0], x, 1e-14);
    EXPECT_NEAR(q.master[0] + q.master[1], 1, 1e-15);
  }
  EXPECT_NEAR(length, 3, 1e-14);
  EXPECT_NEAR(moment, (16 - 1) / 2.0, 1e-13);  // ∫_1^4 x dx
  EXPECT_TRUE(segment_pair_points(s, V(9, 1), V(6, 1), 1e-10).empty());
}

}  // namespace
}  // namespace vpc::mortar
