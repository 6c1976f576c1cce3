// Mortar contact surfaces (mortar/surface, mortar/nodal_normals): the outward normals
// of both facet orders, the errors for bad input, and the area-weighted nodal normals.
#include "../error_of.hpp"
#include "mortar/nodal_normals.hpp"
#include "mortar/surface.hpp"
#include "surfaces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace vpc::mortar {
namespace {


void expect_point(const Point& a, const Point& b, double tol = 1e-15) {
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(a[d], b[d], tol) << "component " << d;
}

TEST(MortarSurface, SegmentNormalsFollowTheStatedOrder) {
  // Walking +x: the body on the left (Outward) is above, so the normal points down.
  const std::vector<Point> x{{0, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  const Surface out = test::polyline(x, 10, FacetOrder::Outward);
  const Surface in = test::polyline(x, 10, FacetOrder::Inward);
  ASSERT_EQ(out.n_facets(), 2);
  expect_point(out.normal(0), {0, -1, 0});
  expect_point(in.normal(1), {0, 1, 0});
  EXPECT_DOUBLE_EQ(out.measure(0), 2);
  EXPECT_DOUBLE_EQ(in.measure(1), 1);
  EXPECT_EQ(in.id(2), 12);
}

TEST(MortarSurface, TriangleNormalsFollowTheStatedOrder) {
  const Surface out = test::grid(2, 1, 0, 2, 0, 1, test::plane_at(1), 0, FacetOrder::Outward);
  const Surface in = test::grid(2, 1, 0, 2, 0, 1, test::plane_at(1), 0, FacetOrder::Inward);
  ASSERT_EQ(out.n_facets(), 4);
  for (int f = 0; f < 4; ++f) {
    expect_point(out.normal(f), {0, 0, 1});
    expect_point(in.normal(f), {0, 0, -1});
    EXPECT_DOUBLE_EQ(out.measure(f), 0.5);
  }
}

TEST(MortarSurface, RejectsInconsistentlyOrderedNeighbours) {
  const std::vector<Point> x{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  expect_error([&] { Surface(2, x, {0, 1, 2}, {0, 1, 2, 1}); }, "segments 0 and 1 both end at node id 1");
  const std::vector<Point> y{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  expect_error(
      [&] {
        Surface(3, y, {0, 1, 2, 3}, {0, 1, 2, 0, 3, 2});
      },
      "triangles 0 and 1 both run from node id 2 to node id 0");
  Surface(3, y, {0, 1, 2, 3}, {0, 1, 2, 0, 2, 3});  // consistent: no error
}

TEST(MortarSurface, RejectsBadInput) {
  const std::vector<Point> x{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  expect_error([&] { Surface(2, x, {0, 1, 1}, {0, 1}); }, "same global id 1");
  expect_error([&] { Surface(2, x, {0, 1, 2}, {0, 0}); }, "names node 0 twice");
  expect_error([&] { Surface(2, x, {0, 1, 2}, {0, 3}); }, "names node 3");
  expect_error([&] { Surface(4, x, {0, 1, 2}, {}); }, "dimension 4");
  expect_error([&] { Surface(2, {{0, 0, 0}, {1, 0, 1e-3}}, {0, 1}, {0, 1}); }, "z = 0.001");
  expect_error([&] { Surface(2, {{0, 0, 0}, {0, 0, 0}}, {4, 5}, {0, 1}); }, "facet 0 (node ids 4, 5) is degenerate");
  // Three collinear points: no normal.
  expect_error([&] { Surface(3, x, {0, 1, 2}, {0, 1, 2}); }, "facet 0 (node ids 0, 1, 2) is degenerate");
}

TEST(MortarSurface, OrientAwayFromInsidePoints) {
  const std::vector<Point> x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<int> facets{0, 1, 2, 0, 2, 1};
  orient_away_from(3, x, facets, {{0.2, 0.2, -1}, {0.2, 0.2, -1}});
  EXPECT_EQ(facets, (std::vector<int>{0, 1, 2, 2, 0, 1}));  // the second one was flipped
  std::vector<int> segment{0, 1};
  orient_away_from(2, x, segment, {{0.5, 1, 0}});
  expect_point(Surface(2, {x[0], x[1]}, {0, 1}, segment).normal(0), {0, -1, 0});
  expect_error(
      [&] {
        orient_away_from(3, x, facets, {{0.1, 0.1, 0}, {0, 0, 1}});
      },
      "inside point of facet 0 lies in the facet's plane");
}

TEST(MortarNodalNormals, AreLengthWeightedAndUnit) {
  // A segment of length 1 facing +y and one of length 2 facing +x meet at node 1.
  const Surface s = test::polyline({{-1, 0, 0}, {0, 0, 0}, {0, -2, 0}}, 0, FacetOrder::Inward);
  expect_point(s.normal(0), {0, 1, 0});
  expect_point(s.normal(1), {1, 0, 0});
  const auto n = nodal_normals(s);
  expect_point(n[0], {0, 1, 0});
  expect_point(n[1], {2 / std::sqrt(5.0), 1 / std::sqrt(5.0), 0});
  expect_point(n[2], {1, 0, 0});
}

TEST(MortarNodalNormals, AreAreaWeightedIn3d) {
  // Two triangles of areas 1/2 (normal +z) and 1 (normal +x) sharing the edge 0-1.
  const Surface s(3, {{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, 0, -2}}, {0, 1, 2, 3}, {0, 1, 2, 1, 0, 3});
  expect_point(s.normal(0), {0, 0, 1});
  expect_point(s.normal(1), {1, 0, 0});
  const auto n = nodal_normals(s);
  expect_point(n[0], {2 / std::sqrt(5.0), 0, 1 / std::sqrt(5.0)});
  expect_point(n[2], {0, 0, 1});
}

TEST(MortarNodalNormals, RejectAKnifeEdge) {
  // Out along one segment and back along the same line: the normals at the tip cancel.
  const Surface s = test::polyline({{0, 0, 0}, {1, 0, 0}, {0, 0, 0}}, 0, FacetOrder::Outward);
  expect_error([&] { nodal_normals(s); }, "facets at node id 1 face opposite ways");
}

}  // namespace
}  // namespace vpc::mortar
