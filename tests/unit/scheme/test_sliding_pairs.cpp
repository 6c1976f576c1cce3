// Issue 29: large sliding between bodies (`[[contact.pair]] sliding = "large"`,
// scheme/pair_slider.hpp): the pair's rows rebuilt at every step in the configuration the step
// starts from. An elastic half-disc (R = 1) pressed into a block by 0.02 and then slid along it by
// 0.2 (24 of the block's elements near the contact): the contact goes with the disc, as it would
// with the block translated, where rows fixed in the reference configuration lose it.
#include "../io/test_files.hpp"
#include "cases/builtin_cases.hpp"
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "io/state_fields.hpp"
#include "part/part_cut.hpp"
#include "problem/contact_pairs.hpp"
#include "run/run_case.hpp"
#include "scheme/sliding_pairs.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <map>
#include <numeric>
#include <string>

#include "../error_of.hpp"
#include "../run_to_end.hpp"

namespace vpc {
namespace {

/// hertz-cylinders-2d's bodies (its meshes, found from its directory) at size_factor 2 (h = 0.0084 near the contact), the disc's arc the
/// slave (it stays on the block), its flat side moved up by 0.02 until t = 1, then along x by 0.2.
std::string slide(const std::string& sliding, const std::string& extra = "") {
  return fmt::format(R"toml(
[mesh]
file = "meshes/hertz-2d-graded.geo"
size_factor = 2

[[body]]
name = "disc"
[body.mesh]
file = "meshes/half-disc.geo"
size_factor = 2

[boundary]
clamped = ["top"]

[[boundary.displacement]]
parts = ["disc.flat"]
ux = "0.2*max(t - 1, 0)"
uy = "0.02*min(t, 1)"

[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3

[viscoplasticity]
law = "elastic"

[damage]
source = "zero"

[[contact.pair]]
slave = "disc.arc"
master = "bottom"
search = 0.05
sliding = "{0}"
{1}
[time]
T = 2.0
breakpoints = [1.0]
dt = [0.5, 0.1]
)toml",
                     sliding, extra);
}

Case slide_case(const std::string& sliding, const std::string& solver, const std::string& extra = "") {
  Case c = parse_case(slide(sliding, extra), "slide.toml", case_source("hertz-cylinders-2d").base_dir, {});
  c.solvers.contact = solver;
  return c;
}

/// The centre of the contact zone in the current configuration: the pressure-weighted mean of x + u_x
/// over the block's bottom (the master side's contact_pressure).
double contact_centre(const TimeStepper& s) {
  const std::vector<double> p = state_field("contact_pressure").vtu_field({s.state(), s.part(), s.contact().nodes}).values;
  const Mesh& m = s.mesh();
  std::vector<char> slave(static_cast<std::size_t>(m.n_nodes()), 0);  // the disc's arc: its top node is at y = 0 too
  for (const PartContactNode& node : s.contact().nodes) slave[static_cast<std::size_t>(node.local_node)] = 1;
  double sum = 0, moment = 0;
  for (int n = 0; n < m.n_nodes(); ++n)
    if (std::abs(m.node(n)[1]) < 1e-12 && !slave[static_cast<std::size_t>(n)] && p[static_cast<std::size_t>(n)] > 0) {
      sum += p[static_cast<std::size_t>(n)];
      moment += p[static_cast<std::size_t>(n)] * (m.node(n)[0] + s.state().u[2 * n]);
    }
  return moment / sum;
}

TEST(SlidingPairs, TheContactGoesWithTheSlidingDisc) {
  double lag[2] = {0, 0}, force[2] = {0, 0};
  for (int k = 0; k < 3; ++k) {  // the dual with steps sliding 0.02 and 0.01, the primal with 0.02
    const char* solver = k == 2 ? "primal-active-set" : "active-set";
    std::string text = slide("large");
    if (k == 1) text.replace(text.find("dt = [0.5, 0.1]"), 15, "dt = [0.5, 0.05]");
    Case c = parse_case(text, "slide.toml", case_source("hertz-cylinders-2d").base_dir, {});
    c.solvers.contact = solver;
    TimeStepper s(c.problem, c.solvers);
    double pressed = 0, lo = INFINITY, hi = 0;
    while (!s.done()) {
      const StepReport r = s.step();
      ASSERT_TRUE(r.ok) << solver << ", t = " << r.t;
      if (r.t > 1.15) lo = std::min(lo, r.pair_force[0]), hi = std::max(hi, r.pair_force[0]);
      if (r.t <= 1 + 1e-12) pressed = r.pair_force[0];
    }
    const double centre = contact_centre(s);
    std::printf("  %s, steps sliding %.2f: P pressed %.6g, sliding %.6g to %.6g (%.2f %%), contact centre %.5f "
                "(the disc moved 0.2)\n", solver, k == 1 ? 0.01 : 0.02, pressed, lo, hi, 100 * (hi / lo - 1), centre);
    // Frictionless sliding on a block wide and deep against the contact: the normal force stays
    // what the first slid step made it, above the pressed one by the lag's error below (+1.0 %
    // with steps sliding 0.02, +0.2 % with 0.01: the disc pushes into the bowl's rising side).
    EXPECT_LT(hi / lo - 1, 2e-3) << solver;
    EXPECT_NEAR(lo / pressed, 1.0, 0.02) << solver;
    // The contact follows the disc a step late at most: each step's rows are those of its start,
    // so the zone lags by a share of the step's slide, halved with the step (first order).
    EXPECT_GT(centre, 0.2 - 0.5 * (k == 1 ? 0.01 : 0.02)) << solver;
    EXPECT_LT(centre, 0.2) << solver;
    if (k < 2) lag[k] = 0.2 - centre, force[k] = hi;
    if (k == 2) {
      EXPECT_NEAR(hi, force[0], 1e-8 * hi);  // the primal is the dual
    }
  }
  EXPECT_NEAR(lag[0] / lag[1], 2.0, 0.2);
  // Rows kept in the reference configuration do not follow the disc: its arc's nodes keep their
  // first masters, and the force more than doubles over the same slide.
  StepReport r;
  run_to_end(slide_case("small", "active-set"), &r);
  EXPECT_GT(r.pair_force[0], 2.0 * 4.7);
}

// The slider keeps only the two surfaces and the cells behind them (scheme/pair_slider.hpp), not the
// whole mesh: a step's rows, built from them, are bit for bit those of the pair's rows on the whole
// mesh moved by the displacement the step started from (masters, weights, normals, measures, gaps).
TEST(SlidingPairs, TheSlidersSurfacesGiveTheWholeMovedMeshsRows) {
  Case c = slide_case("large", "active-set");
  TimeStepper s(c.problem, c.solvers);
  const int d = 2;
  int compared = 0;
  while (!s.done()) {
    const Vector u = s.state().u;  // the configuration the next step starts from
    ASSERT_TRUE(s.step().ok);
    Problem moved = *c.problem;
    for (int i = 0; i < moved.mesh.n_nodes(); ++i)
      for (int j = 0; j < d; ++j) moved.mesh.nodes()[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] += u[i * d + j];
    const std::vector<ContactRow> rows = pair_rows(moved, dirichlet_dofs(*c.problem).condition);
    std::map<int, const ContactRow*> row_of;
    for (const ContactRow& r : rows) row_of[r.node] = &r;
    for (const PartContactNode& node : s.contact().nodes) {
      const int o = s.part().original_node[static_cast<std::size_t>(node.local_node)];
      const auto it = row_of.find(o);
      if (it == row_of.end()) {  // no master within reach: no masters this step
        EXPECT_TRUE(node.masters.empty()) << "t = " << s.state().t << ", node " << o;
        continue;
      }
      const ContactRow& r = *it->second;
      EXPECT_EQ(node.direction, r.direction);
      EXPECT_EQ(node.measure, r.measure);
      ASSERT_EQ(node.masters.size(), r.masters.size());
      double bound = r.gap;  // the bound of N u_n (PairSlider::slide)
      for (int i = 0; i < d; ++i) bound += r.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
      for (std::size_t k = 0; k < r.masters.size(); ++k) {
        const auto [l, w] = node.masters[k];
        EXPECT_EQ(s.part().original_node[static_cast<std::size_t>(l)], r.masters[k].first);
        EXPECT_EQ(w, r.masters[k].second);
        for (int i = 0; i < d; ++i) bound -= w * r.direction[static_cast<std::size_t>(i)] * u[l * d + i];
      }
      EXPECT_EQ(node.gap, bound);
      ++compared;
    }
  }
  std::printf("  %d sliding rows compared with the whole moved mesh's\n", compared);
  EXPECT_GT(compared, 100);
}

// Under MPI each rank moves the rows of its own slave nodes from its piece of the surfaces
// (MeshPart::sliding: the slave facets at those nodes, the whole master side): cut here for a part
// that owns the nodes left of the disc's middle, the piece's rows at a slid configuration are bit
// for bit the whole surfaces' rows at those nodes, with the search distance of the whole slave side.
TEST(SlidingPairs, APartsPieceGivesItsOwnSlaveNodesRowsBitForBit) {
  Case c = slide_case("large", "active-set");
  TimeStepper s(c.problem, c.solvers);
  while (s.state().t < 1.45) ASSERT_TRUE(s.step().ok);  // pressed, then slid by 0.09
  const Problem& p = *c.problem;
  const Mesh& mesh = p.mesh;
  const int d = 2;
  const Vector& u = s.state().u;
  const WholeMeshData whole(p);
  ASSERT_EQ(whole.sliding.size(), 1u);
  std::vector<double> xs;  // the slave side's nodes' x, for its median
  for (int v : whole.sliding[0].slave.ids) xs.push_back(mesh.node(v)[0]);
  std::nth_element(xs.begin(), xs.begin() + static_cast<std::ptrdiff_t>(xs.size() / 2), xs.end());
  const double middle = xs[xs.size() / 2];
  std::vector<int> cells(static_cast<std::size_t>(mesh.n_cells()));
  std::iota(cells.begin(), cells.end(), 0);
  // A part over every node (owned: left of the middle and the master side's, whose nodes the set-up's
  // rows need, then the others) and the whole one.
  std::vector<char> master(static_cast<std::size_t>(mesh.n_nodes()), 0);
  for (int v : whole.sliding[0].master.ids) master[static_cast<std::size_t>(v)] = 1;
  std::vector<int> left, right;
  for (int v = 0; v < mesh.n_nodes(); ++v)
    (mesh.node(v)[0] < middle || master[static_cast<std::size_t>(v)] ? left : right).push_back(v);
  std::vector<int> nodes = left, all(static_cast<std::size_t>(mesh.n_nodes()));
  nodes.insert(nodes.end(), right.begin(), right.end());
  std::iota(all.begin(), all.end(), 0);
  const PartPieces part = cut_part(p, whole, WholeNumbering({left, right}, whole.dirichlet, d), nodes,
                                   static_cast<int>(left.size()), cells);
  const PartPieces one = cut_part(p, whole, WholeNumbering({all}, whole.dirichlet, d), all, mesh.n_nodes(), cells);
  ASSERT_EQ(part.sliding.size(), 1u);
  ASSERT_LT(part.sliding[0].slave.facets.size(), one.sliding[0].slave.facets.size());  // a piece, not the side
  EXPECT_EQ(part.sliding[0].master.facets.size(), one.sliding[0].master.facets.size());
  // Each part's rows at x + u, its nodes numbered as the part's (`nodes`: the part's -> the mesh's).
  auto rows_of = [&](const PartPieces& q, const std::vector<int>& original, double search) {
    const auto x = [&](int l) {
      const int v = original[static_cast<std::size_t>(l)];
      Point y = mesh.node(v);
      for (int i = 0; i < d; ++i) y[static_cast<std::size_t>(i)] += u[v * d + i];
      return y;
    };
    const SlidingPairPiece& piece = q.sliding[0];
    const mortar::Surface slave = sliding_surface(d, 3, piece.slave, x), master = sliding_surface(d, 3, piece.master, x);
    const FixedAt fixed_at = [&](int l) { return q.dirichlet.data() + static_cast<std::size_t>(l) * d; };
    std::vector<ContactRow> rows;
    add_pair_rows(p, 0, slave, master, fixed_at, nullptr, search > 0 ? search : slave.longest_edge(), rows);
    std::map<int, ContactRow> by_node;  // by the mesh's node, masters too
    for (ContactRow& r : rows) {
      for (auto& [k, w] : r.masters) k = original[static_cast<std::size_t>(k)];
      by_node[original[static_cast<std::size_t>(r.node)]] = std::move(r);
    }
    return by_node;
  };
  // The piece's own longest edge is not the side's: the rows need the side's (PairSlider's comm.max).
  const double search = search_margin(p.contact.pairs[0], 0.0);
  const std::map<int, ContactRow> whole_rows = rows_of(one, all, search), piece_rows = rows_of(part, nodes, search);
  int compared = 0;
  for (std::size_t l = 0; l < left.size(); ++l) {
    const auto w = whole_rows.find(left[l]);
    const auto r = piece_rows.find(left[l]);
    ASSERT_EQ(w == whole_rows.end(), r == piece_rows.end()) << "node " << left[l];
    if (w == whole_rows.end()) continue;
    EXPECT_EQ(r->second.direction, w->second.direction);
    EXPECT_EQ(r->second.measure, w->second.measure);
    EXPECT_EQ(r->second.gap, w->second.gap);
    EXPECT_EQ(r->second.masters, w->second.masters);
    ++compared;
  }
  std::printf("  %d rows of a part's own slave nodes compared with the whole side's\n", compared);
  EXPECT_GT(compared, 20);
}

// Coulomb across the sliding pair (μ = 0.3): the disc dragged in full slip, Σ|λ_τ| = μ Σλ_ν, the
// two solvers alike; a checkpoint in mid-slide continues bit for bit (the rows come from its u).
TEST(SlidingPairs, FrictionFollowsTheSlidingRows) {
  const std::string coulomb = "friction = \"coulomb\"\nmu = 0.3\n";
  Vector u[2];
  for (int k = 0; k < 2; ++k) {
    StepReport r;
    const auto s = run_to_end(slide_case("large", k ? "primal-active-set" : "active-set", coulomb), &r);
    const State& st = s->state();
    double normal = 0, tangential = 0;
    for (Eigen::Index i = 0; i < st.lambda.size() / 2; ++i) normal += st.lambda[2 * i], tangential += std::abs(st.lambda[2 * i + 1]);
    EXPECT_EQ(r.contact.n_stick, 0);
    EXPECT_NEAR(tangential, 0.3 * normal, 1e-9 * normal);
    EXPECT_GT(r.pair_tangential_force[0], 0.29 * r.pair_force[0]);  // the block dragged along +x
    u[k] = st.u;
  }
  EXPECT_LT((u[0] - u[1]).cwiseAbs().maxCoeff(), 1e-8 * u[0].cwiseAbs().maxCoeff());
  const Case ca = slide_case("large", "active-set", coulomb), cb = slide_case("large", "active-set", coulomb);
  TimeStepper a(ca.problem, ca.solvers), b(cb.problem, cb.solvers);
  for (int i = 0; i < 6; ++i) a.step();
  b.restore(read_checkpoint(write_checkpoint(test::fresh_dir("sliding_pairs", "restore"), test::checkpoint_of(a))).snapshot);
  while (!a.done()) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.state().u, b.state().u);
  EXPECT_EQ(a.state().lambda, b.state().lambda);
}

// A punch slid half off the block's edge: the slave nodes past it lose their masters (no facet within
// reach) and carry no force; the rest holds the punch, whose top's reaction balances them.
TEST(SlidingPairs, ASlaveNodeSlidOffItsMasterCarriesNoForce) {
  const std::string text = R"toml(
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [1.0, 0.5]
cells = [10, 5]
[[body]]
name = "punch"
[body.mesh]
generator = "rectangle"
lower = [0.7, 0.5]
upper = [0.9, 0.6]
cells = [8, 2]
[body.elasticity]
E = 5000.0
[boundary]
clamped = ["bottom"]
[[boundary.displacement]]
parts = ["punch.top"]
ux = "0.2*max(t - 1, 0)"
uy = "-0.002*min(t, 1)"
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[[contact.pair]]
slave = "punch.bottom"
master = "top"
sliding = "large"
[time]
T = 2.0
breakpoints = [1.0]
dt = [0.5, 0.05]
)toml";
  for (const char* solver : {"active-set", "primal-active-set"}) {
    Case c = parse_case(text, "off.toml", ".", {});
    c.solvers.contact = solver;
    StepReport r;
    const auto s = run_to_end(c, &r);
    int off = 0, on = 0;
    double vertical = 0;  // Σ λ_ν ν_y: the normals are the moved configuration's (the corner tilts them)
    for (const PartContactNode& node : s->contact().nodes) {
      vertical += s->state().lambda[node.row] * node.direction[1];
      const double x = s->mesh().node(node.local_node)[0] + s->state().u[2 * node.local_node];
      if (x > 1.0 + 1e-3) {
        EXPECT_EQ(s->state().lambda[node.row], 0.0) << solver << ", x = " << x;
        ++off;
      } else if (s->state().lambda[node.row] > 0) {
        ++on;
      }
    }
    EXPECT_GE(off, 3) << solver;  // the punch spans [0.9, 1.1]: its right half is off the block
    EXPECT_GE(on, 3) << solver;
    EXPECT_NEAR(vertical, r.reaction[3], 1e-8 * r.pair_force[0]) << solver;  // bottom (2), punch top (2)
  }
}

/// Issue 48 (large-slide-off-stops, small-sliding-no-warning): a block [0.5, 1.5] × [0.5, 1] pressed
/// by 0.005 into a block [0, 2] × [0, 0.5] until t = 1, then its top moved along x by `ux`; `friction`
/// ends the pair's table.
std::string blocks_slid(const std::string& sliding, const std::string& ux, double T, int steps,
                        const std::string& friction = "") {
  return fmt::format(R"toml(
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
ux = "{1}"
uy = "-0.005*min(t, 1)"
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[[contact.pair]]
slave = "upper.bottom"
master = "top"
sliding = "{0}"
{4}
[time]
T = {2}
steps = {3}
)toml",
                     sliding, ux, T, steps, friction);
}

// A slave slid right off its master (by 3 along a block 2 wide) runs on with the pair's force 0, its
// nodes inactive; slid back, it is pressed again as it was at t = 1 (the run stopped at the first
// step where no slave node had a master).
TEST(SlidingPairs, ASlaveSlidRightOffRunsOnAndComesBack) {
  Case c = parse_case(blocks_slid("large", "3.0*max(min(t - 1, 3 - t), 0)", 3.0, 30, "friction = \"coulomb\"\nmu = 0.3"), "off.toml", ".", {});
  TimeStepper s(c.problem, c.solvers);
  double pressed = 0, back = 0;
  int off = 0, touching = 0, touching_back = 0;
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok) << "t = " << r.t;
    if (std::abs(r.t - 1) < 1e-9) pressed = r.pair_force[0], touching = r.contact.n_active;
    if (r.t > 1.75 && r.t < 2.25) {  // t = 1.8 to 2.2: the upper block past x = 2.9 at its start, off
      EXPECT_EQ(r.pair_force[0], 0.0) << "t = " << r.t;
      EXPECT_EQ(r.contact.n_active, 0) << "t = " << r.t;
      EXPECT_EQ(r.pair_tangential_force[0], 0.0) << "t = " << r.t;
      ++off;
    }
    back = r.pair_force[0], touching_back = r.contact.n_active;
  }
  EXPECT_EQ(off, 5);
  EXPECT_GT(pressed, 1.0);
  // Back where it was pressed, every slave node touching again; the force within friction's history
  // (dragged back against μ = 0.3: 12.26 against 11.28).
  EXPECT_EQ(touching_back, touching);
  EXPECT_NEAR(back, pressed, 0.15 * pressed);
}

// sliding = "small" slid 0.5 (2.5 master facets of 0.2) gives a normal force 9.5 % off the large
// sliding one: small_slides measures the slide from the t = 0 masters (RunOutput warns past 0.5 of
// a master facet, and summary.json says it); slid 0.02, it stays below.
TEST(SlidingPairs, SmallSlidingMeasuresTheSlideFromItsMasters) {
  for (const auto& [ux, slid] : {std::pair{"0.5*max(t - 1, 0)", 0.5}, {"0.02*max(t - 1, 0)", 0.02}}) {
    Case c = parse_case(blocks_slid("small", ux, 2.0, 20), "small.toml", ".", {});
    const auto s = run_to_end(c);
    const std::vector<PairSlide> slides = small_slides(*c.problem, s->part(), s->contact().nodes, s->state());
    ASSERT_EQ(slides.size(), 1u);
    EXPECT_NEAR(slides[0].facet, 0.2, 1e-15);
    // The slave slides with the body's top (frictionless: no shear holds it back), the master's mean
    // barely moving.
    EXPECT_NEAR(slides[0].slide, slid, 0.002) << ux;
    EXPECT_EQ(slides[0].ratio > kSmallSlideLimit, slid > 0.1) << ux;
    EXPECT_GE(slides[0].node, 0);
    EXPECT_EQ(slides[0].x[1], 0.5);
    c = parse_case(blocks_slid("large", ux, 2.0, 20), "large.toml", ".", {});
    const auto large = run_to_end(c);
    EXPECT_TRUE(small_slides(*c.problem, large->part(), large->contact().nodes, large->state()).empty());  // rows follow the motion
  }
}

// The run says it: one warning at the pair's table naming sliding = "large", and summary.json.
TEST(SlidingPairs, ARunWarnsOnceWhenSmallSlidingSlidesPastTheLimit) {
  for (const auto& [ux, warns] : {std::pair{"0.5*max(t - 1, 0)", true}, {"0.02*max(t - 1, 0)", false}}) {
    RunOptions o;
    o.quiet = true;
    o.output_directory = test::fresh_dir("sliding_pairs", warns ? "warns" : "quiet");
    const CaseLoader load = [&](const MeshRequest&) {
      Case c = parse_case(blocks_slid("small", ux, 2.0, 20), "small.toml", ".", {});
      c.output.directory = o.output_directory;
      return c;
    };
    testing::internal::CaptureStderr();
    run_case(load, o);
    const std::string err = testing::internal::GetCapturedStderr();
    const std::string warning = "vpcontact: warning: small.toml:30:1: contact.pair[0]: at step ";
    EXPECT_EQ(err.find(warning) != std::string::npos, warns) << err;
    EXPECT_EQ(err.find(warning), err.rfind(warning)) << err;  // once
    if (warns) {
      EXPECT_NE(err.find("set sliding = \"large\" in this [[contact.pair]]"), std::string::npos) << err;
    }
    const auto summary = nlohmann::json::parse(std::ifstream(o.output_directory / "summary.json"));
    ASSERT_TRUE(summary.contains("small_sliding")) << summary.dump();
    const auto& pair = summary["small_sliding"][0];
    EXPECT_EQ(pair["slave"], "upper.bottom");
    EXPECT_NEAR(pair["master_facet"].get<double>(), 0.2, 1e-15);
    EXPECT_EQ(pair["limit"], kSmallSlideLimit);
    EXPECT_EQ(pair["past_limit"], warns);
    const double ratio = pair["slide"].get<double>() / pair["master_facet"].get<double>();
    EXPECT_NEAR(pair["slide_per_facet"].get<double>(), ratio, 1e-14 * ratio);
  }
}

TEST(SlidingPairs, TheKeyIsChecked) {
  const std::string bad = error_of([] { parse_case(slide("big"), "slide.toml", case_source("hertz-cylinders-2d").base_dir, {}); });
  EXPECT_NE(bad.find("unknown value 'big'; expected one of: small, large"), std::string::npos) << bad;
}

}  // namespace
}  // namespace vpc
