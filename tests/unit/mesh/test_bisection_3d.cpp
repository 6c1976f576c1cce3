// Issue 51, 3D (mesh/bisection.hpp): Maubach's bisection of tetrahedra with the labelling from the global
// node numbers. The leaves stay conforming (every interior face shared by two leaves, every face of one leaf
// a boundary facet) on structured, unstructured and renumbered meshes under random marking; they keep the
// volume, the parts' areas and the regions; the dihedral angles stay bounded below 30 generations deep;
// P1 fields are carried exactly and coarsening undoes the bisections.
#include "core/error.hpp"
#include "mesh/bisection.hpp"
#include "mesh/generators.hpp"
#include "mesh/gmsh_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <random>

namespace vpc {
namespace {

double signed_volume(const Mesh& m, int c) {
  const int* v = m.cell(c);
  const Point &p = m.node(v[0]), &q = m.node(v[1]), &r = m.node(v[2]), &s = m.node(v[3]);
  const double a[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, b[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]},
               c3[3] = {s[0] - p[0], s[1] - p[1], s[2] - p[2]};
  return (a[0] * (b[1] * c3[2] - b[2] * c3[1]) - a[1] * (b[0] * c3[2] - b[2] * c3[0]) +
          a[2] * (b[0] * c3[1] - b[1] * c3[0])) / 6;
}

/// Conformity: every face of a leaf is a face of exactly one other leaf or a boundary facet, and the boundary
/// facets are exactly the faces of one leaf (a hanging node would leave a face of one leaf matched by none).
void expect_conforming(const Mesh& m) {
  std::map<std::array<int, 3>, int> faces;
  for (int c = 0; c < m.n_cells(); ++c)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> f{};
      for (int j = 0, n = 0; j < 4; ++j)
        if (j != k) f[static_cast<std::size_t>(n++)] = m.cell(c)[j];
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  std::map<std::array<int, 3>, int> boundary;
  for (int f = 0; f < m.n_facets(); ++f) {
    std::array<int, 3> v = {m.facet(f)[0], m.facet(f)[1], m.facet(f)[2]};
    std::sort(v.begin(), v.end());
    ++boundary[v];
  }
  int once = 0;
  for (const auto& [face, count] : faces) {
    ASSERT_LE(count, 2);
    if (count == 1) {
      ++once;
      EXPECT_EQ(boundary.count(face), 1u) << "a face of one leaf is not a boundary facet";
    }
  }
  EXPECT_EQ(once, m.n_facets());
  for (int c = 0; c < m.n_cells(); ++c) ASSERT_GT(signed_volume(m, c), 0) << "cell " << c;
}

double volume(const Mesh& m) {
  double v = 0;
  for (int c = 0; c < m.n_cells(); ++c) v += std::abs(signed_volume(m, c));  // (a generator's cells: either orientation)
  return v;
}

double part_area(const Mesh& m, const std::string& part) {
  double s = 0;
  for (int f : m.facets_of_parts({part})) s += m.facet_measure(f);
  return s;
}

/// The mesh with its nodes renumbered by `order` (new number of node i: order[i]) and its inner nodes moved
/// by up to `jitter` (deterministically): another global order, and tetrahedra of every shape.
Mesh renumbered(const Mesh& m, const std::vector<int>& order, double jitter, unsigned seed) {
  Mesh out(3);
  std::vector<Point> x(static_cast<std::size_t>(m.n_nodes()));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> shift(-jitter, jitter);
  const auto [lo, hi] = m.bounding_box();
  for (int i = 0; i < m.n_nodes(); ++i) {
    Point p = m.node(i);
    bool inner = true;
    for (int j = 0; j < 3; ++j) inner = inner && p[j] > lo[j] + 1e-9 && p[j] < hi[j] - 1e-9;
    if (inner)
      for (int j = 0; j < 3; ++j) p[j] += shift(rng);
    x[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])] = p;
  }
  for (const Point& p : x) out.add_node(p);
  for (int c = 0; c < m.n_cells(); ++c) {
    int v[4];
    for (int k = 0; k < 4; ++k) v[k] = order[static_cast<std::size_t>(m.cell(c)[k])];
    out.add_cell(v);
  }
  out.build_boundary();
  out.tag_facets("bottom", [](const Point& p) { return p[2] < 1e-9; });
  out.tag_facets("top", [&](const Point& p) { return p[2] > hi[2] - 1e-9; });
  return out;
}

TEST(Bisection3D, RefiningEveryLeafKeepsTheMeshConformingWithItsPartsAndRegions) {
  Mesh coarse = make_box({0, 0, 0}, {2, 1, 1}, 4, 2, 2);
  coarse.tag_cells("left", [](const Point& x) { return x[0] < 1; });
  BisectionForest forest(coarse);
  for (int round = 0; round < 6; ++round) forest.refine(forest.leaves());
  const Mesh fine = forest.leaf_mesh();
  expect_conforming(fine);
  EXPECT_EQ(fine.n_cells(), coarse.n_cells() * 64);  // 6 rounds of one bisection each
  EXPECT_NEAR(volume(fine), 2.0, 1e-12);
  double left = 0;
  for (int c = 0; c < fine.n_cells(); ++c)
    if (fine.cell_region(c) == fine.find_region("left")) left += signed_volume(fine, c);
  EXPECT_NEAR(left, 1.0, 1e-12);
  EXPECT_EQ(fine.part_names(), coarse.part_names());
  for (const std::string& part : coarse.part_names())
    EXPECT_NEAR(part_area(fine, part), part_area(coarse, part), 1e-12) << part;
  // Three generations halve every edge: 6 rounds, the uniform mesh of twice... four times finer
  EXPECT_NEAR(fine.size_range().second, coarse.size_range().second / 4, 1e-12);
}

TEST(Bisection3D, RandomMarkingOnRenumberedUnstructuredMeshesTerminatesConforming) {
  // Any global node order makes a labelling whose closure terminates (Alkämper, Gaspoz & Klöfkorn): random
  // orders of a jittered box, random marks, then coarsening back; conforming after every step.
  const Mesh box = make_box({0, 0, 0}, {1, 1, 1}, 3, 3, 3, Diagonal::alternate);
  for (unsigned seed = 1; seed <= 6; ++seed) {
    std::vector<int> order(static_cast<std::size_t>(box.n_nodes()));
    std::iota(order.begin(), order.end(), 0);
    std::mt19937 rng(seed);
    std::shuffle(order.begin(), order.end(), rng);
    const Mesh coarse = renumbered(box, order, 0.08, seed);
    const double v0 = volume(coarse);
    BisectionForest forest(coarse);
    for (int round = 0; round < 5; ++round) {
      std::vector<int> marked;
      for (int c : forest.leaves())
        if (rng() % 8 == 0) marked.push_back(c);
      forest.refine(marked);
      const Mesh fine = forest.leaf_mesh();
      expect_conforming(fine);
      ASSERT_NEAR(volume(fine), v0, 1e-12);
      ASSERT_NEAR(part_area(fine, "top"), part_area(coarse, "top"), 1e-12);
    }
    const std::size_t refined = forest.leaves().size();
    int rounds = 0;
    while (forest.coarsen(forest.leaves()) > 0) ++rounds;
    const Mesh back = forest.leaf_mesh();
    expect_conforming(back);
    EXPECT_NEAR(volume(back), v0, 1e-12);
    std::printf("  seed %u: %zu leaves refined, %d after %d rounds of coarsening (coarse %d)\n", seed, refined,
                back.n_cells(), rounds, coarse.n_cells());
    EXPECT_EQ(back.n_cells(), coarse.n_cells());  // every bisection undone
  }
}

TEST(Bisection3D, AVertexRefinedThirtyGenerationsDeepKeepsTheDihedralAnglesBoundedBelow) {
  // The Gmsh cube (unstructured) and a jittered box, each refined 30 times at one vertex: local, deep, and the
  // descendants in finitely many similarity classes (the smallest dihedral angle reported and bounded).
  std::vector<Mesh> meshes;
  meshes.push_back(read_gmsh(VPC_TEST_DATA_DIR "/meshes/cube.geo"));
  {
    const Mesh box = make_box({0, 0, 0}, {1, 1, 1}, 3, 3, 3, Diagonal::alternate);
    std::vector<int> order(static_cast<std::size_t>(box.n_nodes()));
    std::iota(order.begin(), order.end(), 0);
    meshes.push_back(renumbered(box, order, 0.1, 7));
  }
  for (const Mesh& coarse : meshes) {
    BisectionForest forest(coarse);
    const double initial = forest.min_angle();
    // an inner node (the one nearest the centre), or the corner for a mesh without one
    int target = 0;
    double best = 1e300;
    const auto [lo, hi] = coarse.bounding_box();
    for (int i = 0; i < coarse.n_nodes(); ++i) {
      double d = 0;
      for (int j = 0; j < 3; ++j) d += std::pow(coarse.node(i)[j] - (lo[j] + hi[j]) / 2, 2);
      if (d < best) best = d, target = i;
    }
    int bisected = 0;
    for (int round = 0; round < 30; ++round) {
      std::vector<int> marked;
      for (int c : forest.leaves())
        for (int v : forest.vertices(c))
          if (v == target) marked.push_back(c);
      bisected += forest.refine(marked);
    }
    const Mesh fine = forest.leaf_mesh();
    expect_conforming(fine);
    const double least = forest.min_angle();
    std::printf("  30 generations at node %d: %d bisections, %d leaves (coarse %d), h_min %.3g; min dihedral angle "
                "%.2f deg (coarse %.2f)\n",
                target, bisected, fine.n_cells(), coarse.n_cells(), fine.size_range().first, least * 180 / M_PI,
                initial * 180 / M_PI);
    EXPECT_LT(fine.size_range().first, coarse.size_range().first / 500);  // 30 generations: 2^-10 of the size
    EXPECT_LT(fine.n_cells(), 60 * coarse.n_cells());                      // local
    // The bound: Maubach's classes of a tetrahedron keep its dihedral angles above a fixed fraction; a
    // quarter of the coarse mesh's holds with room on these meshes (measured: printed above).
    EXPECT_GE(least, initial / 4);
  }
}

TEST(Bisection3D, NodalFieldsAreInterpolatedAndCellFieldsInheritedExactly) {
  const Mesh coarse = make_box({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  BisectionForest forest(coarse);
  auto linear = [](const Point& x) { return 1 + 2 * x[0] - 3 * x[1] + 0.5 * x[2]; };
  std::vector<double> u;
  for (int i = 0; i < coarse.n_nodes(); ++i) u.push_back(linear(coarse.node(i)));
  std::vector<int> before = forest.leaves();
  std::vector<double> cell(before.size());
  for (std::size_t k = 0; k < before.size(); ++k) cell[k] = static_cast<double>(k);
  for (int round = 0; round < 5; ++round) {
    std::vector<int> marked;
    for (int c : forest.leaves())
      if (forest.node(forest.vertices(c)[0])[0] < 0.5) marked.push_back(c);
    forest.refine(marked);
  }
  forest.interpolate(u, 1);
  for (int i = 0; i < forest.n_nodes(); ++i) EXPECT_NEAR(u[static_cast<std::size_t>(i)], linear(forest.node(i)), 1e-14);
  const std::vector<double> inherited = forest.inherit(before, cell, 1);
  const std::vector<int> now = forest.leaves();
  for (std::size_t k = 0; k < now.size(); ++k) EXPECT_EQ(inherited[k], static_cast<double>(forest.root(now[k])));
  // coarsening back: the volume-weighted mean of the children (here equal values: the root's number)
  before = now;
  for (int round = 0; round < 10; ++round) forest.coarsen(forest.leaves());
  const std::vector<double> back = forest.inherit(before, inherited, 1);
  const std::vector<int> roots = forest.leaves();
  ASSERT_EQ(roots.size(), cell.size());
  for (std::size_t k = 0; k < roots.size(); ++k) EXPECT_NEAR(back[k], static_cast<double>(roots[k]), 1e-13);
}

TEST(Bisection3D, ANodeIsRemovedOnlyWithItsWholePatch) {
  const Mesh coarse = make_box({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  BisectionForest forest(coarse);
  forest.refine(forest.leaves());
  forest.refine(forest.leaves());
  const std::vector<int> leaves = forest.leaves();
  // every patch found is whole: each of its parents bisected at the node's edge, both children marked
  for (const auto& patch : forest.coarsenable(leaves)) {
    const auto edge = forest.made_at(patch.node);
    for (int p : patch.parents) {
      const auto r = forest.refinement_edge(p);
      EXPECT_EQ(std::minmax(r[0], r[1]), std::minmax(edge[0], edge[1]));
      for (int child : forest.children(p)) EXPECT_EQ(forest.newest_vertex(child), patch.node);
    }
  }
  // half of one patch: nothing to remove
  const auto patches = forest.coarsenable(leaves);
  ASSERT_FALSE(patches.empty());
  const auto& one = patches.front();
  std::vector<int> half = {forest.children(one.parents.front())[0]};
  EXPECT_TRUE(forest.coarsenable(half).empty());
  EXPECT_EQ(forest.coarsen_patches({one}), 1);
  EXPECT_FALSE(forest.node_alive(one.node));
  expect_conforming(forest.leaf_mesh());
}

}  // namespace
}  // namespace vpc
