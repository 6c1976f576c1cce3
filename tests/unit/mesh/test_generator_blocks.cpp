// Blocks of generated meshes (issue 30): the blocks of split_grid cover the grid once, and
// each block's mesh is the whole generator's mesh restricted to it, cell for cell, node for
// node (coordinates bit for bit), with the whole mesh's tagged boundary facets and no others.
#include "core/error.hpp"
#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace vpc {
namespace {

/// A facet as its sorted whole-mesh node numbers, with its part's name ("" untagged).
using Facet = std::pair<std::vector<int>, std::string>;

std::vector<Facet> tagged_facets(const Mesh& m, const std::vector<int>& node_id) {
  std::vector<Facet> out;
  for (int f = 0; f < m.n_facets(); ++f) {
    std::vector<int> v;
    for (int a = 0; a < m.nodes_per_facet(); ++a) v.push_back(node_id.empty() ? m.facet(f)[a] : node_id[m.facet(f)[a]]);
    std::sort(v.begin(), v.end());
    const int p = m.facet_part(f);
    out.emplace_back(v, p < 0 ? std::string() : m.part_names()[p]);
  }
  return out;
}

struct Generated {
  int dim;
  std::array<int, 3> n;
  Diagonal diagonal;
};

Mesh whole(const Generated& g) {
  if (g.dim == 1) return make_interval(-1, 2, g.n[0]);
  if (g.dim == 2) return make_rectangle({-1, 0, 0}, {2, 0.7, 0}, g.n[0], g.n[1], g.diagonal);
  return make_box({-1, 0, 0.1}, {2, 0.7, 0.4}, g.n[0], g.n[1], g.n[2], g.diagonal);
}

BlockMesh block(const Generated& g, const GridBlock& b) {
  if (g.dim == 1) return make_interval_block(-1, 2, g.n[0], b);
  if (g.dim == 2) return make_rectangle_block({-1, 0, 0}, {2, 0.7, 0}, g.n[0], g.n[1], g.diagonal, b);
  return make_box_block({-1, 0, 0.1}, {2, 0.7, 0.4}, g.n[0], g.n[1], g.n[2], g.diagonal, b);
}

/// Every block of `parts` against the whole mesh.
void expect_blocks_restrict_the_whole_mesh(const Generated& g, int parts) {
  SCOPED_TRACE(::testing::Message() << "dim " << g.dim << ", diagonal " << static_cast<int>(g.diagonal) << ", "
                                    << parts << " parts");
  const Mesh m = whole(g);
  const std::vector<GridBlock> blocks = split_grid(whole_grid(g.n, g.dim), g.dim, parts);
  ASSERT_EQ(static_cast<int>(blocks.size()), parts);
  std::vector<int> cell_seen(m.n_cells(), 0), node_seen(m.n_nodes(), 0);
  std::vector<Facet> facets;
  for (const GridBlock& b : blocks) {
    const BlockMesh bm = block(g, b);
    EXPECT_EQ(bm.whole_nodes, m.n_nodes());
    EXPECT_EQ(bm.whole_cells, m.n_cells());
    ASSERT_EQ(bm.node_id.size(), static_cast<std::size_t>(bm.mesh.n_nodes()));
    ASSERT_EQ(bm.cell_id.size(), static_cast<std::size_t>(bm.mesh.n_cells()));
    EXPECT_TRUE(std::is_sorted(bm.cell_id.begin(), bm.cell_id.end()));  // the whole mesh's order
    EXPECT_TRUE(std::is_sorted(bm.node_id.begin(), bm.node_id.end()));
    for (int i = 0; i < bm.mesh.n_nodes(); ++i) {
      const int v = bm.node_id[i];
      ASSERT_GE(v, 0);
      ASSERT_LT(v, m.n_nodes());
      EXPECT_EQ(bm.mesh.node(i), m.node(v)) << "node " << v;  // bit for bit
      node_seen[v] = 1;
    }
    for (int c = 0; c < bm.mesh.n_cells(); ++c) {
      const int w = bm.cell_id[c];
      ASSERT_GE(w, 0);
      ASSERT_LT(w, m.n_cells());
      ++cell_seen[w];
      for (int a = 0; a < m.nodes_per_cell(); ++a) EXPECT_EQ(bm.node_id[bm.mesh.cell(c)[a]], m.cell(w)[a]) << "cell " << w;
    }
    const std::vector<Facet> f = tagged_facets(bm.mesh, bm.node_id);
    for (const Facet& x : f) EXPECT_NE(x.second, "") << "a block keeps the whole mesh's (tagged) boundary only";
    facets.insert(facets.end(), f.begin(), f.end());
  }
  EXPECT_TRUE(std::all_of(cell_seen.begin(), cell_seen.end(), [](int k) { return k == 1; })) << "each cell in one block";
  EXPECT_TRUE(std::all_of(node_seen.begin(), node_seen.end(), [](int k) { return k == 1; }));
  std::vector<Facet> expected = tagged_facets(m, {});
  std::sort(expected.begin(), expected.end());
  std::sort(facets.begin(), facets.end());
  EXPECT_EQ(facets, expected);
}

TEST(GeneratorBlocks, EachBlockIsTheWholeMeshRestrictedToIt) {
  const std::vector<Generated> meshes = {
      {1, {7, 0, 0}, Diagonal::right},         {2, {5, 4, 0}, Diagonal::right}, {2, {5, 4, 0}, Diagonal::alternate},
      {2, {3, 4, 0}, Diagonal::crossed},       {3, {4, 3, 2}, Diagonal::right}, {3, {4, 3, 3}, Diagonal::alternate},
      {3, {3, 2, 3}, Diagonal::crossed},       {3, {2, 3, 2}, Diagonal::left}};
  for (const Generated& g : meshes)
    for (int parts : {1, 2, 3, 5}) expect_blocks_restrict_the_whole_mesh(g, parts);
}

TEST(GeneratorBlocks, TheWholeGridAsABlockIsTheWholeMesh) {
  const Mesh m = make_box({0, 0, 0}, {1, 1, 1}, 3, 2, 2, Diagonal::crossed);
  const BlockMesh b = make_box_block({0, 0, 0}, {1, 1, 1}, 3, 2, 2, Diagonal::crossed, whole_grid({3, 2, 2}, 3));
  EXPECT_EQ(b.mesh.nodes(), m.nodes());
  EXPECT_EQ(b.mesh.cell_array(), m.cell_array());
  EXPECT_EQ(tagged_facets(b.mesh, {}), tagged_facets(m, {}));  // in the same order
}

TEST(GeneratorBlocks, BisectionCutsTheLongestAxisInProportion) {
  const std::vector<GridBlock> b = split_grid(whole_grid({8, 4, 4}, 3), 3, 3);
  ASSERT_EQ(b.size(), 3u);
  // 3 parts: 1 | 2 along x (8 cells: cut at 3), then the right block's longest axis (y: 4, x: 5 -> x).
  EXPECT_EQ(b[0].lo, (std::array<int, 3>{0, 0, 0}));
  EXPECT_EQ(b[0].hi, (std::array<int, 3>{3, 4, 4}));
  // 8 slabs of 16 cubes in 3 parts: 3, 3 and 2 slabs, the nearest to equal that whole slabs allow.
  EXPECT_EQ(b[1].lo, (std::array<int, 3>{3, 0, 0}));
  EXPECT_EQ(b[1].hi, (std::array<int, 3>{6, 4, 4}));
  EXPECT_EQ(b[2].lo, (std::array<int, 3>{6, 0, 0}));
  EXPECT_EQ(b[2].hi, (std::array<int, 3>{8, 4, 4}));
  // A cube of cubes in 8: octants.
  for (const GridBlock& x : split_grid(whole_grid({6, 6, 6}, 3), 3, 8)) EXPECT_EQ(x.cells(), 27);
}

TEST(GeneratorBlocks, TooFewCellsForThePartsIsAnError) {
  EXPECT_THROW(split_grid(whole_grid({2, 1, 1}, 3), 3, 3), Error);
  EXPECT_THROW(split_grid(whole_grid({3, 0, 0}, 1), 1, 4), Error);
  EXPECT_NO_THROW(split_grid(whole_grid({2, 2, 1}, 3), 3, 4));
}

}  // namespace
}  // namespace vpc
