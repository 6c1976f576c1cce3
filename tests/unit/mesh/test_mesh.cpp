// Generators: counts, measures, boundary parts and outward normals.
#include "core/error.hpp"
#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
  EXPECT_EQ(message([] { make_interval(0, 1, 20'000'000); }),
            "the mesh would have 20000000 cells; at most 10000000 are allowed (use fewer cells per edge)");
  EXPECT_EQ(message([] { make_rectangle({0, 0, 0}, {2, 2, 0}, 5000, 5000); }),
            "the mesh would have 50000000 cells; at most 10000000 are allowed (use fewer cells per edge)");
  EXPECT_EQ(message([] { make_box({0, 0, 0}, {2, 2, 2}, 100000, 100000, 100000); }),
            "the mesh would have 6000000000000000 cells; at most 10000000 are allowed (use fewer cells per edge)");
}

}  // namespace
}  // namespace vpc
