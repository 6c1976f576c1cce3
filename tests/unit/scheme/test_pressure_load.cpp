// Issue 13: a normal pressure p(x, t) on boundary parts, [[loads.pressure]]: the
// traction −p n along the outward normal of the reference configuration.
#include "fem/assembly.hpp"
#include "io/case_file.hpp"
#include "mesh/generators.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <string>

#include "../error_of.hpp"

namespace vpc {
namespace {

/// The resultant of the nodal forces F (full space, d per node).
Point resultant(const Vector& F, int d) {
  Point r{0, 0, 0};
  for (Eigen::Index a = 0; a < F.size() / d; ++a)
    for (int i = 0; i < d; ++i) r[i] += F[a * d + i];
  return r;
}

// A uniform pressure p on a face of area A is the force −p A n; a pressure linear in
// x is integrated exactly (the facet rule has degree 2).
TEST(PressureLoad, ResultantIsMinusPressureTimesAreaAlongTheOutwardNormal) {
  const ScalarField p = [](const Point& x, double t) { return 3.0 * t * (1 + x[0]); };
  const Mesh square = make_rectangle({0, 0, 0}, {2, 1, 0}, 8, 4);
  Vector F = Vector::Zero(square.n_nodes() * 2);
  add_pressure_load(square, square.facets_of_parts({"top"}), p, 2.0, F);  // ∫0² 6(1 + x) dx = 24, n = +y
  Point r = resultant(F, 2);
  EXPECT_NEAR(r[0], 0.0, 1e-13);
  EXPECT_NEAR(r[1], -24.0, 1e-12);
  const Mesh box = make_box({0, 0, 0}, {2, 1, 3}, 2, 2, 3);
  F = Vector::Zero(box.n_nodes() * 3);
  add_pressure_load(box, box.facets_of_parts({"left"}), p, 1.0, F);  // x = 0: p = 3, area 3, n = −x
  r = resultant(F, 3);
  EXPECT_NEAR(r[0], 9.0, 1e-12);
  EXPECT_NEAR(r[1], 0.0, 1e-13);
  EXPECT_NEAR(r[2], 0.0, 1e-13);
}

/// A plane-stress plate clamped at the bottom, contact on the top far away, loaded on
/// its right side either by `pressure` or by `traction` (f2 on that side only).
Case plate(const std::string& loads, const std::string& traction = "") {
  const std::string text = R"(
[case]
name = "pressure-plate"
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [1.0, 2.0]
cells = [4, 8]
[boundary]
clamped = ["bottom"]
contact = ["top"]
)" + traction + R"(
[elasticity]
kind = "plane-stress"
E = 100.0
nu = 0.3
[viscoplasticity]
law = "maxwell-damage"
[contact]
gap = 1.0
[time]
T = 1.0
steps = 4
)" + loads;
  return parse_case(text, "pressure-plate.toml", ".", {});
}

TEST(PressureLoad, IsTheTractionMinusPNormalOnItsPart) {
  const Case by_pressure = plate("[[loads.pressure]]\nparts = \"right\"\np = \"2*t*y\"\n");
  // The same load as a Cartesian traction on the right side only (n = +x there).
  const Case traction = plate("[loads]\nf2 = [\"-2*t*y\", \"0\"]\n", "traction = [\"right\"]");
  TimeStepper a(by_pressure.problem, by_pressure.solvers), b(traction.problem, traction.solvers);
  while (!a.done()) {
    ASSERT_TRUE(a.step().ok);
    ASSERT_TRUE(b.step().ok);
    const double scale = b.state().u.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0.0);
    EXPECT_LE((a.state().u - b.state().u).cwiseAbs().maxCoeff(), 1e-13 * scale);
  }
}

TEST(PressureLoad, BadPressuresAreLocatedErrors) {
  const std::string clamped = error_of([] { plate("[[loads.pressure]]\nparts = \"bottom\"\np = 1\n"); });
  EXPECT_NE(clamped.find("pressure part 'bottom' is a clamped part"), std::string::npos) << clamped;
  const std::string unknown = error_of([] { plate("[[loads.pressure]]\nparts = \"side\"\np = 1\n"); });
  EXPECT_NE(unknown.find("pressure-plate.toml"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("loads.pressure[0].parts"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("'side' does not exist"), std::string::npos) << unknown;
  const std::string formula = error_of([] { plate("[[loads.pressure]]\nparts = \"right\"\np = \"vm\"\n"); });
  EXPECT_NE(formula.find("loads.pressure[0].p: invalid expression"), std::string::npos) << formula;
  const std::string missing = error_of([] { plate("[[loads.pressure]]\nparts = \"right\"\n"); });
  EXPECT_NE(missing.find("missing key 'loads.pressure[0].p'"), std::string::npos) << missing;
  const std::string table = error_of([] { plate("[loads]\npressure = 3\n"); });
  EXPECT_NE(table.find("an array of tables [[loads.pressure]]"), std::string::npos) << table;
}

}  // namespace
}  // namespace vpc
