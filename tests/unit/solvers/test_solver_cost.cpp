// Direct or iterative (solvers/solver_cost.hpp): the estimate adds up its parts, and the
// choice follows the sizes where the two paths differ by a wide margin.
#include "solvers/solver_cost.hpp"

#include <gtest/gtest.h>

namespace vpc {
namespace {

FactorEstimate factor(double entries, double flops) {
  FactorEstimate f;
  f.entries = entries;
  f.flops = flops;
  return f;
}

TEST(SolverCost, DualIsFactorPlusSchurColumnsPlusSteps) {
  SolverRates r;
  r.factor_flops_per_second = 1e9;
  r.solve_seconds_per_entry = 1e-9;
  r.column_share = 0.5;
  r.dual_solves_per_step = 2;
  r.cg_step_seconds_per_nonzero = 1e-7;
  // factor 2 s; a solve 0.1 s; S: 40 columns x 0.5 x 0.1 = 2 s; 10 steps x 2 x 0.1 = 2 s.
  const SolverCost c = estimate_solver_cost(factor(1e8, 2e9), 1e6, 40, 10, true, r);
  EXPECT_DOUBLE_EQ(c.direct, 6.0);
  EXPECT_DOUBLE_EQ(c.iterative, 1.0);  // 10 steps x 1e-7 x 1e6
  EXPECT_NE(c.detail.find("S (40 columns)"), std::string::npos) << c.detail;
  EXPECT_TRUE(iterative_is_faster(c));
}

TEST(SolverCost, PrimalOnAFactorPaysARefactorizationPerSetChange) {
  SolverRates r;
  r.factor_flops_per_second = 1e9;
  r.solve_seconds_per_entry = 0;
  r.primal_direct_factorizations_per_step = 0.5;
  const SolverCost c = estimate_solver_cost(factor(1e8, 1e9), 1e6, 5000, 100, false, r);
  EXPECT_DOUBLE_EQ(c.direct, 1.0 + 50.0);
  EXPECT_NE(c.detail.find("refactorizations"), std::string::npos) << c.detail;
}

TEST(SolverCost, TheChoiceNeedsAWideMargin) {
  SolverCost c;
  c.direct = 10;
  c.iterative = 6;
  EXPECT_FALSE(iterative_is_faster(c));  // faster, but not by half: the estimate is rough
  c.iterative = 4.9;
  EXPECT_TRUE(iterative_is_faster(c));
}

TEST(SolverCost, TheMeasuredRatesKeepSmallProblemsDirectAndLargeZonesIterative) {
  // Sizes of foundation-3d from CHOLMOD's analysis (100 steps; docs/performance.md): at
  // n = 20 the direct path is faster (measured: 2.5 s set-up and 0.04 s a step, against
  // 1.2 s a step on CG); at n = 50 (2,601 contact nodes: the primal solver on a factor,
  // which refactorizes a 2.8e12-flop factor at set changes) CG + GAMG is.
  const SolverCost small = estimate_solver_cost(factor(1.54e7, 1.16e10), 1.14e6, 441, 100, true);
  EXPECT_FALSE(iterative_is_faster(small)) << small.detail;
  const SolverCost large = estimate_solver_cost(factor(6.4e8, 2.8e12), 1.71e7, 2601, 100, false);
  EXPECT_TRUE(iterative_is_faster(large)) << large.detail;
  // Issue 27: the contact start counts. Two steps of foundation-3d n = 16 (13,872 unknowns, 289
  // contact nodes) stay direct (CG's estimate was 0.14 s, its start alone costs more); hertz-3d
  // (27,354 unknowns, 766 contact nodes: S is 766 solves) takes CG + GAMG, measured 1.3-1.7x faster.
  const SolverCost small_run = estimate_solver_cost(factor(8.83e6, 5.39e9), 5.67e5, 289, 2, true);
  EXPECT_FALSE(iterative_is_faster(small_run)) << small_run.detail;
  EXPECT_GT(small_run.iterative, 7 * 1.2e-7 * 5.67e5);  // the start: about five steps more
  const SolverCost hertz = estimate_solver_cost(factor(1.95e7, 1.5e10), 1.15e6, 766, 1, true);
  EXPECT_TRUE(iterative_is_faster(hertz)) << hertz.detail;
}

}  // namespace
}  // namespace vpc
