// Issue 29: friction across contact pairs (SPEC §7 on §8). The slip of a slave node is relative to
// its masters' mortar mean, Δ_j = t_j·(Δu_j − Σ_k w_jk Δu_k) (ContactConstraints::master_mean), on
// both contact solvers: the dual takes T's master entries as they are, the primal moves the whole
// slave node with its masters (contact_basis), so that a stick row fixes its tangential dofs.
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "io/state_fields.hpp"
#include "scheme/time_stepper.hpp"
#include "../io/test_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <string>

#include "../error_of.hpp"
#include "../run_to_end.hpp"

namespace vpc {
namespace {

/// A block (E = 3000) pressed onto a wider one (E = 1000, clamped below) by its top, down by 0.005
/// until t = 1, then its top moved along x by 0.02 (2D) or along (2, 1)·0.01 (3D) until t = 2;
/// Coulomb across the pair with μ = `mu`. Meshes do not match across the interface.
std::string shear(int d, double mu) {
  const bool three = d == 3;
  return fmt::format(R"toml(
[mesh]
generator = "{0}"
lower = {1}
upper = {2}
cells = {3}

[[body]]
name = "upper"
[body.mesh]
generator = "{0}"
lower = {4}
upper = {5}
cells = {6}
diagonal = "{7}"
[body.elasticity]
E = 3000.0

[boundary]
clamped = ["bottom"]

[[boundary.displacement]]
parts = ["upper.top"]
ux = "0.02*max(t - 1, 0)"
{8}

[elasticity]
kind = "{9}"
E = 1000.0
nu = 0.3

[viscoplasticity]
law = "elastic"

[damage]
source = "zero"

[[contact.pair]]
slave = "upper.bottom"
master = "top"
friction = "coulomb"
mu = {10}

[time]
T = 2.0
steps = 20
)toml",
                     three ? "box" : "rectangle", three ? "[-1.2, -1.2, -0.5]" : "[-1.5, -0.5]",
                     three ? "[1.2, 1.2, 0.0]" : "[1.5, 0.0]", three ? "[6, 6, 2]" : "[15, 3]",
                     three ? "[-1.0, -1.0, 0.0]" : "[-1.0, 0.0]", three ? "[1.0, 1.0, 0.5]" : "[1.0, 0.5]",
                     three ? "[5, 5, 2]" : "[14, 4]", three ? "alternate" : "left",
                     three ? "uy = \"0.01*max(t - 1, 0)\"\nuz = \"-0.005*min(t, 1)\"" : "uy = \"-0.005*min(t, 1)\"",
                     three ? "isotropic" : "plane-strain", mu);
}

Case shear_case(int d, double mu, const std::string& solver) {
  Case c = parse_case(shear(d, mu), "shear.toml", ".", {});
  c.solvers.contact = solver;
  return c;
}

/// Σ_j λ_ν,j and Σ_j |λ_τ,j| over the contact rows.
std::pair<double, double> force_sums(const State& s) {
  const int b = s.contact_block;
  double normal = 0, tangential = 0;
  for (Eigen::Index i = 0; i < s.lambda.size() / b; ++i) {
    normal += s.lambda[i * b];
    tangential += s.lambda.segment(i * b + 1, b - 1).norm();
  }
  return {normal, tangential};
}

/// A VTU point field of the stepper's state.
std::vector<double> point_field(const TimeStepper& s, const char* name) {
  return state_field(name).vtu_field({s.state(), s.part(), s.contact().nodes}).values;
}

// Once the whole face slides, every slave row is at its bound: Σ|λ_τ| = μ Σ λ_ν to the solver's
// tolerance, on both solvers, which agree; the bodies balance: the moved top's reaction is the
// pair's tangential force on the master, the master nodes' tangential_force field sums to it and
// the slave nodes' to its opposite (each node's is the force on its own body).
TEST(PairFriction, FullSlipCarriesMuTimesTheNormalForce) {
  for (int d : {2, 3}) {
    Vector u[2];
    for (int k = 0; k < 2; ++k) {
      const std::string solver = k == 0 ? "active-set" : "primal-active-set";
      StepReport r;
      const auto s = run_to_end(shear_case(d, 0.3, solver), &r);
      const std::string at = fmt::format("d = {}, {}", d, solver);
      EXPECT_EQ(s->contact_solver(), solver);
      const int rows = static_cast<int>(s->state().lambda.size() / d);
      EXPECT_EQ(r.contact.n_stick, 0) << at;
      EXPECT_EQ(r.contact.n_slip, rows) << at;
      const auto [normal, tangential] = force_sums(s->state());
      EXPECT_GT(normal, 10.0) << at;
      EXPECT_NEAR(tangential, 0.3 * normal, 1e-9 * normal) << at;
      std::printf("  %s: full slip, sum |lambda_t| / (mu sum lambda_n) - 1 = %.2e\n", at.c_str(),
                  tangential / (0.3 * normal) - 1);
      ASSERT_EQ(r.pair_tangential_force.size(), static_cast<std::size_t>(d)) << at;
      ASSERT_EQ(r.pair_force.size(), 1u) << at;
      EXPECT_EQ(r.pair_force[0], r.contact.total_force) << at;
      // reaction: [bottom (d), upper.top (d)]; the top's along x and y balances the friction
      for (int i = 0; i + 1 < d; ++i) {
        EXPECT_NEAR(r.reaction[static_cast<std::size_t>(d + i)], r.pair_tangential_force[static_cast<std::size_t>(i)],
                    1e-8 * normal)
            << at << ", component " << i;
        EXPECT_EQ(r.pair_tangential_force[static_cast<std::size_t>(i)], r.tangential_force[static_cast<std::size_t>(i)]);
      }
      EXPECT_GT(r.pair_tangential_force[0], 0.2 * normal) << at;  // the master dragged along +x
      // Both sides' fields: the master nodes' forces sum to the pair's, the slave nodes' to its opposite.
      const std::vector<double> f = point_field(*s, "tangential_force");
      double on_masters = 0, on_slaves = 0;
      const Mesh& m = s->mesh();
      const std::vector<double> slip = point_field(*s, "slip");
      for (int n = 0; n < m.n_nodes(); ++n) {
        if (std::abs(m.node(n)[d - 1]) > 1e-12) continue;  // the interface, both sides, is at z (y) = 0
        (slip[static_cast<std::size_t>(n)] > 0 ? on_slaves : on_masters) += f[static_cast<std::size_t>(3 * n)];
      }
      EXPECT_NEAR(on_slaves, -r.pair_tangential_force[0], 1e-12 * normal) << at;
      EXPECT_NEAR(on_masters, r.pair_tangential_force[0], 1e-10 * normal) << at;
      u[k] = s->state().u;
    }
    const double apart = (u[0] - u[1]).cwiseAbs().maxCoeff() / u[0].cwiseAbs().maxCoeff();
    EXPECT_LT(apart, 1e-8) << "d = " << d;
    std::printf("  d = %d: primal and dual u apart by %.2e of max |u|\n", d, apart);
  }
}

/// Each body's sum of a nodal point field (3 components a node): [body][component], a node counted
/// for the body of the cells it is in.
std::vector<std::array<double, 3>> sums_per_body(const Mesh& m, const std::vector<double>& f) {
  std::vector<int> body(static_cast<std::size_t>(m.n_nodes()), -1);
  int bodies = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    bodies = std::max(bodies, m.cell_body(c) + 1);
    for (int k = 0; k < m.nodes_per_cell(); ++k) body[static_cast<std::size_t>(m.cell(c)[k])] = m.cell_body(c);
  }
  std::vector<std::array<double, 3>> sums(static_cast<std::size_t>(bodies), {0.0, 0.0, 0.0});
  for (std::size_t n = 0; n < body.size(); ++n)
    for (std::size_t i = 0; i < 3; ++i) sums[static_cast<std::size_t>(body[n])][i] += f[3 * n + i];
  return sums;
}

// Issue 48: every nodal force field (contact_force, tangential_force) is the force on the body that
// owns the node, so that a per-body sum (ParaView's Threshold on the cell field body, or Python)
// is the force on that body: the slave's and the master's are equal and opposite, and the master's
// is history.csv's pair columns (the force on the master side), on both solvers, in 2D and 3D.
TEST(PairFriction, EachNodalForceFieldSumsPerBodyToEqualAndOpposite) {
  for (int d : {2, 3})
    for (const char* solver : {"active-set", "primal-active-set"}) {
      StepReport r;
      const auto s = run_to_end(shear_case(d, 0.3, solver), &r);
      const std::string at = fmt::format("d = {}, {}", d, solver);
      const double normal = r.pair_force[0];
      ASSERT_GT(normal, 10.0) << at;
      for (const char* name : {"contact_force", "tangential_force"}) {
        const auto sums = sums_per_body(s->mesh(), point_field(*s, name));
        ASSERT_EQ(sums.size(), 2u) << at;  // body 0: the lower (master) block, 1: "upper" (slave)
        const bool tangential = std::string(name) == "tangential_force";
        for (std::size_t i = 0; i < 3; ++i) {
          EXPECT_NEAR(sums[1][i], -sums[0][i], 1e-10 * normal) << at << ", " << name << ", component " << i;
          // the master's: the pair's force on it (normal along −y (−z), tangential the drag)
          const auto last = static_cast<std::size_t>(d - 1);
          double pair = 0;
          if (i == last && !tangential) pair = -normal;
          if (i < last && tangential) pair = r.pair_tangential_force[i];
          EXPECT_NEAR(sums[0][i], pair, 1e-8 * normal) << at << ", " << name << " on the master, component " << i;
        }
      }
    }
}

// μ large: the rows stick from the first step, and a stick row's slave node moves with its masters'
// mean (no relative slip at all), on both solvers. (The trailing edge's node, nearly lifted by the
// shear's moment, slips at the end even at μ = 5: its normal force is small.)
TEST(PairFriction, StickHoldsTheSlaveToItsMasters) {
  for (const char* solver : {"active-set", "primal-active-set"}) {
    StepReport r;
    const auto s = run_to_end(shear_case(2, 5.0, solver), &r);
    EXPECT_LE(r.contact.n_slip, 1) << solver;
    EXPECT_GE(r.contact.n_stick, 14) << solver;
    const State& st = s->state();
    int stuck = 0;
    for (Eigen::Index i = 0; i < st.slip.size(); ++i)
      if (st.contact_status[i] == static_cast<double>(ContactStatus::Stick)) {
        EXPECT_LT(st.slip[i], 1e-12) << solver << ", row " << i;  // over all 20 steps: it never slipped
        ++stuck;
      }
    EXPECT_GE(stuck, 14) << solver;
    const auto [normal, tangential] = force_sums(st);
    EXPECT_GT(tangential, 0.3 * normal) << solver;  // beyond what μ = 0.3 could hold
    EXPECT_NEAR(r.reaction[2], r.pair_tangential_force[0], 1e-8 * normal) << solver;
  }
}

// A master face whose every node is moved by a [[boundary.displacement]] is a rigid obstacle that
// moves: the upper block on it is the same problem as on a rigid plane with that motion (the
// master's motion enters the bound and the slip's shift h, as an obstacle's does), step by step.
TEST(PairFriction, ARigidlyDrivenMasterIsAMovingObstacle) {
  std::string pair = shear(2, 0.3);
  const std::string top = "ux = \"0.02*max(t - 1, 0)\"\nuy = \"-0.005*min(t, 1)\"\n";
  pair.replace(pair.find(top), top.size(),
               "ux = \"0\"\nuy = \"-0.005*min(t, 1)\"\n[[boundary.displacement]]\nparts = [\"top\"]\n"
               "ux = \"-0.02*max(t - 1, 0)\"\nuy = \"0\"\n");
  const std::string obstacle = R"toml(
[mesh]
generator = "rectangle"
lower = [-1.0, 0.0]
upper = [1.0, 0.5]
cells = [14, 4]
diagonal = "left"

[boundary]
contact = ["bottom"]

[[boundary.displacement]]
parts = ["top"]
ux = "0"
uy = "-0.005*min(t, 1)"

[elasticity]
kind = "plane-strain"
E = 3000.0
nu = 0.3

[viscoplasticity]
law = "elastic"

[damage]
source = "zero"

[[obstacle]]
name = "plane"
shape = "plane"
point = ["-0.02*max(t - 1, 0)", "0"]
normal = [0.0, 1.0]

[contact]
friction = "coulomb"
mu = 0.3

[time]
T = 2.0
steps = 20
)toml";
  for (const char* solver : {"active-set", "primal-active-set"}) {
    Case a = parse_case(pair, "pair.toml", ".", {}), b = parse_case(obstacle, "obstacle.toml", ".", {});
    a.solvers.contact = b.solvers.contact = solver;
    TimeStepper on_pair(a.problem, a.solvers), on_plane(b.problem, b.solvers);
    int slipping = 0;
    double forces_apart = 0;
    while (!on_pair.done()) {
      const StepReport p = on_pair.step(), q = on_plane.step();
      ASSERT_TRUE(p.ok && q.ok) << solver << ", step " << p.n;
      const double scale = q.contact.total_force;
      forces_apart = std::max({forces_apart, std::abs(p.pair_force[0] - scale) / scale,
                               std::abs(p.pair_tangential_force[0] - q.tangential_force[0]) / scale});
      EXPECT_NEAR(p.pair_force[0], scale, 1e-10 * scale) << solver << ", step " << p.n;
      EXPECT_NEAR(p.pair_tangential_force[0], q.tangential_force[0], 1e-10 * scale) << solver << ", step " << p.n;
      EXPECT_EQ(p.contact.n_slip, q.contact.n_slip) << solver << ", step " << p.n;
      slipping = p.contact.n_slip;
    }
    EXPECT_EQ(slipping, 15) << solver;  // the whole face slides at the end
    // The upper block's displacement, node by node (the same generated nodes in both meshes).
    std::map<std::pair<double, double>, int> plane_node;
    const Mesh& pm = on_plane.mesh();
    for (int n = 0; n < pm.n_nodes(); ++n) plane_node[{pm.node(n)[0], pm.node(n)[1]}] = n;
    const Mesh& m = on_pair.mesh();
    const double scale = on_plane.state().u.cwiseAbs().maxCoeff();
    int compared = 0;
    double u_apart = 0;
    for (int n = 0; n < m.n_nodes(); ++n) {
      if (m.node(n)[1] < 1e-12) continue;  // the lower block's top is at y = 0, the upper's bottom too: skip both
      const auto it = plane_node.find({m.node(n)[0], m.node(n)[1]});
      if (it == plane_node.end()) continue;
      for (int i = 0; i < 2; ++i) {
        const double e = std::abs(on_pair.state().u[2 * n + i] - on_plane.state().u[2 * it->second + i]);
        EXPECT_LE(e, 1e-9 * scale) << solver << ", node " << n;
        u_apart = std::max(u_apart, e / scale);
      }
      ++compared;
    }
    EXPECT_EQ(compared, 15 * 4);  // the upper block's nodes above its bottom
    std::printf("  %s: on the driven master and on the plane, forces apart by %.2e, u by %.2e\n", solver, forces_apart,
                u_apart);
  }
}

// Rollback and resume keep friction's state across a pair bit for bit: the dual's continuation is
// the uninterrupted run's to the bit. The primal's to its friction tolerance only (1e-9 of the force
// scale; 1e-8 here): it starts each step from the last two answers' extrapolation and keeps its
// factor across steps as GMRES's preconditioner (solver state, not the run's), and a Newton
// iteration stopped at its tolerance ends where its path does (issue 48 item 17: the kept factor's
// GMRES stops at that tolerance, where a fresh factor's solve was exact; 1.5e-9 apart).
TEST(PairFriction, RestoredRunContinuesAsBefore) {
  for (const char* solver : {"active-set", "primal-active-set"}) {
    const Case ca = shear_case(2, 0.3, solver), cb = shear_case(2, 0.3, solver);
    TimeStepper a(ca.problem, ca.solvers), b(cb.problem, cb.solvers);
    for (int i = 0; i < 13; ++i) a.step();  // sliding has begun
    b.restore(read_checkpoint(write_checkpoint(test::fresh_dir("pair_friction", solver), test::checkpoint_of(a))).snapshot);
    EXPECT_EQ(b.state().slip, a.state().slip);
    EXPECT_EQ(b.state().lambda, a.state().lambda);
    while (!a.done()) {
      a.step();
      b.step();
    }
    const double exact = std::string(solver) == "active-set" ? 0.0 : 1e-8;
    EXPECT_LE((a.state().u - b.state().u).cwiseAbs().maxCoeff(), exact * a.state().u.cwiseAbs().maxCoeff()) << solver;
    EXPECT_LE((a.state().lambda - b.state().lambda).cwiseAbs().maxCoeff(), exact * a.state().lambda.cwiseAbs().maxCoeff())
        << solver;
    EXPECT_LE((a.state().slip - b.state().slip).cwiseAbs().maxCoeff(), exact * a.state().slip.maxCoeff()) << solver;
    EXPECT_GT(a.state().slip.maxCoeff(), 0.01) << solver;
  }
}

TEST(PairFriction, FrictionKeysOnAPairAreChecked) {
  auto error = [](const std::string& text) { return error_of([&] { parse_case(text, "c.toml", ".", {}); }); };
  std::string no_law = shear(2, 0.3);
  no_law.replace(no_law.find("friction = \"coulomb\"\n"), 21, "");
  EXPECT_NE(error(no_law).find("contact.pair[0].mu: mu needs friction = \"coulomb\" in the same table"), std::string::npos)
      << error(no_law);
  std::string negative = shear(2, -0.3);
  EXPECT_NE(error(negative).find("mu"), std::string::npos) << error(negative);
  // A pair without a friction key takes [contact]'s.
  std::string inherited = shear(2, 0.3);
  inherited.replace(inherited.find("friction = \"coulomb\"\nmu = 0.3\n"), 29, "");
  inherited += "\n[contact]\nfriction = \"coulomb\"\nmu = 0.3\n";
  const Case c = parse_case(inherited, "c.toml", ".", {});
  ASSERT_EQ(c.problem->contact.pairs.size(), 1u);
  EXPECT_NE(c.problem->contact.pairs[0].friction, nullptr);
  EXPECT_TRUE(c.problem->contact.frictional());
}

}  // namespace
}  // namespace vpc
