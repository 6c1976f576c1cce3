// Generators: counts, measures, boundary parts and outward normals.
#include "../mesh_measures.hpp"
#include "core/error.hpp"
#include "fem/cell_geometry.hpp"
#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace vpc {
namespace {

double total_facet_measure(const Mesh& m, const std::string& part) {
  double s = 0;
  for (int f : m.facets_of_parts({part})) s += m.facet_measure(f);
  return s;
}

TEST(Mesh, IntervalHasTwoEndPoints) {
  const Mesh m = make_interval(0, 1, 10);
  EXPECT_EQ(m.n_nodes(), 11);
  EXPECT_EQ(m.n_cells(), 10);
  EXPECT_EQ(m.n_facets(), 2);
  ASSERT_EQ(m.part_size("left"), 1);
  ASSERT_EQ(m.part_size("right"), 1);
  EXPECT_EQ(m.nodes_of_parts({"right"}), std::vector<int>{10});
  EXPECT_DOUBLE_EQ(m.facet_normal(m.facets_of_parts({"right"})[0])[0], 1.0);
  EXPECT_DOUBLE_EQ(m.facet_normal(m.facets_of_parts({"left"})[0])[0], -1.0);
}

TEST(Mesh, RectangleSidesAndNormals) {
  const Mesh m = make_rectangle({0, 0, 0}, {2, 1, 0}, 4, 3);
  EXPECT_EQ(m.n_nodes(), 5 * 4);
  EXPECT_EQ(m.n_cells(), 2 * 4 * 3);
  EXPECT_EQ(m.n_facets(), 2 * (4 + 3));
  EXPECT_NEAR(total_facet_measure(m, "bottom"), 2.0, 1e-14);
  EXPECT_NEAR(total_facet_measure(m, "left"), 1.0, 1e-14);
  for (int f : m.facets_of_parts({"bottom"})) {
    EXPECT_NEAR(m.facet_normal(f)[0], 0.0, 1e-14);
    EXPECT_NEAR(m.facet_normal(f)[1], -1.0, 1e-14);
  }
  for (int f : m.facets_of_parts({"right"})) EXPECT_NEAR(m.facet_normal(f)[0], 1.0, 1e-14);
}

TEST(Mesh, BoxIsConformingAndClosed) {
  const Mesh m = make_box({0, 0, 0}, {1, 2, 3}, 2, 3, 4);
  EXPECT_EQ(m.n_cells(), 6 * 2 * 3 * 4);
  // Conforming: boundary facets are exactly those on the six faces (2 triangles per square).
  EXPECT_EQ(m.n_facets(), 2 * 2 * (2 * 3 + 3 * 4 + 2 * 4));
  EXPECT_NEAR(total_facet_measure(m, "bottom"), 1.0 * 2.0, 1e-13);  // z = 0
  EXPECT_NEAR(total_facet_measure(m, "front"), 1.0 * 3.0, 1e-13);   // y = 0
  EXPECT_NEAR(total_facet_measure(m, "right"), 2.0 * 3.0, 1e-13);   // x = 1
  for (int f : m.facets_of_parts({"top"})) EXPECT_NEAR(m.facet_normal(f)[2], 1.0, 1e-14);
}

TEST(Mesh, TagFacetsOverridesASubset) {
  Mesh m = make_rectangle({0, 0, 0}, {2, 2, 0}, 10, 10);
  m.tag_facets("contact", [](const Point& x) { return std::abs(x[1]) < 1e-12 && x[0] > 0.8 && x[0] < 1.2; });
  EXPECT_EQ(m.part_size("contact"), 2);
  EXPECT_EQ(m.part_size("bottom"), 8);
  EXPECT_EQ(m.nodes_of_parts({"contact"}).size(), 3u);
}

TEST(Mesh, SizeRange) {
  const Mesh m = make_rectangle({0, 0, 0}, {1, 1, 0}, 4, 4);
  const auto [hmin, hmax] = m.size_range();
  EXPECT_NEAR(hmin, std::sqrt(2.0) / 4, 1e-14);
  EXPECT_NEAR(hmax, std::sqrt(2.0) / 4, 1e-14);
}

TEST(Mesh, BadGeneratorInputIsAnError) {
  EXPECT_THROW(make_interval(0, 1, 0), std::runtime_error);
  EXPECT_THROW(make_rectangle({0, 0, 0}, {-1, 1, 0}, 2, 2), std::runtime_error);
}

/// Issue 11 item 2: every generator refuses a mesh beyond kMaxGeneratedCells
/// before allocating it (these would need terabytes).
TEST(Mesh, GeneratorsRefuseHugeMeshesBeforeAllocating) {
  auto message = [](auto make) {
    try {
      make();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([] { make_interval(0, 1, 40'000'000); }),
            "the mesh would have 40000000 cells; at most 30000000 are allowed (use fewer cells per edge)");
  EXPECT_EQ(message([] { make_rectangle({0, 0, 0}, {2, 2, 0}, 5000, 5000); }),
            "the mesh would have 50000000 cells; at most 30000000 are allowed (use fewer cells per edge)");
  EXPECT_EQ(message([] { make_box({0, 0, 0}, {2, 2, 2}, 100000, 100000, 100000); }),
            "the mesh would have 6000000000000000 cells; at most 30000000 are allowed (use fewer cells per edge)");
}

}  // namespace
}  // namespace vpc

namespace vpc {
namespace {

/// Cell centroids rounded to 1e-9, mirrored about x = xm if asked, sorted.
std::vector<std::array<long long, 3>> centroids(const Mesh& m, bool mirror, double xm) {
  std::vector<std::array<long long, 3>> out;
  for (int c = 0; c < m.n_cells(); ++c) {
    Point p = m.cell_centroid(c);
    if (mirror) p[0] = 2 * xm - p[0];
    out.push_back({std::llround(p[0] * 1e9), std::llround(p[1] * 1e9), std::llround(p[2] * 1e9)});
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Issue 11 item 16: every way of cutting the squares gives a conforming mesh (a
// facet shared by two cells is not a boundary facet: only the 2(nx + ny) outer
// edges are), of the right cell count and area; "alternate" (even n) and "crossed"
// are mirror-symmetric about x = 1, "right" is not.
TEST(Mesh, RectangleDiagonals) {
  for (const std::string& name : diagonal_names()) {
    const Diagonal d = diagonal_from_name(name);
    const Mesh m = make_rectangle({0, 0, 0}, {2, 1, 0}, 4, 3, d);
    EXPECT_EQ(m.n_cells(), (d == Diagonal::crossed ? 4 : 2) * 4 * 3) << name;
    EXPECT_EQ(m.n_nodes(), 5 * 4 + (d == Diagonal::crossed ? 12 : 0)) << name;
    EXPECT_EQ(m.n_facets(), 2 * (4 + 3)) << name;
    EXPECT_NEAR(total_volume(m), 2.0, 1e-13) << name;
    EXPECT_NEAR(total_facet_measure(m, "bottom"), 2.0, 1e-14) << name;
    EXPECT_NEAR(total_facet_measure(m, "left"), 1.0, 1e-14) << name;
    const bool symmetric = centroids(m, false, 1.0) == centroids(m, true, 1.0);
    EXPECT_EQ(symmetric, d == Diagonal::alternate || d == Diagonal::crossed) << name;
  }
  EXPECT_FALSE(centroids(make_rectangle({0, 0, 0}, {2, 1, 0}, 5, 3, Diagonal::alternate), false, 1.0) ==
               centroids(make_rectangle({0, 0, 0}, {2, 1, 0}, 5, 3, Diagonal::alternate), true, 1.0))
      << "alternate with an odd number of cells is not symmetric (documented)";
}

TEST(Mesh, BoxDiagonals) {
  for (const std::string& name : diagonal_names()) {
    const Diagonal d = diagonal_from_name(name);
    const Mesh m = make_box({0, 0, 0}, {2, 1, 3}, 2, 3, 4, d);
    const bool crossed = d == Diagonal::crossed;
    EXPECT_EQ(m.n_cells(), (crossed ? 24 : 6) * 2 * 3 * 4) << name;
    EXPECT_EQ(m.n_facets(), (crossed ? 4 : 2) * 2 * (2 * 3 + 3 * 4 + 4 * 2)) << name;  // conforming
    EXPECT_NEAR(total_volume(m), 6.0, 1e-12) << name;
    EXPECT_NEAR(total_facet_measure(m, "bottom"), 2.0, 1e-13) << name;
    EXPECT_NEAR(total_facet_measure(m, "front"), 6.0, 1e-13) << name;
    const bool symmetric = centroids(m, false, 1.0) == centroids(m, true, 1.0);
    EXPECT_EQ(symmetric, d == Diagonal::alternate || d == Diagonal::crossed) << name;
  }
}

TEST(Mesh, UnknownDiagonalListsTheNames) {
  try {
    diagonal_from_name("up");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "unknown diagonal 'up'; expected one of: right, left, alternate, crossed");
  }
}

}  // namespace
}  // namespace vpc
