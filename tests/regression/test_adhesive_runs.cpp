// Issue 49: a normal law with its own per-node datum runs through both contact solvers by its law
// alone. The test-only adhesive law (tests/support/test_laws.hpp): Signorini whose force may go down
// to the tension −a_i, a_i = strength |Γ3|_i, (λ_i + a_i) ⟂ (g_i − N_i u) ≥ 0.
//   A plane-strain block (E = 1000, ν = 0.3, H = 0.5) on rollers at x = 0, glued on its bottom (Γ3,
//   gap 0) and pulled up by its top, u_y = δ(t) = 0.004 t. Bonded, its stress is uniform,
//   σ_yy = E δ / (H (1 − ν²)), each bottom node carrying λ_i = −σ_yy |Γ3|_i; once σ_yy would pass the
//   strength the bottom lets go and carries exactly −a_i, a uniform traction: σ_yy = strength and the
//   bottom lifts by δ − strength H (1 − ν²)/E. P1 elements reproduce both states exactly.
//   The paper's rod made elastic (E = 1, L = 1), glued at x = L (gap 0) and pulled away by the body
//   force −p: bonded, λ = −p/2 (≥ −a); debonded (p > 2a), u(L) = a − p/2 (P1 is nodally exact).
#include "friction_runs.hpp"
#include "solvers/contact_capabilities.hpp"
#include "test_laws.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace vpc {
namespace {

using namespace friction_test;

constexpr double kE = 1000, kNu = 0.3, kH = 0.5, kPull = 0.004;  // δ(t) = kPull t

const char* const kBlock = R"toml(
[case]
name = "glued-block-2d"

[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [1.0, 0.5]
cells = [4, 2]

[boundary]
symmetry = ["left"]
contact = ["bottom"]

[[boundary.displacement]]
parts = ["top"]
uy = "{pull}*t"

[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3

[viscoplasticity]
law = "elastic"

[damage]
source = "zero"

[contact]
gap = 0.0
{law}

[time]
T = 1.0
steps = 4
)toml";

/// The block with `law` (the [contact] lines) solved by `solver`, its top moved by `pull` t.
Case block(const std::string& law, const std::string& solver, double pull = kPull) {
  test::register_test_laws();
  Case c = parse_case(fmt::format(fmt::runtime(kBlock), fmt::arg("pull", pull), fmt::arg("law", law)),
                      "glued-block-2d.toml", ".");
  c.solvers.contact = solver;
  return c;
}

std::string adhesive(double strength) { return fmt::format("law = \"test-adhesive\"\nstrength = {}", strength); }

struct Step {
  double t = 0;
  Vector u, lambda;
  std::vector<NodeForces> forces;
};

std::vector<Step> history(const Case& c) {
  std::vector<Step> out;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    out.push_back({r.t, s.state().u, s.state().lambda, node_forces(s)});
  });
  return out;
}

const std::vector<std::string> kSolvers = {"active-set", "primal-active-set"};

/// The bottom's lift u_y at the nodes of Γ3 (the block's bottom, y = 0), largest |u_y − lift|.
double lift_error(const Case& c, const Vector& u, double lift) {
  const Mesh& mesh = c.problem->mesh;
  double e = 0;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (mesh.node(i)[1] == 0) e = std::max(e, std::abs(u[i * 2 + 1] - lift));
  return e;
}

// Pulled past its bond (strength 5: σ_yy would be 6.6 and 8.8 at t = 0.75 and 1), every bottom node
// carries exactly −a_i and the bottom lifts by δ − strength H (1 − ν²)/E; below it (t = 0.25, 0.5:
// σ_yy 2.2 and 4.4) the bottom stays closed with λ_i = −σ_yy |Γ3|_i > −a_i. Both solvers.
TEST(AdhesiveLaw, ABondedNodeInTensionCarriesExactlyItsStrength) {
  const double strength = 5;
  for (const std::string& solver : kSolvers) {
    SCOPED_TRACE(solver);
    const Case c = block(adhesive(strength), solver);
    const auto steps = history(c);
    ASSERT_EQ(steps.size(), 4u);
    int debonded = 0, bonded = 0;
    double force_error = 0, lift = 0, closed_force = 0;
    for (const Step& s : steps) {
      const double delta = kPull * s.t, sigma = kE * delta / (kH * (1 - kNu * kNu));
      const bool holds = sigma <= strength;
      (holds ? bonded : debonded) += 1;
      for (const NodeForces& f : s.forces) {
        const double a = strength * f.measure;
        if (holds) {
          closed_force = std::max(closed_force, std::abs(f.normal + sigma * f.measure) / (sigma * f.measure));
          EXPECT_GT(f.normal, -a) << "t = " << s.t;
        } else {
          force_error = std::max(force_error, std::abs(f.normal + a) / a);
        }
      }
      const double expected = holds ? 0.0 : delta - strength * kH * (1 - kNu * kNu) / kE;
      lift = std::max(lift, lift_error(c, s.u, expected) / delta);
    }
    std::printf("  %s: %d steps bonded (|lambda_i / (-sigma |G3|_i) - 1| %.2g), %d debonded "
                "(|lambda_i / (-a_i) - 1| %.2g); bottom's lift off by %.2g of delta\n",
                solver.c_str(), bonded, closed_force, debonded, force_error, lift);
    EXPECT_EQ(bonded, 2);
    EXPECT_EQ(debonded, 2);
    EXPECT_LE(force_error, 1e-12);
    EXPECT_LE(closed_force, 1e-10);
    EXPECT_LE(lift, 1e-10);
  }
}

// A strong bond (strength 100) holds throughout: the block is stretched as if clamped at its bottom
// in y, every node in tension above −a_i, the gap closed.
TEST(AdhesiveLaw, BelowItsStrengthTheBondHolds) {
  const double strength = 100;
  for (const std::string& solver : kSolvers) {
    SCOPED_TRACE(solver);
    const Case c = block(adhesive(strength), solver);
    for (const Step& s : history(c)) {
      const double sigma = kE * kPull * s.t / (kH * (1 - kNu * kNu));
      EXPECT_LE(lift_error(c, s.u, 0.0), 1e-12 * kPull);
      for (const NodeForces& f : s.forces) {
        EXPECT_NEAR(f.normal, -sigma * f.measure, 1e-10 * sigma * f.measure) << "t = " << s.t;
        EXPECT_GT(f.normal, -strength * f.measure);
      }
    }
  }
}

// Strength 0 (every node debonded) is Signorini: u and λ to 1e-12 of Signorini's run, on both solvers.
TEST(AdhesiveLaw, StrengthZeroIsSignorini) {
  for (const std::string& solver : kSolvers) {
    SCOPED_TRACE(solver);
    // Pulled (no force at all), and pushed down (δ < 0), so that Signorini's forces are not all zero.
    for (const bool push : {false, true}) {
      const double pull = push ? -kPull : kPull;
      const auto x = history(block(adhesive(0), solver, pull)), y = history(block("law = \"signorini\"", solver, pull));
      ASSERT_EQ(x.size(), y.size());
      double du = 0, dl = 0;
      for (std::size_t n = 0; n < x.size(); ++n) {
        du = std::max(du, (x[n].u - y[n].u).cwiseAbs().maxCoeff() / std::max(y[n].u.cwiseAbs().maxCoeff(), 1e-300));
        dl = std::max(dl, (x[n].lambda - y[n].lambda).cwiseAbs().maxCoeff() /
                              std::max(y[n].lambda.cwiseAbs().maxCoeff(), 1.0));
      }
      EXPECT_LE(du, 1e-12) << (push ? "pushed" : "pulled");
      EXPECT_LE(dl, 1e-12) << (push ? "pushed" : "pulled");
      if (push) {
        EXPECT_GT(y.back().lambda.maxCoeff(), 1.0);  // in contact: forces to compare
      }
    }
  }
}

// The dual and the primal give the same answer, step by step.
TEST(AdhesiveLaw, TheTwoSolversAgree) {
  const auto dual = history(block(adhesive(5), "active-set")), primal = history(block(adhesive(5), "primal-active-set"));
  ASSERT_EQ(dual.size(), primal.size());
  double du = 0, dl = 0;
  for (std::size_t n = 0; n < dual.size(); ++n) {
    du = std::max(du, relative_difference(primal[n].u, dual[n].u));
    dl = std::max(dl, relative_difference(primal[n].lambda, dual[n].lambda));
  }
  std::printf("  adhesive block, primal against dual: u %.3g, lambda %.3g\n", du, dl);
  EXPECT_LE(du, 1e-12);
  EXPECT_LE(dl, 1e-12);
}

// The rod pulled by −p = −4t with a = 1: bonded while p ≤ 2 (λ = −p/2), then u(L) = a − p/2.
TEST(AdhesiveLaw, AGluedRodLetsGoAtTwiceItsStrength) {
  test::register_test_laws();
  const double a = 1;
  const std::string text = fmt::format(R"toml(
[mesh]
generator = "interval"
lower = [0.0]
upper = [1.0]
cells = 10

[boundary]
clamped = ["left"]
contact = ["right"]

[elasticity]
kind = "1d"
E = 1.0

[viscoplasticity]
law = "elastic"

[damage]
source = "zero"

[loads]
f0 = ["-4*t"]

[contact]
gap = 0.0
law = "test-adhesive"
strength = {}

[time]
T = 1.0
steps = 8
)toml", a);
  for (const std::string& solver : kSolvers) {
    SCOPED_TRACE(solver);
    Case c = parse_case(text, "glued-rod.toml", ".");
    c.solvers.contact = solver;
    int debonded = 0;
    run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
      const double p = 4 * r.t, lambda = s.state().lambda[0], uL = s.state().u[s.state().u.size() - 1];
      if (p <= 2 * a) {
        EXPECT_NEAR(lambda, -p / 2, 1e-12) << "t = " << r.t;
        EXPECT_NEAR(uL, 0.0, 1e-12) << "t = " << r.t;
      } else {
        ++debonded;
        EXPECT_NEAR(lambda, -a, 1e-12 * a) << "t = " << r.t;
        EXPECT_NEAR(uL, a - p / 2, 1e-10) << "t = " << r.t;
      }
    });
    EXPECT_EQ(debonded, 4);
  }
}

// The capability table: penalty–duality solves λ ≥ 0 only, and no solver takes friction together with
// a tension (the friction bound of a tension is not defined): refused, naming the law.
TEST(AdhesiveLaw, WhatCannotSolveItRefusesItByName) {
  for (const auto& [solver, friction, expected] :
       {std::tuple{"penalty-duality", false,
                   "contact solver 'penalty-duality' solves the Signorini conditions only (a force >= 0); law = "
                   "\"test-adhesive\" (a force down to a tension) needs 'active-set' or 'primal-active-set'"},
        std::tuple{"active-set", true, "contact solver 'active-set': law = \"test-adhesive\" lets a node carry a tension"},
        std::tuple{"primal-active-set", true,
                   "contact solver 'primal-active-set': law = \"test-adhesive\" lets a node carry a tension"}}) {
    SCOPED_TRACE(solver);
    const Case c = block(adhesive(5) + (friction ? "\nfriction = \"coulomb\"\nmu = 0.3" : ""), solver);
    try {
      TimeStepper s(c.problem, c.solvers);
      ADD_FAILURE() << "took the adhesive law";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  // Strength 0 has no tension: penalty–duality takes it (it is Signorini).
  const Case zero = block(adhesive(0), "penalty-duality");
  EXPECT_NO_THROW(TimeStepper(zero.problem, zero.solvers));
}

}  // namespace
}  // namespace vpc
