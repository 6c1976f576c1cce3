// Damage solvers (solvers/damage_solver): the box QP 0 ≤ β ≤ 1 with H = M + kκA on a
// 2D mesh, a right-hand side that drives β to both bounds; active-set and
// penalty–duality must agree, and the active-set factor cache must work.
#include "solvers/damage_solver.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "mesh/generators.hpp"
#include "solvers/box_qp.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace vpc {
namespace {

struct DamageProblem {
  SparseMatrix H;
  Vector rhs;
};

/// Unit square, 16 × 16; H = M + kκA with kκ = 2e-3; rhs = M β̂ with β̂ = 2.6x − 0.8 +
/// 0.3 sin(2πy) in [−0.8 − 0.3, 1.8 + 0.3]: β = 0 on the left, β = 1 on the right.
DamageProblem damage_problem() {
  const Mesh m = make_rectangle({0, 0, 0}, {1, 1, 0}, 16, 16);
  const auto geo = compute_geometry(m);
  const SparseMatrix M = assemble_mass(m, geo), A = assemble_laplacian(m, geo);
  Vector target(m.n_nodes());
  for (int i = 0; i < m.n_nodes(); ++i)
    target[i] = 2.6 * m.node(i)[0] - 0.8 + 0.3 * std::sin(2 * M_PI * m.node(i)[1]);
  DamageProblem p;
  p.H = M + 2e-3 * A;
  p.rhs = M * target;
  return p;
}

void expect_in_unit_box(const Vector& beta) {
  for (int i = 0; i < beta.size(); ++i) {
    ASSERT_GE(beta[i], 0.0) << i;
    ASSERT_LE(beta[i], 1.0) << i;
  }
}

// Same β to 1e-8, exactly in [0, 1], KKT residual ≤ 1e-10, both bounds active.
TEST(DamageSolver, ActiveSetAndPenaltyDualityAgree) {
  const DamageProblem p = damage_problem();
  const int n = static_cast<int>(p.rhs.size());
  Vector beta[2];
  DamageReport rep[2];
  const char* names[2] = {"active-set", "penalty-duality"};
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(names[s]);
    auto solver = make_damage_solver(names[s], p.H);
    EXPECT_EQ(solver->name(), names[s]);
    beta[s] = Vector::Constant(n, 0.5);
    rep[s] = solver->solve(p.rhs, beta[s]);
    ASSERT_TRUE(rep[s].converged) << rep[s].iterations << " iterations";
    expect_in_unit_box(beta[s]);
    EXPECT_LE(rep[s].kkt_residual, 1e-10);
    // Recomputed independently of the solver's own report.
    EXPECT_LE(box_qp_kkt_residual(p.H * beta[s], p.H.diagonal(), p.rhs, Vector::Zero(n), Vector::Ones(n), beta[s]),
              1e-10);
    EXPECT_GT(rep[s].n_lower, 0);
    EXPECT_GT(rep[s].n_upper, 0);
    EXPECT_LT(rep[s].n_lower + rep[s].n_upper, n);
  }
  EXPECT_LE((beta[1] - beta[0]).cwiseAbs().maxCoeff(), 1e-8);
  // Same active sets up to the penalty–duality tolerance. (Not rep.n_lower: the
  // penalty–duality iterate may end a round-off *inside* the box, e.g. β = 1e-20 at
  // a node with a clearly positive multiplier, which the projection leaves as is.)
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(beta[0][i] == 0.0, beta[1][i] <= 1e-12) << i;
    EXPECT_EQ(beta[0][i] == 1.0, beta[1][i] >= 1 - 1e-12) << i;
  }
  EXPECT_LE(rep[1].n_lower, rep[0].n_lower);
  EXPECT_LE(rep[1].n_upper, rep[0].n_upper);
}

// The active-set solver factors H once and a reduced H_FF per active set: solving
// again with the same active set (the same rhs, or a slightly perturbed one, warm
// started) must not factorize again, while the solution still updates.
TEST(DamageSolver, ActiveSetReusesFactorForSameActiveSet) {
  const DamageProblem p = damage_problem();
  const int n = static_cast<int>(p.rhs.size());
  auto solver = make_damage_solver("active-set", p.H);
  Vector beta = Vector::Zero(n);
  const DamageReport first = solver->solve(p.rhs, beta);
  ASSERT_TRUE(first.converged);
  const int nf = solver->n_factorizations();
  EXPECT_GE(nf, 2);  // the full factor and at least one reduced factor

  const DamageReport again = solver->solve(p.rhs, beta);  // already optimal: no solve
  EXPECT_TRUE(again.converged);
  EXPECT_EQ(again.iterations, 0);
  EXPECT_EQ(solver->n_factorizations(), nf);

  const Vector rhs2 = p.rhs * (1 + 1e-9);
  const Vector beta1 = beta;
  const DamageReport perturbed = solver->solve(rhs2, beta);
  EXPECT_TRUE(perturbed.converged);
  EXPECT_EQ(perturbed.iterations, 1);  // one reduced solve, then the set repeats
  EXPECT_EQ(perturbed.n_lower, first.n_lower);
  EXPECT_EQ(perturbed.n_upper, first.n_upper);
  EXPECT_EQ(solver->n_factorizations(), nf);
  EXPECT_GT((beta - beta1).cwiseAbs().maxCoeff(), 0.0);  // it did solve the new problem
  EXPECT_LE(perturbed.kkt_residual, 1e-12);
}

TEST(DamageSolver, UnknownNameThrows) {
  const DamageProblem p = damage_problem();
  try {
    make_damage_solver("magic", p.H);
    FAIL() << "expected vpc::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown damage solver 'magic'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vpc
