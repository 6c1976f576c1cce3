// Issue 51's first piece (mesh/bisection.hpp): conforming newest-vertex bisection of triangle meshes. The
// leaves stay conforming (every interior edge shared by two leaves, no hanging node), keep the area, their
// orientation, the boundary parts and the regions, the closure bisects exactly what conformity needs, and
// the angles stay bounded below when one vertex is refined 30 levels deep.
#include "core/error.hpp"
#include "mesh/bisection.hpp"
#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace vpc {
namespace {

double signed_area(const Mesh& m, int c) {
  const int* v = m.cell(c);
  const Point &p = m.node(v[0]), &q = m.node(v[1]), &r = m.node(v[2]);
  return 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
}

/// Conformity: every edge of a leaf is an edge of one other leaf or a boundary facet, and no leaf's edge
/// holds another node (a hanging node would make an edge of one leaf two edges of its neighbours).
void expect_conforming(const Mesh& m) {
  std::map<std::pair<int, int>, int> edges;
  for (int c = 0; c < m.n_cells(); ++c)
    for (int e = 0; e < 3; ++e) {
      const int a = m.cell(c)[e], b = m.cell(c)[(e + 1) % 3];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  std::set<std::pair<int, int>> boundary;
  for (int f = 0; f < m.n_facets(); ++f) {
    const int a = m.facet(f)[0], b = m.facet(f)[1];
    boundary.insert({std::min(a, b), std::max(a, b)});
  }
  int once = 0;
  for (const auto& [edge, count] : edges) {
    ASSERT_LE(count, 2);
    if (count == 1) {
      ++once;
      EXPECT_TRUE(boundary.count(edge)) << "edge " << edge.first << "-" << edge.second << " of one leaf is not a boundary facet";
    }
  }
  EXPECT_EQ(once, m.n_facets());  // the boundary facets are exactly the edges of one leaf
  for (int c = 0; c < m.n_cells(); ++c) EXPECT_GT(signed_area(m, c), 0) << "cell " << c;
}

double part_length(const Mesh& m, const std::string& part) {
  double s = 0;
  for (int f : m.facets_of_parts({part})) s += m.facet_measure(f);
  return s;
}

TEST(Bisection, RefiningEveryLeafKeepsTheMeshConformingWithItsPartsAndRegions) {
  Mesh coarse = make_rectangle({0, 0, 0}, {2, 1, 0}, 4, 3, Diagonal::alternate);
  coarse.tag_cells("left", [](const Point& x) { return x[0] < 1; });
  BisectionForest forest(coarse);
  for (int round = 0; round < 4; ++round) forest.refine(forest.leaves());
  const Mesh fine = forest.leaf_mesh();
  expect_conforming(fine);
  double area = 0, left = 0;
  for (int c = 0; c < fine.n_cells(); ++c) {
    area += signed_area(fine, c);
    if (fine.cell_region(c) == fine.find_region("left")) left += signed_area(fine, c);
  }
  EXPECT_EQ(fine.n_cells(), coarse.n_cells() * 16);  // 4 rounds of one bisection each: 2^4 leaves a cell
  EXPECT_NEAR(area, 2.0, 1e-13);
  EXPECT_NEAR(left, 1.0, 1e-13);
  for (const std::string& part : coarse.part_names())
    EXPECT_NEAR(part_length(fine, part), part_length(coarse, part), 1e-14) << part;
  EXPECT_EQ(fine.part_names(), coarse.part_names());
}

TEST(Bisection, OneMarkedCellBisectsOnlyWhatConformityNeeds) {
  // The unit square's two triangles (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1) share their longest edge, the
  // diagonal: bisecting one bisects the other at the same midpoint (2 bisections, 4 leaves, 5 nodes).
  const Mesh square = make_rectangle({0, 0, 0}, {1, 1, 0}, 1, 1, Diagonal::right);
  BisectionForest forest(square);
  EXPECT_EQ(forest.refine({0}), 2);
  EXPECT_EQ(forest.leaves().size(), 4u);
  EXPECT_EQ(forest.n_nodes(), 5);
  expect_conforming(forest.leaf_mesh());
  // A leaf whose refinement edge is a boundary edge (a leg of the square) bisects alone.
  const int leg = forest.leaves().front();
  const auto& v = forest.vertices(leg);
  const Point &a = forest.node(v[0]), &b = forest.node(v[1]);
  EXPECT_TRUE(std::abs(a[0] - b[0]) < 1e-15 || std::abs(a[1] - b[1]) < 1e-15);  // axis-aligned: the square's side
  EXPECT_EQ(forest.refine({leg}), 1);
  expect_conforming(forest.leaf_mesh());
}

TEST(Bisection, AVertexRefinedThirtyLevelsDeepKeepsTheAnglesBoundedBelow) {
  // Marking, 30 times, every leaf at the corner (0, 0): the closure spreads the refinement and the
  // descendants stay in finitely many similarity classes.
  const Mesh coarse = make_rectangle({0, 0, 0}, {1, 1, 0}, 3, 3, Diagonal::alternate);
  BisectionForest forest(coarse);
  const double initial = forest.min_angle();
  int bisected = 0;
  for (int round = 0; round < 30; ++round) {
    std::vector<int> marked;
    for (int c : forest.leaves())
      for (int v : forest.vertices(c))
        if (forest.node(v)[0] == 0 && forest.node(v)[1] == 0) marked.push_back(c);
    bisected += forest.refine(marked);
  }
  const Mesh fine = forest.leaf_mesh();
  expect_conforming(fine);
  auto [h_min, h_max] = fine.size_range();
  const double least = forest.min_angle();
  std::printf("  30 levels at a corner: %d bisections, %d leaves, h in [%.3g, %.3g]; min angle %.2f deg (coarse %.2f)\n",
              bisected, fine.n_cells(), h_min, h_max, least * 180 / M_PI, initial * 180 / M_PI);
  EXPECT_LT(h_min, 1e-4);           // deep at the corner ...
  EXPECT_LT(fine.n_cells(), 2000);  // ... and local: a uniform mesh that fine would have ~1e9 cells
  EXPECT_GE(least, initial / 2 - 1e-12);
}

TEST(Bisection, AnUnstructuredMeshKeepsItsAnglesBoundedBelowThirtyLevelsDeep) {
  // The 5 x 5 rectangle's inner nodes moved by up to 0.3 h (deterministically): triangles of every shape,
  // refined at an inner node 30 times (the descendants of each coarse triangle: at most 4 similarity classes).
  Mesh coarse = make_rectangle({0, 0, 0}, {1, 1, 0}, 5, 5, Diagonal::alternate);
  unsigned state = 12345;
  auto next = [&] { return (state = state * 1103515245u + 12345u) % 1000 / 1000.0 - 0.5; };
  for (Point& x : coarse.nodes())
    if (x[0] > 1e-9 && x[0] < 1 - 1e-9 && x[1] > 1e-9 && x[1] < 1 - 1e-9) x[0] += 0.12 * next(), x[1] += 0.12 * next();
  BisectionForest forest(coarse);
  const double initial = forest.min_angle();
  const Point target = coarse.node(coarse.cell(12)[0]);
  for (int round = 0; round < 30; ++round) {
    std::vector<int> marked;
    for (int c : forest.leaves())
      for (int v : forest.vertices(c))
        if (forest.node(v)[0] == target[0] && forest.node(v)[1] == target[1]) marked.push_back(c);
    forest.refine(marked);
  }
  const Mesh fine = forest.leaf_mesh();
  expect_conforming(fine);
  const double least = forest.min_angle();
  std::printf("  unstructured, 30 rounds at (%.3f, %.3f): %d leaves, h_min %.3g; min angle %.2f deg (coarse %.2f)\n",
              target[0], target[1], fine.n_cells(), fine.size_range().first, least * 180 / M_PI, initial * 180 / M_PI);
  EXPECT_GE(least, initial / 4);
}

TEST(Bisection, NodalFieldsAreInterpolatedAndCellFieldsInheritedExactly) {
  // P1 fields are carried exactly (a new node is its edge's midpoint), P0 fields by inheritance: their
  // integrals are kept.
  const Mesh coarse = make_rectangle({0, 0, 0}, {2, 1, 0}, 4, 2, Diagonal::alternate);
  BisectionForest forest(coarse);
  auto linear = [](const Point& x) { return std::array<double, 2>{1 + 2 * x[0] - 3 * x[1], -0.5 * x[0] + x[1]}; };
  std::vector<double> u;
  for (const Point& x : coarse.nodes())
    for (double v : linear(x)) u.push_back(v);
  std::vector<double> z;  // one number a cell: its index, and its area's integral
  std::vector<int> before = forest.leaves();
  for (std::size_t k = 0; k < before.size(); ++k) z.push_back(static_cast<double>(k));
  for (int round = 0; round < 3; ++round) {
    std::vector<int> marked;
    for (int c : forest.leaves())
      if (forest.node(forest.vertices(c)[2])[0] < 0.8) marked.push_back(c);  // the left part
    forest.refine(marked);
    forest.interpolate(u, 2);
    z = forest.inherit(before, z, 1);
    before = forest.leaves();
  }
  double off = 0;
  for (int i = 0; i < forest.n_nodes(); ++i) {
    const auto exact = linear(forest.node(i));
    for (int j = 0; j < 2; ++j) off = std::max(off, std::abs(u[static_cast<std::size_t>(2 * i + j)] - exact[static_cast<std::size_t>(j)]));
  }
  EXPECT_EQ(u.size(), static_cast<std::size_t>(2 * forest.n_nodes()));
  EXPECT_LE(off, 1e-14);
  const Mesh fine = forest.leaf_mesh();
  ASSERT_EQ(z.size(), static_cast<std::size_t>(fine.n_cells()));
  std::vector<double> by_root(static_cast<std::size_t>(coarse.n_cells()), 0.0);
  for (int k = 0; k < fine.n_cells(); ++k) {
    const int c = before[static_cast<std::size_t>(k)];
    EXPECT_EQ(z[static_cast<std::size_t>(k)], static_cast<double>(forest.root(c)));  // the coarse cell's value
    by_root[static_cast<std::size_t>(forest.root(c))] += signed_area(fine, k);
  }
  for (int c = 0; c < coarse.n_cells(); ++c) EXPECT_NEAR(by_root[static_cast<std::size_t>(c)], signed_area(coarse, c), 1e-15);
  EXPECT_GT(fine.n_cells(), coarse.n_cells());
}

TEST(Bisection, CoarseningUndoesTheBisectionsAndKeepsTheIntegrals) {
  // Refined at a corner 6 times, then coarsened wherever every leaf is marked, round after round: each round
  // conforming, the cell field's integral kept (the area-weighted mean), and back to the coarse mesh at the end.
  Mesh coarse = make_rectangle({0, 0, 0}, {1, 1, 0}, 3, 3, Diagonal::alternate);
  BisectionForest forest(coarse);
  for (int round = 0; round < 6; ++round) {
    std::vector<int> marked;
    for (int c : forest.leaves())
      for (int v : forest.vertices(c))
        if (forest.node(v)[0] == 0 && forest.node(v)[1] == 0) marked.push_back(c);
    forest.refine(marked);
  }
  const int fine_cells = static_cast<int>(forest.leaves().size());
  std::vector<int> before = forest.leaves();
  std::vector<double> z;  // x + y at each leaf's centroid: not constant, so that the mean is a real mean
  double integral = 0;
  {
    const Mesh m = forest.leaf_mesh();
    for (int k = 0; k < m.n_cells(); ++k) {
      const Point x = m.cell_centroid(k);
      z.push_back(x[0] + x[1]);
      integral += z.back() * signed_area(m, k);
    }
  }
  int rounds = 0, removed = 0;
  for (int n; (n = forest.coarsen(forest.leaves())) > 0; ++rounds) {
    removed += n;
    z = forest.inherit(before, z, 1);
    before = forest.leaves();
    const Mesh m = forest.leaf_mesh();
    expect_conforming(m);
    double now = 0;
    for (int k = 0; k < m.n_cells(); ++k) now += z[static_cast<std::size_t>(k)] * signed_area(m, k);
    EXPECT_NEAR(now, integral, 1e-15);
  }
  const Mesh back = forest.leaf_mesh();
  std::printf("  coarsened in %d rounds: %d nodes removed, %d leaves -> %d (coarse %d)\n", rounds, removed, fine_cells,
              back.n_cells(), coarse.n_cells());
  EXPECT_EQ(back.n_cells(), coarse.n_cells());
  EXPECT_EQ(back.n_nodes(), coarse.n_nodes());
  for (int i = 0; i < coarse.n_nodes(); ++i) EXPECT_TRUE(forest.node_alive(i));
  // ... and refined again, conforming, from the coarsened forest.
  forest.refine(forest.leaves());
  expect_conforming(forest.leaf_mesh());
}

TEST(Bisection, ANodeIsRemovedOnlyWithItsWholePatch) {
  // Refined twice everywhere, then coarsened on the left half only: the nodes whose patch lies partly on
  // the right stay, and the mesh stays conforming.
  const Mesh coarse = make_rectangle({0, 0, 0}, {2, 1, 0}, 2, 1, Diagonal::alternate);
  BisectionForest forest(coarse);
  forest.refine(forest.leaves());
  forest.refine(forest.leaves());
  const int nodes = static_cast<int>(forest.leaf_mesh().n_nodes());
  std::vector<int> left;
  for (int c : forest.leaves()) {
    bool in = true;
    for (int v : forest.vertices(c)) in = in && forest.node(v)[0] <= 1 + 1e-12;
    if (in) left.push_back(c);
  }
  const int removed = forest.coarsen(left);
  const Mesh m = forest.leaf_mesh();
  expect_conforming(m);
  EXPECT_GT(removed, 0);
  EXPECT_EQ(m.n_nodes(), nodes - removed);
  for (int i = 0; i < forest.n_nodes(); ++i) {
    if (forest.node_alive(i)) continue;
    EXPECT_LT(forest.node(i)[0], 1 - 1e-12);  // nodes on x = 1 have a patch on the right
  }
}

TEST(Bisection, RefusesWhatItCannotBisect) {
  EXPECT_THROW(BisectionForest(make_interval(0, 1, 4)), Error);  // (tetrahedra: test_bisection_3d.cpp)
  BisectionForest forest(make_rectangle({0, 0, 0}, {1, 1, 0}, 1, 1));
  EXPECT_THROW(forest.refine({7}), Error);
  forest.refine({0});
  EXPECT_THROW(forest.coarsen({0}), Error);  // not a leaf any more
}

}  // namespace
}  // namespace vpc
