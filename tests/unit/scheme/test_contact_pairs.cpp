// Issue 29, second part: contact pairs between bodies by dual mortar (SPEC §8,
// `[[contact.pair]]`, problem/contact_pairs.hpp), on the serial engine and the dual solver.
// The contact patch test: two blocks of different stiffness, meshed without matching nodes,
// pressed together: the stress is uniform in both to round-off (node-to-segment fails it).
#include "../io/test_files.hpp"
#include "cases/builtin_cases.hpp"
#include "io/case_file.hpp"
#include "io/state_fields.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <string>

#include "../error_of.hpp"
#include "../run_to_end.hpp"

namespace vpc {
namespace {

/// The shipped contact patch test, cases/contact-patch-{2,3}d.toml: two blocks on [0, 1]^(d−1),
/// the case's [mesh] below z (y) = 0.5, body "upper" above it (E = 3000 against 1000, other cells
/// and diagonals), its top moved down by 0.01 t, on rollers; `extra` is added at the end.
std::string blocks(int d, const std::string& extra = "") {
  return case_source(fmt::format("contact-patch-{}d", d)).text + "\n" + extra;
}

/// The 2D blocks with the upper one `gap` above the lower one.
Case blocks_apart(double gap, const std::string& extra = "") {
  CaseOverrides o;
  o.sets = {fmt::format("body[0].mesh.lower=[0.0, {}]", 0.5 + gap), fmt::format("body[0].mesh.upper=[1.0, {}]", 1.0 + gap)};
  return parse_case(blocks(2, extra), "gap.toml", ".", o);
}

/// The largest deviation of any stress component from the uniform uniaxial σ_zz = σ (σ_yy in 2D).
double patch_error(const State& s, int d, double sigma) {
  double worst = 0;
  for (const SymTensor& t : s.sigma)
    for (int i = 0; i < 6; ++i) {
      const bool normal = (d == 2 && i == 1) || (d == 3 && i == 2);
      const double expected = normal ? sigma : (d == 2 && i == 2 ? 0.3 * sigma : 0.0);  // plane strain: σ_zz = ν σ_yy
      worst = std::max(worst, std::abs(t[i] - expected));
    }
  return worst / std::abs(sigma);
}

TEST(ContactPairs, PatchTestIsPassedOnNonMatchingMeshesIn2dAnd3d) {
  for (int d : {2, 3}) {
    StepReport r;
    const auto s = run_to_end(load_case(fmt::format("contact-patch-{}d", d)), &r);
    // Springs in series, 0.5 tall each: σ (0.5/E₁ + 0.5/E₂) = 0.01 with E' = E/(1 − ν²) in plane strain.
    const double soften = d == 2 ? 1 - 0.3 * 0.3 : 1.0;
    const double sigma = -0.01 / (0.5 * soften / 1000 + 0.5 * soften / 3000);
    EXPECT_LT(patch_error(s->state(), d, sigma), 1e-11) << "d = " << d;
    EXPECT_GT(s->state().lambda.size(), 0);
    EXPECT_EQ(s->contact_solver(), "active-set") << "d = " << d;  // auto: few rows on CHOLMOD
    // The pair's force (history.csv force_pair_upper.bottom) is σ times the interface's area, 1.
    ASSERT_EQ(r.pair_force.size(), 1u);
    EXPECT_NEAR(r.pair_force[0], -sigma, 1e-11 * std::abs(sigma)) << "d = " << d;
    EXPECT_NEAR(r.contact.total_force, r.pair_force[0], 1e-11 * std::abs(sigma));
    // The primal solver on the pair basis (P = H + E, solvers/contact_frame.hpp) passes it too.
    Case primal = load_case(fmt::format("contact-patch-{}d", d));
    primal.solvers.contact = "primal-active-set";
    const auto p = run_to_end(primal, &r);
    EXPECT_EQ(p->contact_solver(), "primal-active-set");
    EXPECT_LT(patch_error(p->state(), d, sigma), 1e-11) << "d = " << d << ", primal";
    EXPECT_NEAR(r.pair_force[0], -sigma, 1e-11 * std::abs(sigma)) << "d = " << d << ", primal";
  }
}

// A node on the slave side of one pair and the master side of another: the upper block's corner
// (0, 0.5) is on its bottom (the slave of the patch test's pair) and on its left side, the master
// of a second pair whose slave is a third body's right side. The primal's basis cannot write that
// node both ways: asked for, it is refused, naming the way out; the dual (auto here) solves it.
TEST(ContactPairs, ANodeOnBothSidesIsLeftToTheDual) {
  std::string text = blocks(2);
  text.replace(text.find("symmetry = [\"left\", \"bottom\", \"upper.left\"]"), 43, "symmetry = [\"left\", \"bottom\"]");
  text.replace(text.find("uy = \"-0.01*t\""), 15, "ux = \"0\"\nuy = \"-0.01*t\"");
  text += R"(
[[body]]
name = "side"
[body.mesh]
generator = "rectangle"
lower = [-0.5, 0.5]
upper = [0.0, 1.0]
cells = [3, 5]

[[boundary.displacement]]
parts = ["side.left"]
ux = "0.002*t"
uy = "0"

[[contact.pair]]
slave = "side.right"
master = "upper.left"
)";
  Case dual = parse_case(text, "three.toml", ".", {});
  StepReport r;
  const auto s = run_to_end(dual, &r);
  EXPECT_EQ(s->contact_solver(), "active-set");
  ASSERT_EQ(r.pair_force.size(), 2u);
  EXPECT_GT(r.pair_force[1], 0);  // the side presses on the upper block
  Case primal = parse_case(text, "three.toml", ".", {});
  primal.solvers.contact = "primal-active-set";
  const std::string msg = error_of([&] { TimeStepper t(primal.problem, primal.solvers); });
  EXPECT_NE(msg.find("a node is on the slave side of one contact pair row and the master side of another"),
            std::string::npos)
      << msg;
}

// A pair's own normal law (`law` in [[contact.pair]]): linear normal compliance c between the
// blocks adds the interface as a third spring in series, σ (0.5/E₁' + 0.5/E₂' + 1/c) = −0.01 with
// the pressure c × the closure; the stress stays uniform to round-off on non-matching meshes, in
// 2D and 3D, and the pair's force is σ × the area. A power law (e = 2) on the same pair: the closure
// δ solves σ = c δ², still uniform.
TEST(ContactPairs, NormalComplianceOnAPairIsAThirdSpringInSeries) {
  for (int d : {2, 3}) {
    std::string text = blocks(d);
    text.replace(text.find("master = \"top\""), 14, "master = \"top\"\nlaw = \"normal-compliance\"\nstiffness = 5000.0");
    StepReport r;
    const auto s = run_to_end(parse_case(text, "compliance.toml", ".", {}), &r);
    const double soften = d == 2 ? 1 - 0.3 * 0.3 : 1.0;
    const double sigma = -0.01 / (0.5 * soften / 1000 + 0.5 * soften / 3000 + 1.0 / 5000);
    EXPECT_LT(patch_error(s->state(), d, sigma), 1e-11) << "d = " << d;
    ASSERT_EQ(r.pair_force.size(), 1u);
    EXPECT_NEAR(r.pair_force[0], -sigma, 1e-11 * std::abs(sigma)) << "d = " << d;
  }
  std::string power = blocks(2);
  power.replace(power.find("master = \"top\""), 14,
                "master = \"top\"\nlaw = \"normal-compliance\"\nstiffness = 1e6\nexponent = 2");
  const auto s = run_to_end(parse_case(power, "power.toml", ".", {}));
  // −σ = c δ² and the blocks take 0.01 − δ: σ (0.5/E₁' + 0.5/E₂') = −(0.01 − δ).
  const double flex = 0.5 * 0.91 / 1000 + 0.5 * 0.91 / 3000;
  double delta = 0.001;
  for (int i = 0; i < 100; ++i) delta -= (1e6 * delta * delta * flex - (0.01 - delta)) / (2e6 * delta * flex + 1);
  EXPECT_LT(patch_error(s->state(), 2, -1e6 * delta * delta), 1e-10);
}

// A master part moved by a prescribed displacement (a face driven as a rigid punch): its nodes
// leave N and their motion moves the bound. The lower block's top rises by 0.005 t against the
// upper block, whose top is held: the upper block is compressed uniformly, σ = −0.005 E₂'/0.5, to
// round-off, and the pair carries −σ.
TEST(ContactPairs, AMovedMasterPartMovesTheBound) {
  std::string text = blocks(2);
  text.replace(text.find("uy = \"-0.01*t\""), 14, "uy = \"0\"\n[[boundary.displacement]]\nparts = [\"top\"]\nuy = \"0.005*t\"");
  StepReport r;
  const auto s = run_to_end(parse_case(text, "moved.toml", ".", {}), &r);
  const double sigma = -0.005 * 3000 / (0.5 * (1 - 0.3 * 0.3));
  double worst = 0;
  const Mesh& m = s->mesh();
  for (int c = 0; c < m.n_cells(); ++c)
    if (m.cell_body(c) == 1) worst = std::max(worst, std::abs(s->state().sigma[static_cast<std::size_t>(c)][1] - sigma));
  EXPECT_LT(worst, 1e-11 * std::abs(sigma));
  ASSERT_EQ(r.pair_force.size(), 1u);
  EXPECT_NEAR(r.pair_force[0], -sigma, 1e-11 * std::abs(sigma));
}

TEST(ContactPairs, AnOpenGapClosesWhereTheMotionReachesIt) {
  // The upper block starts 0.004 above: free until the top has moved 0.004 (t = 0.4), then the
  // blocks are pressed by the rest of the motion, uniformly.
  const auto s = run_to_end(blocks_apart(0.004));
  const double sigma = -0.006 / (0.5 * 0.91 / 1000 + 0.5 * 0.91 / 3000);
  EXPECT_LT(patch_error(s->state(), 2, sigma), 1e-10);
  const Case open = blocks_apart(0.004);
  auto early = std::make_unique<TimeStepper>(open.problem, open.solvers);
  early->step();  // t = 0.25: still open
  EXPECT_EQ(early->state().lambda.cwiseAbs().maxCoeff(), 0.0);
}

/// A VTU point field of the stepper's state, one number a node.
std::vector<double> point_field(const TimeStepper& s, const char* name) {
  return state_field(name).vtu_field({s.state(), s.part(), s.contact().nodes}).values;
}

// The outputs on both sides of a pair: in the patch test the pressure is −σ on the slave nodes
// (λ_j / D_jj) and on the master nodes (their reaction over their measure in contact), zero
// elsewhere, and the gap is 0 on both sides; apart, the gap is the distance left on both sides.
TEST(ContactPairs, BothSidesOfAPairCarryThePressureAndTheGap) {
  for (int d : {2, 3}) {
    const auto s = run_to_end(load_case(fmt::format("contact-patch-{}d", d)));
    const double soften = d == 2 ? 1 - 0.3 * 0.3 : 1.0;
    const double sigma = -0.01 / (0.5 * soften / 1000 + 0.5 * soften / 3000);
    const std::vector<double> p = point_field(*s, "contact_pressure"), gap = point_field(*s, "gap");
    const Mesh& m = s->mesh();
    int on_interface = 0;
    for (int i = 0; i < m.n_nodes(); ++i) {
      const bool interface = std::abs(m.node(i)[d - 1] - 0.5) < 1e-12;
      on_interface += interface;
      EXPECT_NEAR(p[static_cast<std::size_t>(i)], interface ? -sigma : 0.0, 1e-11 * std::abs(sigma))
          << "d = " << d << ", node " << i;
      EXPECT_NEAR(gap[static_cast<std::size_t>(i)], 0.0, 1e-14) << "d = " << d << ", node " << i;
    }
    EXPECT_GE(on_interface, 2 * (d == 2 ? 3 : 9));  // both sides' nodes
  }
  const Case open = blocks_apart(0.004);
  TimeStepper early(open.problem, open.solvers);
  const Mesh& m = early.mesh();
  for (int n = 0; n < 2; ++n) {  // t = 0 and t = 0.25: the top moved down by 0.0025, all of it rigidly
    const std::vector<double> gap = point_field(early, "gap");
    for (int i = 0; i < m.n_nodes(); ++i) {
      const double y = m.node(i)[1];
      const bool interface = std::abs(y - 0.5) < 1e-12 || std::abs(y - 0.504) < 1e-12;
      EXPECT_NEAR(gap[static_cast<std::size_t>(i)], interface ? 0.004 - 0.01 * early.state().t : 0.0, 1e-14)
          << "t = " << early.state().t << ", node " << i;
    }
    early.step();
  }
  // Without pairs the gap is not recorded, and asking for it says so.
  const auto one = run_to_end(load_case("paper-1d"));
  EXPECT_EQ(one->state().gap.size(), 0);
  EXPECT_NE(error_of([&] { point_field(*one, "gap"); }).find("only for cases with contact pairs"), std::string::npos);
  CaseOverrides ask;
  ask.sets = {"output.fields=[\"gap\", \"beta\"]"};
  const std::string asked = error_of([&] { parse_case(case_source("paper-1d").text, "p.toml", ".", ask); });
  EXPECT_NE(asked.find("output.fields=[\"gap\", \"beta\"]: the field \"gap\" is written only for cases with contact pairs"),
            std::string::npos)
      << asked;
}

/// The paper's damageable viscoplastic material on the block [0, 2] × [0, 1] (clamped bottom),
/// pressed by an elastic punch [0.8, 1.2] × [1, 1.3] (body "punch", its own mesh; its top moved
/// down) through a pair: the punch's bottom the slave, the block's top the master.
const char* const kPunch = R"toml(
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [20, 10]
[[body]]
name = "punch"
[body.mesh]
generator = "rectangle"
lower = [0.8, 1.0]
upper = [1.2, 1.3]
cells = [7, 5]
[body.elasticity]
E = 20000.0
[body.viscoplasticity]
law = "elastic"
[body.damage]
source = "zero"
[boundary]
clamped = ["bottom"]
[[boundary.displacement]]
parts = ["punch.top"]
ux = "0"
uy = "-0.01*t"
[elasticity]
kind = "plane-stress"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "maxwell-damage"
[damage]
kappa = 0.1
source = "von-mises"
c = 0.05
[contact]
gap = 0.0
[[contact.pair]]
slave = "punch.bottom"
master = "top"
[time]
T = 1.0
steps = 6
)toml";

// The whole scheme on two bodies: damage grows in the block under the punch and not in the
// elastic punch, each step's residuals hold (TimeStepper's checks), and the forces balance
// across the pair: the block's support and the punch's top carry the pair's force.
TEST(ContactPairs, APunchDamagesTheBlockAndTheForcesBalance) {
  const Case c = parse_case(kPunch, "punch.toml", ".", {});
  TimeStepper s(c.problem, c.solvers);
  StepReport r;
  while (!s.done()) {
    r = s.step();
    ASSERT_TRUE(r.ok) << "step " << r.n;
  }
  ASSERT_EQ(r.pair_force.size(), 1u);
  const double P = r.pair_force[0];
  EXPECT_GT(P, 0.0);
  ASSERT_EQ(r.reaction.size(), 4u);  // bottom x, y; punch.top x, y
  EXPECT_NEAR(r.reaction[1], P, 1e-8 * P);   // the support pushes the block up by P
  EXPECT_NEAR(r.reaction[3], -P, 1e-8 * P);  // and the punch's top holds it down by P
  const Mesh& m = s.mesh();
  double beta_block = 1, beta_punch = 1;
  for (int c = 0; c < m.n_cells(); ++c)
    for (int a = 0; a < 3; ++a) {
      double& b = m.cell_body(c) == 0 ? beta_block : beta_punch;
      b = std::min(b, s.state().beta[m.cell(c)[a]]);
    }
  EXPECT_LT(beta_block, 0.99);
  EXPECT_NEAR(beta_punch, 1.0, 1e-12);  // its φ is zero: β stays β0 (to the damage solve's round-off)
}

// A checkpoint of a run with a pair restores it bit for bit: the mortar rows are rebuilt from
// the reference configuration, λ and the rest come from the snapshot.
TEST(ContactPairs, RestoredRunIsBitIdentical) {
  const Case ca = parse_case(kPunch, "punch.toml", ".", {}), cb = parse_case(kPunch, "punch.toml", ".", {});
  TimeStepper a(ca.problem, ca.solvers), b(cb.problem, cb.solvers);
  for (int i = 0; i < 3; ++i) a.step();
  b.restore(read_checkpoint(write_checkpoint(test::fresh_dir("pairs", "restore"), test::checkpoint_of(a))).snapshot);
  EXPECT_EQ(b.state().gap, a.state().gap);  // not in the checkpoint: recomputed from u
  EXPECT_GT(a.state().gap.size(), 0);
  while (!a.done()) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.state().u, b.state().u);
  EXPECT_EQ(a.state().beta, b.state().beta);
  EXPECT_EQ(a.state().lambda, b.state().lambda);
  EXPECT_GT(a.state().lambda.cwiseAbs().maxCoeff(), 0.0);
}

TEST(ContactPairs, BadPairsAreRefusedNamingTheKey) {
  auto error = [](const std::string& text) { return error_of([&] { parse_case(text, "c.toml", ".", {}); }); };
  std::string one_body = blocks(2);
  one_body.replace(one_body.find("master = \"top\""), 14, "master = \"upper.top\"");
  EXPECT_NE(error(one_body).find("are parts of one body"), std::string::npos) << error(one_body);
  std::string missing = blocks(2);
  missing.replace(missing.find("master = \"top\""), 14, "master = \"tpo\"");
  EXPECT_NE(error(missing).find("part 'tpo' does not exist"), std::string::npos) << error(missing);
  std::string both = blocks(2);
  both.replace(both.find("[[boundary.displacement]]"), 25, "contact = [\"top\"]\n[[boundary.displacement]]");
  EXPECT_NE(error(both).find("is on Γ3"), std::string::npos) << error(both);
  const std::string far = error_of([] { blocks_apart(0.3); });
  EXPECT_NE(far.find("covers no node"), std::string::npos) << far;
  // Overlapping at t = 0 by 0.01 (a fifth of a cell): refused, as a body inside an obstacle is.
  const std::string overlap = error_of([] { blocks_apart(-0.01); });
  EXPECT_NE(overlap.find("lies 0.01 inside the master part 'top' at t = 0"), std::string::npos) << overlap;
  // A slave side with every node clamped would constrain nothing: refused, not left out.
  std::string clamped = blocks(2);
  clamped.replace(clamped.find("[boundary]\n"), 11, "[boundary]\nclamped = [\"upper.bottom\"]\n");
  EXPECT_NE(error(clamped).find("every node of slave part 'upper.bottom' that the master part 'top' "
                                "covers has every component prescribed"), std::string::npos) << error(clamped);
  std::string no_law = blocks(2);
  no_law.replace(no_law.find("master = \"top\""), 14, "master = \"top\"\nstiffness = 5000.0");
  EXPECT_NE(error(no_law).find("stiffness needs law = \"normal-compliance\" in the same table"), std::string::npos)
      << error(no_law);
  std::string negative = blocks(2);
  negative.replace(negative.find("master = \"top\""), 14, "master = \"top\"\nsearch = -1");
  EXPECT_NE(error(negative).find("expected a distance >= 0"), std::string::npos) << error(negative);
}

/// Issue 48 (slave-moved-tangentially): two blocks, the upper pressed down by its top, its bottom
/// (the slave) also moved by `[[boundary.displacement]]` `slave_motion`; `extra` ends the file.
std::string slave_moved(const std::string& slave_motion, const std::string& extra = "") {
  return R"toml(
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 0.5]
cells = [10, 3]
[[body]]
name = "upper"
[body.mesh]
generator = "rectangle"
lower = [0.5, 0.5]
upper = [1.5, 1.0]
cells = [7, 4]
[body.elasticity]
E = 3000.0
[boundary]
clamped = ["bottom"]
[[boundary.displacement]]
parts = ["upper.top"]
ux = "0.02*max(t - 1, 0)"
uy = "-0.005*min(t, 1)"
[[boundary.displacement]]
parts = ["upper.bottom"]
)toml" + slave_motion + R"toml(
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[time]
T = 2.0
steps = 4
[[contact.pair]]
slave = "upper.bottom"
master = "top"
)toml" + extra;
}

// A slave face slid along itself leaves the rows ν_j·u_j − Σ w ν·u_k ≤ g as they are (ν_j has no x):
// right in a frictionless small-sliding pair, where the forces balance; refused along the normal, under
// friction (the slip would not see the motion) and under large sliding, naming the displacement.
TEST(ContactPairs, ASlaveMovedAcrossItsNormalIsRightOnlyWithoutFrictionAndLargeSliding) {
  StepReport r;
  run_to_end(parse_case(slave_moved("ux = \"0.01*t\""), "c.toml", ".", {}), &r);
  ASSERT_EQ(r.pair_force.size(), 1u);
  EXPECT_GT(r.pair_force[0], 1.0);
  // reaction: bottom (x, y), upper.top (x, y), upper.bottom (x): the pair's force is what both supports carry.
  ASSERT_EQ(r.reaction.size(), 5u);
  EXPECT_NEAR(r.pair_force[0], r.reaction[1], 1e-10 * r.pair_force[0]);
  EXPECT_NEAR(r.pair_force[0], -r.reaction[3], 1e-10 * r.pair_force[0]);
  auto error = [](const std::string& text) { return error_of([&] { parse_case(text, "c.toml", ".", {}); }); };
  std::string m = error(slave_moved("uy = \"-0.001*t\""));
  EXPECT_NE(m.find("c.toml:22:1: boundary.displacement[1]: uy of slave node"), std::string::npos) << m;
  EXPECT_NE(m.find("its normal (0, -1, 0) has a component along it"), std::string::npos) << m;
  m = error(slave_moved("ux = \"0.01*t\"", "friction = \"coulomb\"\nmu = 0.3\n"));
  EXPECT_NE(m.find("boundary.displacement[1]: ux of slave node"), std::string::npos) << m;
  EXPECT_NE(m.find("the pair has friction"), std::string::npos) << m;
  m = error(slave_moved("ux = \"0.01*t\"", "sliding = \"large\"\n"));
  EXPECT_NE(m.find("the pair slides large"), std::string::npos) << m;
  EXPECT_NE(m.find("contact.pair[0]: make the moved part the master"), std::string::npos) << m;
}

}  // namespace
}  // namespace vpc
