// Issue 50: the frictionless dual with adhesion's bonds (solvers/bond_dual.hpp): the three-state active
// set and the split box QP give the same λ, which satisfies every row's graph (the bond's tension branch
// below λ = 0, the law's above), on random dense problems with bonded and unbonded, rigid and compliant rows.
#include "solvers/bond_dual.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace vpc {
namespace {

struct Problem {
  Eigen::MatrixXd S;  // with the springs 1/k on the compliance rows' diagonal
  Vector spring, lower, upper, bond, length, b;
};

Problem random_problem(unsigned seed, int m) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Problem p;
  Eigen::MatrixXd A(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) A(i, j) = u(gen);
  p.S = A * A.transpose() / m + 0.2 * Eigen::MatrixXd::Identity(m, m);
  p.spring = Vector::Zero(m);
  p.lower = Vector::Zero(m);
  p.upper = Vector::Constant(m, std::numeric_limits<double>::infinity());
  p.bond = Vector::Zero(m);
  p.length = Vector::Zero(m);
  p.b.resize(m);
  for (int j = 0; j < m; ++j) {
    p.b[j] = u(gen);              // pressing where b > 0 at the free solution, pulled apart where b < 0
    if (j % 3 == 1) p.spring[j] = 0.5 + 0.5 * std::abs(u(gen));  // a compliance row, 1/k
    if (j % 4 != 0) {                                             // bonded, a and L of several sizes
      p.bond[j] = std::pow(10.0, 2 * u(gen));
      p.length[j] = 0.05 + 0.5 * std::abs(u(gen));
    }
    p.S(j, j) += p.spring[j];
  }
  return p;
}

/// The largest violation of a row's graph at λ (relative to max |λ| and max |b|).
double graph_residual(const Problem& p, const Vector& lambda) {
  const Vector d = p.b - (p.S - Eigen::MatrixXd(p.spring.asDiagonal())) * lambda;  // the penetration
  double worst = 0;
  for (Eigen::Index j = 0; j < lambda.size(); ++j) {
    const double a = p.bond[j], L = p.length[j], l = lambda[j];
    const double pull = a * std::max(std::min(d[j], 0.0), -L);  // the bond's force at d ≤ 0 (0 unbonded)
    double off;
    if (p.spring[j] > 0) {
      off = std::abs(l - (d[j] > 0 ? d[j] / p.spring[j] : pull));  // λ a function of d
    } else if (l < 0) {
      off = std::abs(l - pull) + std::max(d[j], 0.0);  // on the bond, d ≤ 0
    } else {  // closed: d = 0 where λ > 0 or where a bond would pull at d < 0; d ≤ 0 unbonded at λ = 0
      off = l > 0 || a > 0 ? std::abs(d[j]) : std::max(d[j], 0.0);
    }
    worst = std::max(worst, off);
  }
  return worst / std::max({lambda.cwiseAbs().maxCoeff(), p.b.cwiseAbs().maxCoeff(), 1e-300});
}

TEST(BondDual, TheThreeStatesAndTheSplitBoxQpAgreeAndMeetEveryRowsGraph) {
  int three_states = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE(seed);
    const Problem p = random_problem(seed, 12);
    Vector by_states = Vector::Zero(12), by_split = Vector::Zero(12);
    const auto r = solve_bond_states(p.S, p.spring, p.lower, p.bond, p.length, p.b, by_states);
    const BoxQpResult q = solve_bond_split(p.S, p.spring, p.lower, p.upper, p.bond, p.length, p.b, by_split);
    ASSERT_TRUE(q.converged);
    EXPECT_LE(graph_residual(p, by_split), 1e-12);
    if (!r) continue;  // its sets came back: the caller takes the split
    ++three_states;
    EXPECT_TRUE(r->converged);
    EXPECT_LE(graph_residual(p, by_states), 1e-12);
    EXPECT_LE((by_states - by_split).cwiseAbs().maxCoeff(), 1e-11 * std::max(by_split.cwiseAbs().maxCoeff(), 1.0));
  }
  std::printf("  the three states solved %d of 40 random problems alone\n", three_states);
  EXPECT_GE(three_states, 30);
}

TEST(BondDual, WithoutBondsItIsTheBoxQp) {
  Problem p = random_problem(7, 10);
  p.bond.setZero();
  Vector x = Vector::Zero(10), y = Vector::Zero(10);
  ASSERT_TRUE(solve_bond_states(p.S, p.spring, p.lower, p.bond, p.length, p.b, x).has_value());
  DenseBoxQpOperator H(p.S);
  ASSERT_TRUE(solve_box_qp(H, p.b, p.lower, p.upper, y).converged);
  EXPECT_LE((x - y).cwiseAbs().maxCoeff(), 1e-12 * y.cwiseAbs().maxCoeff());
  EXPECT_GE(x.minCoeff(), 0.0);
}

}  // namespace
}  // namespace vpc
