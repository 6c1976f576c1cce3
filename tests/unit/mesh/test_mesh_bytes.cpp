// A mesh as bytes and back (mesh/mesh_bytes.hpp): what rank 0 sends of a file's mesh to refine.
#include "core/error.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_bytes.hpp"

#include <gtest/gtest.h>

namespace vpc {
namespace {

TEST(MeshBytes, TheSameMeshBitForBit) {
  Mesh m = read_gmsh(VPC_TEST_DATA_DIR "/meshes/two-layers.geo");
  m.set_facet_part(0, "");  // an untagged facet too
  const Mesh back = mesh_from_bytes(mesh_bytes(m));
  EXPECT_EQ(back.dim(), m.dim());
  EXPECT_EQ(back.nodes(), m.nodes());
  EXPECT_EQ(back.cell_array(), m.cell_array());
  EXPECT_EQ(back.part_names(), m.part_names());
  EXPECT_EQ(back.region_names(), m.region_names());
  ASSERT_EQ(back.n_facets(), m.n_facets());
  for (int f = 0; f < m.n_facets(); ++f) {
    EXPECT_EQ(back.facet_part(f), m.facet_part(f));
    for (int a = 0; a < m.nodes_per_facet(); ++a) EXPECT_EQ(back.facet(f)[a], m.facet(f)[a]);
  }
  for (int c = 0; c < m.n_cells(); ++c) EXPECT_EQ(back.cell_region(c), m.cell_region(c));
}

TEST(MeshBytes, BytesCutShortAreAnError) {
  const std::string bytes = mesh_bytes(read_gmsh(VPC_TEST_DATA_DIR "/meshes/square.msh"));
  EXPECT_THROW((void)mesh_from_bytes(std::string_view(bytes).substr(0, bytes.size() / 2)), Error);
}

}  // namespace
}  // namespace vpc
