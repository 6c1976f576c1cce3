// Whole runs of the built-in cases: the 1D elastic limit against its analytic
// solution, and for every case the contact conditions, 0 ≤ β ≤ 1 and the
// agreement of the active-set and penalty–duality solvers at every step.
#include "cases/builtin_cases.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace vpc {
namespace {

constexpr double kResidualTolerance = 1e-10;

/// Checks that hold at every step of every run: converged solvers, contact KKT
/// residuals (equilibrium, no penetration, λ ≥ 0, complementarity), damage KKT
/// residual, and β in [0, 1] exactly.
void check_step(const TimeStepper& s, const StepReport& r) {
  ASSERT_TRUE(r.contact.converged) << "step " << r.n;
  ASSERT_TRUE(r.damage.converged) << "step " << r.n;
  ASSERT_LE(r.contact.residuals.max(), kResidualTolerance) << "step " << r.n;
  ASSERT_LE(r.damage.kkt_residual, kResidualTolerance) << "step " << r.n;
  ASSERT_GE(s.state().beta.minCoeff(), 0.0);
  ASSERT_LE(s.state().beta.maxCoeff(), 1.0);
  ASSERT_TRUE(r.ok);
}

struct RunResult {
  std::vector<StepReport> reports;
  State final_state;
  int factorizations = 0;
};

RunResult run(const Case& c, const SolverChoice& choice = {}) {
  TimeStepper s(c.problem, choice);
  RunResult out;
  while (!s.done()) {
    out.reports.push_back(s.step());
    check_step(s, out.reports.back());
  }
  out.final_state = s.state();
  out.factorizations = s.n_factorizations();
  return out;
}

double rel_diff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

/// Active-set and penalty–duality solvers return the same discrete solution.
void expect_solvers_agree(const Case& c, double tol) {
  const RunResult as = run(c);
  SolverChoice pd;
  pd.contact = pd.damage = "penalty-duality";
  const RunResult bm = run(c, pd);
  EXPECT_LT(rel_diff(as.final_state.u, bm.final_state.u), tol);
  EXPECT_LT(rel_diff(as.final_state.beta, bm.final_state.beta), tol);
  if (as.final_state.lambda.cwiseAbs().maxCoeff() > 0) {
    EXPECT_LT(rel_diff(as.final_state.lambda, bm.final_state.lambda), tol);
  }
  for (size_t n = 0; n < as.reports.size(); ++n)
    EXPECT_NEAR(as.reports[n].contact.total_force, bm.reports[n].contact.total_force,
                tol * std::max(1.0, std::abs(as.reports[n].contact.total_force)))
        << "step " << n + 1;
}

TEST(Paper1D, ElasticLimitMatchesAnalyticSolution) {
  // λ → ∞: no viscoplasticity, σ(x) = t(L − x) + σ_L, free tip t L²/(2E) = t/2:
  // contact at t = 0.5, then σ_L = (g − t/2) E / L (SPEC §4.1). P1 in 1D is
  // nodally exact and the P0 stress is the exact stress at the midpoint.
  Case c = load_case("paper-1d");
  c.problem->law = make_viscoplastic_law("perzyna", {{"E", 1}, {"lambda", 1e14}, {"sigma_y", 1}});
  TimeStepper s(c.problem);
  const Mesh& m = s.mesh();
  const int tip = m.n_nodes() - 1;
  while (!s.done()) {
    const StepReport r = s.step();
    check_step(s, r);
    const double t = r.t, sigma_l = t <= 0.5 ? 0.0 : 0.25 - t / 2;
    ASSERT_NEAR(s.state().u[tip], std::min(t / 2, 0.25), 1e-9) << "t = " << t;
    ASSERT_NEAR(r.contact.total_force, -sigma_l, 1e-9) << "t = " << t;
    if (t < 0.5 - 1e-9) {
      ASSERT_EQ(r.contact.n_active, 0) << "t = " << t;
    }
    if (t > 0.5 + 1e-9) {
      ASSERT_EQ(r.contact.n_active, 1) << "t = " << t;
    }
    for (int c2 = 0; c2 < m.n_cells(); ++c2) {
      const double xm = m.cell_centroid(c2)[0];
      ASSERT_NEAR(s.state().sigma[c2][0], t * (1 - xm) + sigma_l, 1e-9) << "t = " << t << " x = " << xm;
    }
  }
}

TEST(Paper1D, ContactStartsAtHalfTimeAndViscoplasticityRelaxes) {
  const RunResult r = run(load_case("paper-1d"));
  ASSERT_EQ(r.reports.size(), 100u);
  for (const auto& rep : r.reports) {
    if (rep.t < 0.5 - 1e-9) {
      EXPECT_EQ(rep.contact.n_active, 0) << rep.t;
    }
    if (rep.t > 0.5 + 1e-9) {
      EXPECT_EQ(rep.contact.n_active, 1) << rep.t;
    }
  }
  // Damage decreases β from 1 where the rod is stretched.
  EXPECT_LT(r.final_state.beta.minCoeff(), 0.9);
  // K and M + kκA factorized once; no reduced factor when no bound is active.
  EXPECT_LE(r.factorizations, 3);
}

TEST(Paper1D, SmallKappaMakesTheUpperBoundActiveAndSolversAgree) {
  // SPEC §4.3: κ ≤ 0.01 makes β ≤ 1 active near the contact end once the rod there
  // is compressed; the active set changes during the run.
  Case c = load_case("paper-1d", {.kappa = 0.001});
  const RunResult r = run(c);
  // Step 1 keeps β0 = 1 (φ0 = 0); from step 2 the stretched rod damages
  // everywhere, and β returns to the bound 1 only where contact compresses it.
  int max_upper = 0, first_upper = -1;
  for (const auto& rep : r.reports) {
    if (rep.n < 2) continue;
    if (rep.damage.n_upper > 0 && first_upper < 0) first_upper = rep.n;
    max_upper = std::max(max_upper, rep.damage.n_upper);
  }
  EXPECT_GT(max_upper, 0);
  EXPECT_GT(first_upper, 50);  // only after contact (t > 0.5) is the rod compressed
  expect_solvers_agree(c, 1e-7);
}

TEST(Paper1D, ActiveSetAndPenaltyDualityAgree) { expect_solvers_agree(load_case("paper-1d"), 1e-7); }

TEST(Paper2D, ChecksHoldAndSolversAgree) {
  Case c = load_case("paper-2d", {}, {.cells = 20});
  const RunResult r = run(c);
  for (const auto& rep : r.reports) EXPECT_EQ(rep.contact.n_active, 5);  // SPEC §4.3: all in contact
  // Equilibrium of vertical forces: contact + clamp carry the weight 10 t |Ω|;
  // the contact force is a sizeable, growing share of it.
  EXPECT_GT(r.reports.back().contact.total_force, 1.0);
  EXPECT_LT(r.reports.back().contact.total_force, 40.0);
  EXPECT_LT(r.final_state.beta.maxCoeff(), 1.0);
  EXPECT_EQ(r.factorizations, 2);  // K and M + kκA, once each
  expect_solvers_agree(c, 1e-7);
}

TEST(Block3D, PressedBlockRunsAndSolversAgree) {
  Case c = load_case("block-3d", {.steps = 20}, {.cells = 5});
  const RunResult r = run(c);
  EXPECT_GT(r.reports.back().contact.n_active, 0);
  EXPECT_GT(r.reports.back().contact.total_force, 0.0);
  EXPECT_LT(r.final_state.beta.minCoeff(), 1.0);
  expect_solvers_agree(c, 1e-7);
}

TEST(Block3D, ContactWithLiftOffChangesTheActiveSet) {
  // A wide contact zone under a body pulled sideways and down: part of the zone
  // lifts off, so the active set is a strict subset and the solvers must agree.
  Case c = load_case("block-3d", {.steps = 10}, {.cells = 5});
  c.problem->mesh.tag_facets("contact", [](const Point& x) { return std::abs(x[2]) < 1e-12; });
  c.problem->f0 = [](const Point&, double t) { return Point{40 * t, 0, -10 * t}; };
  const RunResult r = run(c);
  const int n_contact = static_cast<int>(r.final_state.lambda.size());
  EXPECT_GT(r.reports.back().contact.n_active, 0);
  EXPECT_LT(r.reports.back().contact.n_active, n_contact);
  expect_solvers_agree(c, 1e-7);
}

}  // namespace
}  // namespace vpc
