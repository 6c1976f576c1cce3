// Issue 13: several materials (SPEC §6): ℰ, G and φ per region of cells (a Gmsh
// physical group of the mesh's dimension, or a case file's `where`), one β over the body.
#include "io/case_file.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../error_of.hpp"
#include "../run_to_end.hpp"

namespace vpc {
namespace {

Case parse(const std::string& text) { return parse_case(text, "materials.toml", ".", {}); }


// An elastic bar −(E u')' = 1 on [0, 1], u(0) = 0, free at x = 1 (the gap never
// closes), E = 1 on [0, 1/2] and 4 on [1/2, 1]: P1 is exact at the nodes in 1D when E
// jumps at a node, u(x) = ∫₀ˣ (1 − s)/E(s) ds, and σ on each cell is 1 − x at its midpoint.
TEST(Materials, SeriesBarIsExactAtTheNodes) {
  const Case c = parse(R"(
[mesh]
generator = "interval"
lower = [0.0]
upper = [1.0]
cells = [8]
[boundary]
clamped = ["left"]
contact = ["right"]
[elasticity]
E = 1.0
[loads]
f0 = ["1"]
[contact]
gap = 10.0
[time]
T = 1.0
steps = 1
[[material]]
name = "stiff"
where = "x > 0.5"
[material.elasticity]
E = 4.0
)");
  const auto s = run_to_end(c);
  const Mesh& m = s->mesh();
  auto exact = [](double x) {
    const double w = x - x * x / 2;  // ∫₀ˣ (1 − s) ds
    return x <= 0.5 ? w : 0.375 + (w - 0.375) / 4;
  };
  for (int i = 0; i < m.n_nodes(); ++i) EXPECT_NEAR(s->state().u[i], exact(m.node(i)[0]), 1e-14) << i;
  EXPECT_NEAR(s->state().u[m.n_nodes() - 1], 0.40625, 1e-14);
  for (int k = 0; k < m.n_cells(); ++k)
    EXPECT_NEAR(s->state().sigma[k](0, 0), 1 - m.cell_centroid(k)[0], 1e-13) << k;
}

/// A plane-stress block with the law G and the [damage] section `damage`; `extra` is appended (materials).
std::string block(const std::string& law, const std::string& damage, const std::string& extra) {
  return fmt::format(R"(
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [8, 4]
[boundary]
clamped = ["top"]
contact = ["bottom"]
[elasticity]
kind = "plane-stress"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "{}"
[damage]
{}
[loads]
f0 = ["0", "-40*t"]
[time]
T = 1.0
steps = 5
)",
                     law, damage) +
         extra;
}

// A material that repeats the body's data changes no bit of the result.
TEST(Materials, ACopyOfTheBodysMaterialChangesNothing) {
  const auto one = run_to_end(parse(block("maxwell-damage", "source = \"von-mises\"\nc = 0.01", "")));
  const auto two = run_to_end(parse(block("maxwell-damage", "source = \"von-mises\"\nc = 0.01", R"(
[[material]]
name = "copy"
where = "x > 1"
[material.viscoplasticity]
law = "maxwell-damage"
[material.damage]
source = "von-mises"
c = 0.01
)")));
  EXPECT_EQ(one->state().u, two->state().u);
  EXPECT_EQ(one->state().beta, two->state().beta);
  for (std::size_t c = 0; c < one->state().sigma.size(); ++c)
    for (int i = 0; i < 6; ++i) EXPECT_EQ(one->state().sigma[c][i], two->state().sigma[c][i]);
}

// G and φ act where their material is: an elastic body (G = 0, φ = 0) with a damaging
// viscoplastic lower half keeps z = 0 on its own cells; β decreases (one field, diffusing)
// and is lowest in the lower half.
TEST(Materials, LawAndSourceActOnTheirCells) {
  const auto s = run_to_end(parse(block("elastic", "source = \"zero\"", R"(
[[material]]
name = "soft"
where = "y < 0.5"
[material.elasticity]
E = 500.0
[material.viscoplasticity]
law = "maxwell-damage"
[material.damage]
source = "von-mises"
c = 0.05
)")));
  const Mesh& m = s->mesh();
  int viscous = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    const double z = s->state().z[c].norm();
    if (m.cell_centroid(c)[1] > 0.5) {
      EXPECT_EQ(z, 0.0) << c;
    } else {
      viscous += z > 0;
    }
  }
  EXPECT_EQ(viscous, m.n_cells() / 2);
  int lowest = 0;
  for (int i = 0; i < m.n_nodes(); ++i)
    if (s->state().beta[i] < s->state().beta[lowest]) lowest = i;
  EXPECT_LT(s->state().beta[lowest], 1.0);
  EXPECT_LT(m.node(lowest)[1], 0.5);
  EXPECT_EQ(s->problem().material_list()[1].elasticity.young(), 500.0);
  EXPECT_EQ(s->problem().material_list()[1].elasticity.poisson(), 0.3);  // left out: the body's
}

/// The two-layer Gmsh rectangle ([0, 2] × [0, 1], regions "lower" and "upper").
std::string layers(const std::string& material) {
  return fmt::format(R"(
[mesh]
file = "{}/meshes/two-layers.geo"
[boundary]
clamped = ["top"]
contact = ["bottom"]
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "maxwell-damage"
[damage]
source = "von-mises"
c = 0.01
[loads]
f0 = ["0", "-40*t"]
[time]
T = 1.0
steps = 3
[[material]]
name = "hard"
{}
[material.elasticity]
E = 5000.0
)",
                     VPC_TEST_DATA_DIR, material);
}

// A Gmsh region and a `where` that selects the same cells give the same run, bit for bit.
TEST(Materials, GmshRegionsAndWherePredicatesAgree) {
  const Case by_region = parse(layers(R"(regions = ["upper"])"));
  const Case by_where = parse(layers(R"(where = "y > 0.5")"));
  const std::vector<int> cells = cell_materials(*by_region.problem);
  EXPECT_EQ(cells, cell_materials(*by_where.problem));
  EXPECT_EQ(std::count(cells.begin(), cells.end(), 1), by_region.problem->mesh.region_size("upper"));
  const auto a = run_to_end(by_region), b = run_to_end(by_where);
  EXPECT_EQ(a->state().u, b->state().u);
  EXPECT_EQ(a->state().beta, b->state().beta);
  // The stiffer upper layer deforms less than the same body in one material.
  const std::string text = layers(R"(regions = ["upper"])");
  const auto soft = run_to_end(parse(text.substr(0, text.find("[[material]]"))));
  EXPECT_LT(a->state().u.norm(), soft->state().u.norm());
}

TEST(Materials, ErrorsAreLocated) {
  auto error = [](const std::string& extra) {
    return error_of([&] { parse(block("maxwell-damage", "source = \"von-mises\"\nc = 0.01", extra)); });
  };
  const std::string no_region = error("[[material]]\nname = \"m\"\nregions = [\"steel\"]\n");
  EXPECT_NE(no_region.find("materials.toml:"), std::string::npos) << no_region;
  EXPECT_NE(no_region.find("region 'steel'"), std::string::npos) << no_region;
  EXPECT_NE(no_region.find("physical groups"), std::string::npos) << no_region;
  const std::string nothing = error("[[material]]\nname = \"m\"\nwhere = \"x > 5\"\n");
  EXPECT_NE(nothing.find("material[0].where"), std::string::npos) << nothing;
  EXPECT_NE(nothing.find("selects no cell"), std::string::npos) << nothing;
  const std::string both = error("[[material]]\nname = \"m\"\nwhere = \"x > 1\"\nregions = [\"a\"]\n");
  EXPECT_NE(both.find("not both"), std::string::npos) << both;
  const std::string neither = error("[[material]]\nname = \"m\"\n");
  EXPECT_NE(neither.find("not neither"), std::string::npos) << neither;
  const std::string kind =
      error("[[material]]\nname = \"m\"\nwhere = \"x > 1\"\n[material.elasticity]\nkind = \"plane-strain\"\n");
  EXPECT_NE(kind.find("material[0].elasticity.kind"), std::string::npos) << kind;
  EXPECT_NE(kind.find("'plane-stress'"), std::string::npos) << kind;
  const std::string kappa = error("[[material]]\nname = \"m\"\nwhere = \"x > 1\"\n[material.damage]\nkappa = 2.0\n");
  EXPECT_NE(kappa.find("material[0].damage.kappa"), std::string::npos) << kappa;
  EXPECT_NE(kappa.find("one field over the whole body"), std::string::npos) << kappa;
  const std::string twice = error(
      "[[material]]\nname = \"m\"\nwhere = \"x > 1\"\n[[material]]\nname = \"m\"\nwhere = \"x < 1\"\n");
  EXPECT_NE(twice.find("'m' is taken"), std::string::npos) << twice;
  const std::string param =
      error("[[material]]\nname = \"m\"\nwhere = \"x > 1\"\n[material.damage]\nsource = \"von-mises\"\nk = 1.0\n");
  EXPECT_NE(param.find("material[0].damage.k"), std::string::npos) << param;
  const std::string key = error("[[material]]\nname = \"m\"\nwhere = \"x > 1\"\nE = 3.0\n");
  EXPECT_NE(key.find("unknown key 'E' in [material[0]]"), std::string::npos) << key;
}

// Problem::validate checks materials made in code too.
TEST(Materials, ValidateRefusesAnotherKindOfElasticity) {
  const Case c = parse(block("elastic", "source = \"zero\"", ""));
  auto p = std::make_shared<Problem>(*c.problem);
  p->mesh.tag_cells("left", [](const Point& x) { return x[0] < 1; });
  p->materials.push_back({"m", {"left"}, Elasticity(Elasticity::Kind::PlaneStrain, 1.0, 0.3), p->law, p->source});
  const std::string what = error_of([&] { p->validate(); });
  EXPECT_NE(what.find("material 'm' has elasticity 'plane-strain' but the body's is 'plane-stress'"),
            std::string::npos)
      << what;
  p->materials.back().elasticity = p->elasticity;
  p->materials.back().regions = {"right"};
  const std::string missing = error_of([&] { p->validate(); });
  EXPECT_NE(missing.find("no cell in region 'right' (its regions: left)"), std::string::npos) << missing;
}

}  // namespace
}  // namespace vpc
