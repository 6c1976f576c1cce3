// Candidate facet pairs (mortar/facet_search): the bucket grid finds exactly the pairs
// an all-pairs check of the bounding boxes finds.
#include "mortar/facet_search.hpp"
#include "surfaces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace vpc::mortar {
namespace {

std::vector<std::vector<int>> brute_force(const Surface& slave, const Surface& master, double margin) {
  std::vector<std::vector<int>> pairs(slave.n_facets());
  for (int s = 0; s < slave.n_facets(); ++s)
    for (int m = 0; m < master.n_facets(); ++m)
      if (facet_box(slave, s).near(facet_box(master, m), margin)) pairs[s].push_back(m);
  return pairs;
}

void expect_same_pairs(const Surface& slave, const Surface& master, double margin) {
  const FacetPairs found = candidate_pairs(slave, master, margin);
  const auto want = brute_force(slave, master, margin);
  int n = 0;
  for (int s = 0; s < slave.n_facets(); ++s) {
    const auto got = found.of(s);
    EXPECT_EQ(std::vector<int>(got.begin(), got.end()), want[s]) << "slave facet " << s << ", margin " << margin;
    n += static_cast<int>(want[s].size());
  }
  EXPECT_EQ(found.n_pairs(), n);
  EXPECT_GT(n, 0);  // the case pairs something
}

TEST(MortarFacetSearch, FindsTheBruteForcePairsIn3d) {
  // Wavy, irregular, rotated surfaces of different sizes and resolutions.
  const auto wavy = [](double h) {
    return [h](double u, double v) { return Point{u, v, h + 0.1 * std::sin(3 * u) * std::cos(2 * v)}; };
  };
  const Surface slave = test::grid(13, 9, 0, 1, 0, 0.8, wavy(0), 0, FacetOrder::Outward, false, 0.3);
  const Surface master = test::grid(17, 21, -0.2, 1.1, -0.1, 0.9, test::rotated(0.4, 0.5, 0.4, wavy(0.05)), 1000,
                                    FacetOrder::Inward, true, 0.35);
  for (const double margin : {0.0, 0.01, 0.05, 0.3}) expect_same_pairs(slave, master, margin);
}

TEST(MortarFacetSearch, FindsTheBruteForcePairsIn2d) {
  const auto f = [](double x) { return 0.2 * std::sin(4 * x); };
  const Surface slave = test::polyline(test::line_points(23, 0, 1, f, 0.4), 0, FacetOrder::Inward);
  const Surface master = test::polyline(test::line_points(
                                            37, -0.3, 1.2, [&](double x) { return f(x) + 0.03; }, 0.4),
                                        100, FacetOrder::Outward);
  for (const double margin : {0.0, 0.01, 0.05, 0.3}) expect_same_pairs(slave, master, margin);
}

TEST(MortarFacetSearch, FarSurfacesHaveNoPairs) {
  const Surface slave = test::grid(4, 4, 0, 1, 0, 1, test::plane_at(0), 0, FacetOrder::Outward);
  const Surface master = test::grid(4, 4, 0, 1, 0, 1, test::plane_at(0.5), 100, FacetOrder::Inward);
  EXPECT_EQ(candidate_pairs(slave, master, 0.4).n_pairs(), 0);
  expect_same_pairs(slave, master, 0.5);  // every slave facet pairs the master facets above and around it
}

}  // namespace
}  // namespace vpc::mortar
