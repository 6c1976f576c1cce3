// Gmsh reader: .msh and .geo files, physical groups as parts, and the errors.
#include "mesh/gmsh_reader.hpp"

#include "../mesh_measures.hpp"
#include "core/error.hpp"
#include "fem/cell_geometry.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace vpc {
namespace {

namespace fs = std::filesystem;

fs::path data(const std::string& name) { return fs::path(VPC_TEST_DATA_DIR) / "meshes" / name; }

/// Writes `text` to a file of that name in a fresh per-process temporary folder.
fs::path temp_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("vpc_gmsh_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / name;
  std::ofstream(file) << text;
  return file;
}

double untagged_measure(const Mesh& m) {
  double s = 0;
  for (int f = 0; f < m.n_facets(); ++f)
    if (m.facet_part(f) < 0) s += m.facet_measure(f);
  return s;
}

/// The error message of `read_gmsh(file, options)`; fails the test if it does not throw.
std::string read_error(const fs::path& file, const GmshOptions& options = {}) {
  try {
    read_gmsh(file, options);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error reading " << file;
  return "";
}

/// square.geo: unit square, "clamped" on top, "contact" at the bottom, "free" left and right.
void expect_unit_square(const Mesh& m) {
  ASSERT_EQ(m.dim(), 2);
  EXPECT_EQ(m.part_names(), (std::vector<std::string>{"contact", "clamped", "free"}));
  EXPECT_NEAR(part_measure(m, "contact"), 1.0, 1e-12);
  EXPECT_NEAR(part_measure(m, "clamped"), 1.0, 1e-12);
  EXPECT_NEAR(part_measure(m, "free"), 2.0, 1e-12);  // two sides
  EXPECT_EQ(untagged_measure(m), 0.0);
  EXPECT_NEAR(total_volume(m), 1.0, 1e-12);
  for (int f : m.facets_of_parts({"contact"})) {
    EXPECT_NEAR(m.facet_centroid(f)[1], 0.0, 1e-14);
    EXPECT_NEAR(m.facet_normal(f)[0], 0.0, 1e-12);
    EXPECT_NEAR(m.facet_normal(f)[1], -1.0, 1e-12);
  }
  for (int f : m.facets_of_parts({"clamped"})) EXPECT_NEAR(m.facet_normal(f)[1], 1.0, 1e-12);
  for (const Point& x : m.nodes()) EXPECT_EQ(x[2], 0.0);
}

TEST(GmshReader, SquareMsh) {
  const Mesh m = read_gmsh(data("square.msh"));
  expect_unit_square(m);
  EXPECT_EQ(m.n_nodes(), 30);  // as written in the file: every node is used by a triangle
}

TEST(GmshReader, SquareGeo) {
  const Mesh m = read_gmsh(data("square.geo"));
  expect_unit_square(m);
  EXPECT_EQ(m.part_size("contact"), 4);  // h = 0.25 on the sides
}

TEST(GmshReader, SizeFactorRefinesAGeneratedMesh) {
  const Mesh coarse = read_gmsh(data("square.geo"));
  GmshOptions fine_options;
  fine_options.size_factor = 0.5;
  const Mesh fine = read_gmsh(data("square.geo"), fine_options);
  expect_unit_square(fine);
  EXPECT_EQ(fine.part_size("contact"), 2 * coarse.part_size("contact"));
  EXPECT_GT(fine.n_cells(), 3 * coarse.n_cells());
}

TEST(GmshReader, DescribeParts) {
  const Mesh m = read_gmsh(data("square.geo"));
  EXPECT_EQ(describe_parts(m), "contact (4 facets), clamped (4 facets), free (8 facets)");
  EXPECT_EQ(describe_parts(Mesh(2)), "no parts");
}

TEST(GmshReader, CubeGeoWithOpenCascade) {
  const Mesh m = read_gmsh(data("cube.geo"));
  ASSERT_EQ(m.dim(), 3);
  EXPECT_EQ(m.part_names(), (std::vector<std::string>{"contact", "clamped"}));
  EXPECT_NEAR(part_measure(m, "clamped"), 1.0, 1e-12);
  EXPECT_NEAR(part_measure(m, "contact"), 1.0, 1e-12);
  EXPECT_NEAR(untagged_measure(m), 4.0, 1e-12);  // the four sides are in no physical group
  EXPECT_NEAR(total_volume(m), 1.0, 1e-12);
  for (int f : m.facets_of_parts({"contact"})) EXPECT_NEAR(m.facet_normal(f)[2], -1.0, 1e-12);
  for (int f : m.facets_of_parts({"clamped"})) EXPECT_NEAR(m.facet_normal(f)[2], 1.0, 1e-12);
}

TEST(GmshReader, RodGeoIsOneDimensional) {
  const Mesh m = read_gmsh(data("rod.geo"));
  ASSERT_EQ(m.dim(), 1);
  EXPECT_EQ(m.n_cells(), 8);
  EXPECT_EQ(m.n_facets(), 2);
  ASSERT_EQ(m.part_size("left"), 1);
  ASSERT_EQ(m.part_size("right"), 1);
  EXPECT_EQ(m.node(m.nodes_of_parts({"left"})[0])[0], 0.0);
  EXPECT_EQ(m.node(m.nodes_of_parts({"right"})[0])[0], 1.0);
  EXPECT_DOUBLE_EQ(m.facet_normal(m.facets_of_parts({"left"})[0])[0], -1.0);
  EXPECT_DOUBLE_EQ(m.facet_normal(m.facets_of_parts({"right"})[0])[0], 1.0);
  EXPECT_NEAR(total_volume(m), 1.0, 1e-14);
}

TEST(GmshReader, QuadrilateralsAreRejected) {
  const std::string what = read_error(data("quads.geo"));
  EXPECT_NE(what.find("quads.geo"), std::string::npos) << what;
  EXPECT_NE(what.find("Quadrilateral"), std::string::npos) << what;
  EXPECT_NE(what.find("only linear simplices"), std::string::npos) << what;
}

TEST(GmshReader, SecondOrderElementsAreRejected) {
  const fs::path file = temp_file("p2.geo", R"(
Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
Mesh.ElementOrder = 2;
)");
  const std::string what = read_error(file);
  EXPECT_NE(what.find("Triangle 6"), std::string::npos) << what;
}

TEST(GmshReader, MissingFileNamesTheFile) {
  const std::string what = read_error("no/such/dir/missing_mesh.msh");
  EXPECT_NE(what.find("missing_mesh.msh"), std::string::npos) << what;
  EXPECT_NE(what.find("does not exist"), std::string::npos) << what;
}

TEST(GmshReader, GarbageIsAnErrorAndLeavesGmshUsable) {
  for (const char* name : {"garbage.msh", "garbage.geo"}) {
    const fs::path file = temp_file(name, "this is { not a mesh ;; $$ at all\n\x01\x02\n");
    const std::string what = read_error(file);
    EXPECT_NE(what.find(name), std::string::npos) << what;
  }
  const fs::path truncated = temp_file("truncated.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2\nxx\n");
  EXPECT_NE(read_error(truncated).find("truncated.msh"), std::string::npos);
  // Gmsh's .geo parser must not be left broken by the errors above.
  expect_unit_square(read_gmsh(data("square.geo")));
}

TEST(GmshReader, UnnamedGroupsAndUntaggedFacets) {
  const fs::path file = temp_file("unnamed.geo", R"(
Point(1) = {0, 0, 0, 0.5}; Point(2) = {2, 0, 0, 0.5}; Point(3) = {2, 1, 0, 0.5}; Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve(7) = {1};
)");
  const Mesh m = read_gmsh(file);
  EXPECT_EQ(m.part_names(), std::vector<std::string>{"group7"});
  EXPECT_NEAR(part_measure(m, "group7"), 2.0, 1e-12);
  EXPECT_NEAR(untagged_measure(m), 4.0, 1e-12);
  EXPECT_NEAR(total_volume(m), 2.0, 1e-12);
}

TEST(GmshReader, NoPhysicalGroupsGivesUntaggedBoundary) {
  const fs::path file = temp_file("plain.geo", R"(
Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
)");
  const Mesh m = read_gmsh(file);
  EXPECT_TRUE(m.part_names().empty());
  EXPECT_TRUE(m.region_names().empty());
  EXPECT_EQ(m.cell_region(0), -1);
  EXPECT_NEAR(untagged_measure(m), 2.0 + std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(total_volume(m), 0.5, 1e-12);
}

TEST(GmshReader, InteriorGroupIsAnError) {
  const fs::path file = temp_file("crack.geo", R"(
Point(1) = {0, 0, 0, 0.25}; Point(2) = {1, 0, 0, 0.25}; Point(3) = {1, 1, 0, 0.25}; Point(4) = {0, 1, 0, 0.25};
Point(5) = {0.3, 0.5, 0, 0.25}; Point(6) = {0.7, 0.5, 0, 0.25};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1}; Line(5) = {5, 6};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Line{5} In Surface{1};
Physical Curve("bottom") = {1};
Physical Curve("crack") = {5};
Physical Surface("body") = {1};
)");
  const std::string what = read_error(file);
  EXPECT_NE(what.find("'crack'"), std::string::npos) << what;
  EXPECT_NE(what.find("not on the boundary"), std::string::npos) << what;
}

TEST(GmshReader, FacetInTwoGroupsIsAnError) {
  const fs::path file = temp_file("twice.geo", R"(
Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("all") = {1, 2, 3};
)");
  const std::string what = read_error(file);
  EXPECT_NE(what.find("'bottom' and 'all'"), std::string::npos) << what;
}

// Physical groups of the mesh's dimension name regions of cells (the materials' regions).
TEST(GmshReader, PhysicalSurfacesAreRegions) {
  const Mesh m = read_gmsh(data("two-layers.geo"));
  EXPECT_EQ(m.region_names(), (std::vector<std::string>{"lower", "upper"}));
  EXPECT_EQ(m.region_size("lower") + m.region_size("upper"), m.n_cells());
  for (int c = 0; c < m.n_cells(); ++c)
    EXPECT_EQ(m.region_names()[m.cell_region(c)], m.cell_centroid(c)[1] < 0.5 ? "lower" : "upper") << c;
  EXPECT_EQ(m.part_names(), (std::vector<std::string>{"bottom", "top", "sides"}));
  const Mesh square = read_gmsh(data("square.geo"));  // one Physical Surface: every cell
  EXPECT_EQ(square.region_names(), std::vector<std::string>{"body"});
  EXPECT_EQ(square.region_size("body"), square.n_cells());
}

TEST(GmshReader, CellInTwoRegionsIsAnError) {
  const fs::path file = temp_file("two-regions.geo", R"(
Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
Physical Surface("steel") = {1};
Physical Surface("all") = {1};
)");
  const std::string what = read_error(file);
  EXPECT_NE(what.find("'steel' and 'all'"), std::string::npos) << what;
  EXPECT_NE(what.find("one region"), std::string::npos) << what;
}

TEST(GmshReader, PlanarMeshOffTheXYPlaneIsAnError) {
  const fs::path file = temp_file("lifted.geo", R"(
Point(1) = {0, 0, 1, 0.5}; Point(2) = {1, 0, 1, 0.5}; Point(3) = {0, 1, 1, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
)");
  const std::string what = read_error(file);
  EXPECT_NE(what.find("z = 1"), std::string::npos) << what;
  EXPECT_NE(what.find("plane z = 0"), std::string::npos) << what;
}

TEST(GmshReader, KeepsOnlyUsedNodesInTagOrder) {
  // MSH 2.2 written by hand: sparse node tags, node 99 used by no element, node 40
  // listed before node 30, and an unnamed physical line 5 at the bottom.
  const fs::path file = temp_file("sparse.msh", R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
10 0 0 0
20 1 0 0
99 5 5 0
40 0 1 0
30 1 1 0
$EndNodes
$Elements
3
1 1 2 5 1 10 20
2 2 2 0 1 10 20 30
3 2 2 0 1 10 30 40
$EndElements
)");
  const Mesh m = read_gmsh(file);
  ASSERT_EQ(m.n_nodes(), 4);
  EXPECT_EQ(m.node(2), (Point{1, 1, 0}));  // tag 30
  EXPECT_EQ(m.node(3), (Point{0, 1, 0}));  // tag 40
  EXPECT_EQ(m.n_cells(), 2);
  EXPECT_EQ(m.n_facets(), 4);
  EXPECT_EQ(describe_parts(m), "group5 (1 facet)");
  EXPECT_EQ(m.nodes_of_parts({"group5"}), (std::vector<int>{0, 1}));
}

TEST(GmshReader, DegenerateCellIsAnError) {
  const fs::path file = temp_file("flat.msh", R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
4 2 0 0
$EndNodes
$Elements
2
1 2 2 0 1 1 2 3
2 2 2 0 1 1 2 4
$EndElements
)");
  const std::string what = read_error(file);
  EXPECT_NE(what.find("Gmsh element 2 is degenerate"), std::string::npos) << what;
}

TEST(GmshReader, BadOptionsAreErrors) {
  GmshOptions options;
  options.size_factor = 0;
  EXPECT_NE(read_error(data("square.geo"), options).find("size factor"), std::string::npos);
  options = {};
  options.dim = 4;
  EXPECT_NE(read_error(data("square.geo"), options).find("dimension"), std::string::npos);
}

TEST(GmshReader, MissingDimensionIsAnError) {
  GmshOptions options;
  options.dim = 3;  // square.msh has triangles only
  const std::string what = read_error(data("square.msh"), options);
  EXPECT_NE(what.find("no elements of dimension 3"), std::string::npos) << what;
}

}  // namespace
}  // namespace vpc
