// Issue 13: prescribed displacement components and symmetry planes (SPEC §6): the
// lifting u = u_D + ũ, the reactions, and the located errors of [boundary].
#include "io/case_file.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../error_of.hpp"

namespace vpc {
namespace {

TEST(DofMap, PrescribedComponentsAreDroppedOneByOne) {
  const DofMap dofs(2, {-1, 0, -1, -1, 1, -1});  // node 0: uy fixed; node 2: ux fixed
  EXPECT_EQ(dofs.n_full(), 6);
  EXPECT_EQ(dofs.n_free(), 4);
  EXPECT_EQ(dofs.free_index(0), 0);
  EXPECT_EQ(dofs.free_index(1), -1);
  EXPECT_EQ(dofs.free_index(3), 2);
  EXPECT_EQ(dofs.free_index(4), -1);
  EXPECT_EQ(dofs.free_index(5), 3);
}

/// A plane-strain block [x0, 1] × [0, 1] (crossed diagonals: symmetric about x = 0) of the
/// paper's material, lifted by a rigid cylinder of radius 2 under x = 0; `boundary` is its
/// [boundary] section and what follows it.
Case block(double x0, int nx, const std::string& boundary) {
  const std::string text = fmt::format(R"(
[case]
name = "block"
[mesh]
generator = "rectangle"
lower = [{}, 0.0]
upper = [1.0, 1.0]
cells = [{}, 4]
diagonal = "crossed"
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "maxwell-damage"
[damage]
source = "von-mises"
c = 0.01
[[obstacle]]
shape = "cylinder"
center = [0.0, "-2.0 + 0.01*t"]
radius = 2.0
[time]
T = 1.0
steps = 5
)",
                                       x0, nx);
  return parse_case(text + boundary, "block.toml", ".", {});
}

// The half model on a symmetry plane is the full model's right half: same u, σ, β
// at the same points, half the contact force and half the reaction.
TEST(Symmetry, TheHalfModelIsTheFullModelsHalf) {
  const Case full = block(-1.0, 8, "[boundary]\nclamped = [\"top\"]\ncontact = [\"bottom\"]\n");
  const Case half = block(0.0, 4, "[boundary]\nclamped = [\"top\"]\ncontact = [\"bottom\"]\nsymmetry = [\"left\"]\n");
  TimeStepper f(full.problem, full.solvers), h(half.problem, half.solvers);
  const Mesh &mf = f.mesh(), &mh = h.mesh();
  std::vector<int> same(mh.n_nodes(), -1);  // the full mesh's node at each node of the half
  for (int i = 0; i < mh.n_nodes(); ++i)
    for (int j = 0; j < mf.n_nodes(); ++j)
      if (std::hypot(mh.node(i)[0] - mf.node(j)[0], mh.node(i)[1] - mf.node(j)[1]) < 1e-12) same[i] = j;
  while (!f.done()) {
    const StepReport rf = f.step(), rh = h.step();
    ASSERT_TRUE(rf.ok && rh.ok);
    ASSERT_GT(rf.contact.total_force, 0.0);
    EXPECT_NEAR(rh.contact.total_force, 0.5 * rf.contact.total_force, 1e-10 * rf.contact.total_force);
    EXPECT_NEAR(rh.reaction[1], 0.5 * rf.reaction[1], 1e-10 * std::abs(rf.reaction[1]));  // top: x, y
    for (int i = 0; i < mh.n_nodes(); ++i) {
      ASSERT_GE(same[i], 0);
      for (int c = 0; c < 2; ++c) EXPECT_NEAR(h.state().u[2 * i + c], f.state().u[2 * same[i] + c], 1e-12);
      EXPECT_NEAR(h.state().beta[i], f.state().beta[same[i]], 1e-12);
    }
  }
}

/// The plate [0, 1] × [0, 0.5] of `cells` ("[8, 4]"), then `rest`: the tests below.
std::string press_text(const std::string& cells, const std::string& rest) {
  return "[case]\nname = \"press\"\n[mesh]\ngenerator = \"rectangle\"\nlower = [0.0, 0.0]\nupper = [1.0, 0.5]\ncells = " +
         cells + "\n" + rest;
}

// Displacement control: the top moved in both components onto a foundation, held by a
// roller on the left, a pressure on the right. The reactions balance the contact force and
// the pressure; the top moves by exactly the prescribed amount.
TEST(PrescribedDisplacement, ReactionsBalanceTheContactForce) {
  const Case c = parse_case(press_text("[8, 4]", R"toml(
[boundary]
symmetry = ["left"]
contact = ["bottom"]
[[boundary.displacement]]
parts = ["top"]
ux = "0.001*t*x"
uy = "-0.002*t*(1 + x)"
[[loads.pressure]]
parts = ["right"]
p = "2*t*y"
[elasticity]
kind = "plane-stress"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "maxwell-damage"
[damage]
source = "von-mises"
c = 0.01
[contact]
gap = "0.001*x"
[time]
T = 1.0
steps = 4
)toml"),
                            "press.toml", ".", {});
  TimeStepper s(c.problem, c.solvers);
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok);
    ASSERT_EQ(r.reaction.size(), 3u);  // top: x, y; left: x
    const double P = r.contact.total_force;
    EXPECT_GT(P, 0.0);
    // The supports' forces on the body, the foundation's (+P along y) and the pressure's
    // (−∫p dy = −t/4 along x) cancel. The top-left corner, on both parts, counts once.
    EXPECT_NEAR(r.reaction[1] + P, 0.0, 1e-10 * P);
    EXPECT_NEAR(r.reaction[0] + r.reaction[2] - 0.25 * r.t, 0.0, 1e-10 * P);
    EXPECT_NE(r.reaction[2], 0.0);
    for (int i : s.mesh().nodes_of_parts({"top"})) {
      EXPECT_EQ(s.state().u[2 * i], 0.001 * r.t * s.mesh().node(i)[0]);
      EXPECT_EQ(s.state().u[2 * i + 1], -0.002 * r.t * (1 + s.mesh().node(i)[0]));
    }
  }
}

std::string press_error(const std::string& boundary, const std::string& elsewhere = "") {
  return error_of([&] {
    parse_case(press_text("[4, 2]", R"(
[elasticity]
kind = "plane-stress"
E = 1.0
nu = 0.3
[contact]
gap = 0.1
[time]
steps = 1
)" + elsewhere + boundary),
               "press.toml", ".", {});
  });
}

TEST(PrescribedDisplacement, BadBoundariesAreLocatedErrors) {
  std::string e = press_error("[boundary]\ncontact = [\"bottom\"]\n");
  EXPECT_NE(e.find("missing key 'boundary.clamped'"), std::string::npos) << e;
  e = press_error("[boundary]\ncontact = [\"bottom\"]\n[[boundary.displacement]]\nparts = [\"top\"]\nuz = 0\n");
  EXPECT_NE(e.find("press.toml:21:6: boundary.displacement[0].uz: the mesh has d = 2"), std::string::npos) << e;
  e = press_error("[boundary]\ncontact = [\"bottom\"]\n[[boundary.displacement]]\nparts = [\"top\"]\n");
  EXPECT_NE(e.find("expected at least one of ux, uy"), std::string::npos) << e;
  e = press_error("[boundary]\ncontact = [\"bottom\"]\n[[boundary.displacement]]\nparts = [\"tpo\"]\nuy = 0\n");
  EXPECT_NE(e.find("boundary part 'tpo' does not exist"), std::string::npos) << e;
  e = press_error("[boundary]\ncontact = [\"bottom\"]\nsymmetry = [\"slant\"]\n",
                  "[[mesh.part]]\nname = \"slant\"\nwhere = \"x > 0.99 || y > 0.49\"\n");
  EXPECT_NE(e.find("symmetry part 'slant' does not lie in a plane"), std::string::npos) << e;
  EXPECT_NE(e.find("press.toml:"), std::string::npos) << e;
  // Two values for one component at the corner (1, 0.5).
  e = press_error(
      "[boundary]\ncontact = [\"bottom\"]\nclamped = [\"left\"]\n[[boundary.displacement]]\nparts = [\"top\"]\nuy = "
      "\"-0.1*t\"\n[[boundary.displacement]]\nparts = [\"right\"]\nuy = 0\n");
  EXPECT_NE(e.find("uy at node"), std::string::npos) << e;
  EXPECT_NE(e.find("prescribed twice with different values at t = 1"), std::string::npos) << e;
  // Contact along a prescribed component (not a symmetry plane).
  e = press_error(
      "[boundary]\ncontact = [\"bottom\"]\nclamped = [\"top\"]\n[[boundary.displacement]]\nparts = [\"left\"]\nuy = 0\n");
  EXPECT_NE(e.find("boundary.contact: contact node"), std::string::npos) << e;
  EXPECT_NE(e.find("has uy prescribed (by press.toml:"), std::string::npos) << e;
  EXPECT_NE(e.find("boundary.displacement[0]), but its contact direction"), std::string::npos) << e;
  // The same values twice are not a conflict; a formula that is not finite is.
  e = press_error("[boundary]\ncontact = [\"bottom\"]\nclamped = [\"left\"]\n[[boundary.displacement]]\nparts = "
                  "[\"top\"]\nux = \"0*t\"\n");
  EXPECT_EQ(e, "(no vpc::Error thrown)");
  e = press_error("[boundary]\ncontact = [\"bottom\"]\n[[boundary.displacement]]\nparts = [\"top\"]\nux = \"1/(x - 0.5)\"\n"
                  "uy = 0\n");
  EXPECT_NE(e.find("(not finite) at t = 0 at node"), std::string::npos) << e;
}

}  // namespace
}  // namespace vpc
