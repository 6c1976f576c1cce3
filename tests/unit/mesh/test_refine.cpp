// `[mesh] refine = k` (mesh/refine.hpp): k levels of red refinement at once, numbered from the
// coarse mesh alone, and a rank's block of it equal to the whole refinement where they meet.
#include "../mesh_measures.hpp"
#include "core/error.hpp"
#include "fem/cell_geometry.hpp"
#include "mesh/generators.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/refine.hpp"
#include "verification/refine.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace vpc {
namespace {

/// Coarse meshes of every dimension, with parts, a region and unstructured 3D cells (Gmsh).
std::vector<Mesh> coarse_meshes() {
  std::vector<Mesh> meshes{make_interval(0, 2, 3), make_rectangle({0, 0, 0}, {2, 1, 0}, 3, 2, Diagonal::alternate),
                           make_box({0, 0, 0}, {1, 1, 2}, 2, 1, 2, Diagonal::right),
                           read_gmsh(VPC_TEST_DATA_DIR "/meshes/cube.geo")};
  for (Mesh& m : meshes) m.tag_cells("left", [](const Point& x) { return x[0] < 0.5; });
  return meshes;
}

TEST(MeshRefinement, LevelsKeepMeasuresPartsAndRegionsAndAreConforming) {
  for (const Mesh& coarse : coarse_meshes()) {
    const int d = coarse.dim();
    for (int levels = 1; levels <= (d == 3 ? 2 : 3); ++levels) {
      const Mesh fine = refine_mesh(coarse, levels);
      const int children = 1 << (d * levels);
      ASSERT_EQ(fine.n_cells(), coarse.n_cells() * children);
      EXPECT_NEAR(total_volume(fine), total_volume(coarse), 1e-12 * total_volume(coarse));
      EXPECT_EQ(fine.part_names(), coarse.part_names());
      for (const std::string& part : coarse.part_names()) {
        EXPECT_EQ(fine.part_size(part), coarse.part_size(part) * (1 << ((d - 1) * levels)));
        EXPECT_NEAR(part_measure(fine, part), part_measure(coarse, part), 1e-12);
      }
      EXPECT_EQ(fine.region_size("left"), coarse.region_size("left") * children);
      // Conforming: the facets used by one cell only are exactly the refined boundary facets.
      Mesh rebuilt = fine;
      rebuilt.build_boundary();
      EXPECT_EQ(rebuilt.n_facets(), fine.n_facets()) << "d = " << d << ", " << levels << " levels";
      // Nodes: every lattice point once (no two nodes at one place).
      std::vector<Point> x = fine.nodes();
      std::sort(x.begin(), x.end());
      EXPECT_EQ(std::adjacent_find(x.begin(), x.end()), x.end());
    }
  }
}

TEST(MeshRefinement, OneLevelAtATimeGivesTheSameCellsAndNodes) {
  // k levels at once against k single levels (verification/refine.hpp's hierarchy): the same node
  // positions (to rounding: the lattice's sums against midpoints of midpoints) and cell count.
  for (const Mesh& coarse : coarse_meshes()) {
    const Mesh at_once = refine_mesh(coarse, 2);
    const Mesh stepwise = refine_uniform(refine_uniform(coarse).fine).fine;
    ASSERT_EQ(at_once.n_nodes(), stepwise.n_nodes());
    ASSERT_EQ(at_once.n_cells(), stepwise.n_cells());
    double farthest = 0;  // from a node of one to the nearest of the other
    for (const Point& p : at_once.nodes()) {
      double nearest = INFINITY;
      for (const Point& q : stepwise.nodes())
        nearest = std::min(nearest, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
      farthest = std::max(farthest, nearest);
    }
    EXPECT_LT(farthest, 1e-14);
  }
}

TEST(MeshRefinement, TetrahedraStayShapedAfterSeveralLevels) {
  // Bey's refinement keeps a bounded number of shapes: the smallest child of 3 levels is 1/8^3 of
  // its parent's measure at least a good fraction.
  const Mesh coarse = read_gmsh(VPC_TEST_DATA_DIR "/meshes/cube.geo");
  const Mesh fine = refine_mesh(coarse, 3);
  const auto gc = compute_geometry(coarse), gf = compute_geometry(fine);
  for (int c = 0; c < fine.n_cells(); ++c)
    ASSERT_NEAR(gf[static_cast<std::size_t>(c)].volume, gc[static_cast<std::size_t>(c >> 9)].volume / 512, 1e-12);
  const auto [hmin, hmax] = fine.size_range();
  const auto [cmin, cmax] = coarse.size_range();
  EXPECT_LT(hmax, 0.5 * cmax);  // longest edges shrink
  EXPECT_GT(hmin, 0.1 * cmin);
}

TEST(MeshRefinement, EachRanksBlockIsTheWholeRefinementThere) {
  for (const Mesh& coarse : coarse_meshes()) {
    const int levels = 2;
    const MeshRefinement refinement(coarse, levels);
    const BlockMesh whole = refinement.refine_all();
    ASSERT_EQ(whole.whole_nodes, whole.mesh.n_nodes());
    for (int ranks : {1, 2, 3}) {
      if (coarse.n_cells() < ranks) continue;
      const std::vector<int> rank = split_cells(coarse, ranks);
      std::vector<int> counts(static_cast<std::size_t>(ranks), 0);
      for (const int r : rank) ++counts[static_cast<std::size_t>(r)];
      EXPECT_LE(*std::max_element(counts.begin(), counts.end()) - *std::min_element(counts.begin(), counts.end()), 1);
      long long own_cells = 0;
      for (int r = 0; r < ranks; ++r) {
        std::vector<int> own;
        for (int c = 0; c < coarse.n_cells(); ++c)
          if (rank[static_cast<std::size_t>(c)] == r) own.push_back(c);
        const BlockMesh b = refinement.refine(own, layer_cells(coarse, rank, r));
        const Mesh& m = b.mesh;
        ASSERT_EQ(static_cast<int>(b.node_id.size()), m.n_nodes());
        ASSERT_TRUE(std::is_sorted(b.node_id.begin(), b.node_id.end()));
        EXPECT_EQ(m.part_names(), whole.mesh.part_names());
        EXPECT_EQ(m.region_names(), whole.mesh.region_names());
        for (int v = 0; v < m.n_nodes(); ++v)
          ASSERT_EQ(m.node(v), whole.mesh.node(b.node_id[static_cast<std::size_t>(v)]));  // bit for bit
        for (int c = 0; c < m.n_cells(); ++c) {
          const int w = b.cell_id[static_cast<std::size_t>(c)];
          for (int a = 0; a <= coarse.dim(); ++a)
            ASSERT_EQ(b.node_id[static_cast<std::size_t>(m.cell(c)[a])], whole.mesh.cell(w)[a]);
          EXPECT_EQ(m.cell_region(c), whole.mesh.cell_region(w));
          own_cells += rank[static_cast<std::size_t>(w >> (coarse.dim() * levels))] == r;
        }
        // Every node of its own cells has all its cells and boundary facets here.
        std::vector<int> whole_around(static_cast<std::size_t>(whole.mesh.n_nodes()), 0), around(whole_around);
        for (int c = 0; c < whole.mesh.n_cells(); ++c)
          for (int a = 0; a <= coarse.dim(); ++a) ++whole_around[static_cast<std::size_t>(whole.mesh.cell(c)[a])];
        for (int f = 0; f < whole.mesh.n_facets(); ++f)
          for (int a = 0; a < coarse.dim(); ++a) ++whole_around[static_cast<std::size_t>(whole.mesh.facet(f)[a])];
        std::vector<char> of_own(static_cast<std::size_t>(whole.mesh.n_nodes()), 0);
        for (int c = 0; c < m.n_cells(); ++c)
          for (int a = 0; a <= coarse.dim(); ++a) {
            const auto v = static_cast<std::size_t>(b.node_id[static_cast<std::size_t>(m.cell(c)[a])]);
            ++around[v];
            if (rank[static_cast<std::size_t>(b.cell_id[static_cast<std::size_t>(c)] >> (coarse.dim() * levels))] == r) of_own[v] = 1;
          }
        for (int f = 0; f < m.n_facets(); ++f)
          for (int a = 0; a < coarse.dim(); ++a) ++around[static_cast<std::size_t>(b.node_id[static_cast<std::size_t>(m.facet(f)[a])])];
        for (std::size_t v = 0; v < of_own.size(); ++v)
          if (of_own[v]) {
            ASSERT_EQ(around[v], whole_around[v]) << "node " << v << ", rank " << r << " of " << ranks;
          }
        // Its facets: the whole mesh's boundary facets on its cells, none where the block is cut.
        std::map<std::vector<int>, int> whole_facets;
        for (int f = 0; f < whole.mesh.n_facets(); ++f) {
          std::vector<int> key(whole.mesh.facet(f), whole.mesh.facet(f) + coarse.dim());
          std::sort(key.begin(), key.end());
          whole_facets[key] = whole.mesh.facet_part(f);
        }
        for (int f = 0; f < m.n_facets(); ++f) {
          std::vector<int> key;
          for (int a = 0; a < coarse.dim(); ++a) key.push_back(b.node_id[static_cast<std::size_t>(m.facet(f)[a])]);
          std::sort(key.begin(), key.end());
          const auto it = whole_facets.find(key);
          ASSERT_NE(it, whole_facets.end());
          EXPECT_EQ(it->second, m.facet_part(f));
        }
      }
      EXPECT_EQ(own_cells, whole.mesh.n_cells());
    }
  }
}

TEST(MeshRefinement, RefusesWhatDoesNotFit) {
  const Mesh coarse = make_box({0, 0, 0}, {1, 1, 1}, 4, 4, 4, Diagonal::right);  // 384 tetrahedra
  try {
    (void)refine_mesh(coarse, 7);  // 384 · 2^21 = 8e8 cells
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at most"), std::string::npos) << e.what();
  }
  try {
    (void)split_cells(make_interval(0, 1, 2), 3);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fewer than the 3 ranks"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vpc
