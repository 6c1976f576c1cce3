// The primal active-set contact solver (solvers/primal_active_set, issue 14): its
// reflections, agreement with the dual solver on an elastic block with slanted contact
// directions (Signorini and linear compliance rows mixed), warm starts, the automatic
// choice, and its refusals.
#include "../error_of.hpp"
#include "contact/normal_compliance.hpp"
#include "solvers/contact_frame.hpp"
#include "solvers/contact_capabilities.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/primal_active_set.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "material/elasticity.hpp"
#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace vpc {
namespace {

/// (0, 2) × (0, 1), plane strain E = 1, ν = 0.3, clamped on "top", pushed down by f0 =
/// (0.3, −1). One contact row per "bottom" node, direction (sin θ, −cos θ) with θ from
/// −0.6 to 0.6 along the base (θ = 0 at one node: that row needs no reflection), gaps growing
/// with x: a free boundary across the base.
struct SlantedBlock {
  Mesh mesh;
  DofMap dofs;
  SparseMatrix K, N;
  Vector F, g;
};

SlantedBlock make_slanted_block(double theta_max = 0.6) {
  SlantedBlock b;
  b.mesh = make_rectangle({0, 0, 0}, {2, 1, 0}, 16, 8);
  const auto geo = compute_geometry(b.mesh);
  b.dofs = DofMap(b.mesh.n_nodes(), 2, b.mesh.nodes_of_parts({"top"}));
  b.K = assemble_stiffness(b.mesh, geo, Elasticity(Elasticity::Kind::PlaneStrain, 1, 0.3), b.dofs);
  const VectorField f0 = [](const Point&, double) { return Point{0.3, -1, 0}; };
  b.F = restrict_to_free(b.dofs, assemble_load(b.mesh, geo, {}, f0, nullptr, 0.0));
  const std::vector<int> bottom = b.mesh.nodes_of_parts({"bottom"});
  const int m = static_cast<int>(bottom.size());
  std::vector<Eigen::Triplet<double>> t;
  b.g.resize(m);
  for (int r = 0; r < m; ++r) {
    const double x = b.mesh.node(bottom[r])[0], theta = theta_max * (x - 1);
    t.emplace_back(r, b.dofs.free_index(b.dofs.full_index(bottom[r], 0)), std::sin(theta));
    t.emplace_back(r, b.dofs.free_index(b.dofs.full_index(bottom[r], 1)), -std::cos(theta));
  }
  b.N.resize(m, b.dofs.n_free());
  b.N.setFromTriplets(t.begin(), t.end());
  b.N.prune(0.0);  // θ = 0: one entry
  // Gap from the free deflection d: from 0.2 d (x = 0) to 1.2 d (x = 2).
  auto f = la::make_cholmod_factor();
  f->factorize(la::SparseOperator(b.K), "block stiffness");
  Vector u_free;
  f->solve(b.F, u_free);
  const double d = (b.N * u_free).maxCoeff();
  for (int r = 0; r < m; ++r) b.g[r] = d * (0.2 + 0.5 * b.mesh.node(bottom[r])[0]);
  return b;
}

TEST(PrimalActiveSet, ReflectionsTurnEachRowIntoOneDof) {
  const SlantedBlock b = make_slanted_block();
  const SparseMatrix Q = contact_reflections(b.N);
  ASSERT_EQ(Q.rows(), b.N.cols());
  const Eigen::MatrixXd Qd(Q);
  EXPECT_LE((Qd - Qd.transpose()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((Qd * Qd - Eigen::MatrixXd::Identity(Q.rows(), Q.cols())).cwiseAbs().maxCoeff(), 1e-15);
  const Eigen::MatrixXd NQ = Eigen::MatrixXd(b.N) * Qd;
  for (Eigen::Index i = 0; i < NQ.rows(); ++i) {
    int entries = 0;
    for (Eigen::Index j = 0; j < NQ.cols(); ++j)
      if (std::abs(NQ(i, j)) > 1e-15) ++entries;
    EXPECT_EQ(entries, 1) << "row " << i;
    EXPECT_NEAR(NQ.row(i).cwiseAbs().maxCoeff(), 1.0, 1e-15);
  }
  // Rows along the axes need no reflection at all.
  SparseMatrix axis = b.N;
  for (int k = 0; k < axis.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(axis, k); it; ++it)
      if (std::abs(it.value()) < 0.9) it.valueRef() = 0;
  axis.prune(0.0);
  EXPECT_EQ(contact_reflections(axis).size(), 0);
}

/// The dual ("active-set", [0]) and the primal solver ([1], on K_rot) on the same constraints,
/// each converged with residuals ≤ 1e-10, and their answers alike: u and λ to 1e-10 (relative)
/// and the same strict, non-empty active set.
struct BothSolvers {
  Vector u[2], lambda[2];
  ContactReport rep[2];
};
BothSolvers solve_both(const SparseMatrix& K_matrix, const Vector& F, const ContactConstraints& c,
                       const SparseMatrix& K_rot_matrix) {
  BothSolvers out;
  auto K = std::make_shared<const la::SparseOperator>(K_matrix);
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(s == 0 ? "active-set" : "primal-active-set");
    std::unique_ptr<ContactSolver> solver;
    if (s == 0) {
      std::shared_ptr<la::LinearSolver> f = la::make_cholmod_factor("K");
      f->factorize(*K, "K");
      solver = make_contact_solver("active-set", K, f, c, la::make_cholmod_factor);
    } else {
      solver = make_primal_active_set_solver(K, std::make_shared<const la::SparseOperator>(K_rot_matrix),
                                             la::make_cholmod_factor("K"), c);
    }
    out.rep[s] = solver->solve(F, out.u[s], out.lambda[s]);
    EXPECT_TRUE(out.rep[s].converged) << out.rep[s].iterations << " iterations";
    EXPECT_LE(out.rep[s].residuals.max(), 1e-10);
  }
  EXPECT_GT(out.rep[1].n_active, 1);
  EXPECT_LT(out.rep[1].n_active, c.m - 1);
  EXPECT_EQ(out.rep[1].n_active, out.rep[0].n_active);
  EXPECT_LE((out.u[1] - out.u[0]).cwiseAbs().maxCoeff(), 1e-10 * out.u[0].cwiseAbs().maxCoeff());
  EXPECT_LE((out.lambda[1] - out.lambda[0]).cwiseAbs().maxCoeff(), 1e-10 * out.lambda[0].cwiseAbs().maxCoeff());
  return out;
}

// Both methods solve the same inequality: u and λ to 1e-10 (relative), residuals ≤ 1e-10,
// a strict non-empty active set; then the same with every third row a linear compliance.
TEST(PrimalActiveSet, AgreesWithTheDualSolverOnSlantedRows) {
  const SlantedBlock b = make_slanted_block();
  const int m = static_cast<int>(b.N.rows());
  const SparseMatrix Q = contact_reflections(b.N);
  for (const bool compliance : {false, true}) {
    SCOPED_TRACE(compliance ? "Signorini and compliance rows" : "Signorini rows");
    ContactConstraints c;
    c.m = m;
    c.N = b.N;
    c.gap = b.g;
    for (int i = 0; i < m; ++i) c.rows.push_back(i);
    if (compliance) {
      c.laws = {signorini_law(), std::make_shared<const NormalComplianceLaw>(1 / 0.05, 1.0)};
      c.law.assign(static_cast<std::size_t>(m), 0);
      c.datum = Vector::Zero(m);
      for (int i = 0; i < m; i += 3) {
        c.law[static_cast<std::size_t>(i)] = 1;
        c.datum[i] = 1 / 0.05;
      }
    }
    const BothSolvers r = solve_both(b.K, b.F, c, SparseMatrix(Q * b.K * Q));
    EXPECT_EQ(r.rep[1].cycles, 0);
    EXPECT_EQ(r.rep[1].factorizations, r.rep[1].iterations);  // a new set each iteration but the last
  }
}

/// The slanted block's rows as contact pair rows (issue 29): each bottom node's row also reads the
/// two nodes above it, −w ν on their dofs (w = 0.3, 0.7), as a pair's row reads its masters; the
/// rows' own dofs as node_dofs. Offset by `shift` rows of nodes (1: the row just above).
SparseMatrix with_masters(const SlantedBlock& b, std::vector<std::vector<int>>& node_dofs, int shift = 1) {
  std::vector<Eigen::Triplet<double>> t;
  node_dofs.assign(static_cast<std::size_t>(b.N.rows()), {});
  const std::vector<int> bottom = b.mesh.nodes_of_parts({"bottom"});
  for (int k = 0; k < b.N.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(b.N, k); it; ++it) t.emplace_back(static_cast<int>(it.row()), k, it.value());
  const Eigen::MatrixXd dense(b.N);
  for (int r = 0; r < static_cast<int>(bottom.size()); ++r) {
    const int node = bottom[static_cast<std::size_t>(r)];
    for (int c = 0; c < 2; ++c) node_dofs[static_cast<std::size_t>(r)].push_back(b.dofs.free_index(b.dofs.full_index(node, c)));
    const double nu[2] = {dense(r, node_dofs[static_cast<std::size_t>(r)][0]), dense(r, node_dofs[static_cast<std::size_t>(r)][1])};
    // The 17 nodes of a row of the 16 × 8 mesh are numbered along x: the node above is + 17 shift.
    const int above[2] = {node + 17 * shift, node + 17 * shift + (r + 1 < 17 ? 1 : -1)};
    const double w[2] = {0.3, 0.7};
    for (int a = 0; a < 2; ++a)
      for (int c = 0; c < 2; ++c)
        if (nu[c] != 0) t.emplace_back(r, b.dofs.free_index(b.dofs.full_index(above[a], c)), -w[a] * nu[c]);
  }
  SparseMatrix N(b.N.rows(), b.N.cols());
  N.setFromTriplets(t.begin(), t.end());
  return N;
}

// The pair basis u = P w (contact_basis): every row, masters and all, is one dof of w with |α| = ρ,
// P P⁻¹ = I; then the primal solver on it solves the inequality as the dual does (u, λ to 1e-10).
// A master on another row's own dofs (a node on both sides) is refused, naming the dof.
TEST(PrimalActiveSet, ThePairBasisTurnsEachPairRowIntoOneDof) {
  const SlantedBlock b = make_slanted_block();
  std::vector<std::vector<int>> node_dofs;
  const SparseMatrix N = with_masters(b, node_dofs);
  ASSERT_TRUE(masters_apart_from_slaves(N, node_dofs));
  const ContactBasis basis = contact_basis(N, node_dofs);
  ASSERT_TRUE(basis.pairs());
  const Eigen::MatrixXd P(basis.P), P_inv(basis.P_inverse);
  EXPECT_LE((P * P_inv - Eigen::MatrixXd::Identity(P.rows(), P.cols())).cwiseAbs().maxCoeff(), 1e-14);
  const Eigen::MatrixXd NP = Eigen::MatrixXd(N) * P;
  for (Eigen::Index i = 0; i < NP.rows(); ++i) {
    const auto& row = basis.rows[static_cast<std::size_t>(i)];
    EXPECT_NEAR(NP(i, row.dof), row.alpha, 1e-14) << "row " << i;
    EXPECT_NEAR(std::abs(row.alpha), 1.0, 1e-15);
    EXPECT_LE((NP.row(i).cwiseAbs().sum() - std::abs(NP(i, row.dof))), 1e-14) << "row " << i;
  }
  const int m = static_cast<int>(N.rows());
  // Gaps from each row's free value: 0.2 of it at x = 0 to 1.2 at x = 2 (violated for x < 1.6).
  Vector u_free;
  auto free_factor = la::make_cholmod_factor();
  free_factor->factorize(la::SparseOperator(b.K), "block stiffness");
  free_factor->solve(b.F, u_free);
  const Vector free_rows = N * u_free;
  const std::vector<int> bottom = b.mesh.nodes_of_parts({"bottom"});
  ContactConstraints c;
  c.m = m;
  c.N = N;
  c.gap.resize(m);
  for (int r = 0; r < m; ++r) c.gap[r] = free_rows[r] * (0.2 + 0.5 * b.mesh.node(bottom[static_cast<std::size_t>(r)])[0]);
  c.node_dofs = node_dofs;
  for (int i = 0; i < m; ++i) c.rows.push_back(i);
  solve_both(b.K, b.F, c, SparseMatrix(basis.P.transpose() * b.K * basis.P));
  // Masters on the bottom row itself (shift 0 reads the row's own and its neighbour's node).
  const SparseMatrix both = with_masters(b, node_dofs, 0);
  EXPECT_FALSE(masters_apart_from_slaves(both, node_dofs));
  const std::string msg = error_of([&] { contact_basis(both, node_dofs); });
  EXPECT_NE(msg.find("a node on the slave and the master side"), std::string::npos) << msg;
}

// Solved again from its own answer, the primal solver stops after one solve with the factor
// it has: no factorization.
TEST(PrimalActiveSet, WarmStartCostsOneSolveAndNoFactorization) {
  const SlantedBlock b = make_slanted_block();
  auto solver = make_contact_solver("primal-active-set", b.K, b.N, b.g);
  Vector u, lambda;
  const ContactReport first = solver->solve(b.F, u, lambda);
  ASSERT_TRUE(first.converged);
  EXPECT_GT(first.iterations, 1);
  const Vector u0 = u, l0 = lambda;
  const ContactReport again = solver->solve(b.F, u, lambda);
  ASSERT_TRUE(again.converged);
  EXPECT_EQ(again.iterations, 1);
  EXPECT_EQ(again.factorizations, 0);
  EXPECT_LE((u - u0).cwiseAbs().maxCoeff(), 1e-13 * u0.cwiseAbs().maxCoeff());
  EXPECT_LE((lambda - l0).cwiseAbs().maxCoeff(), 1e-12 * l0.cwiseAbs().maxCoeff());
}

// Three dofs, each bounded above (u_i ≤ g_i), K symmetric positive definite but not an
// M-matrix (found by a search over random 3 x 3 problems): from the empty set, the plain
// update rule (active where λ_i + c_i (u_i − g_i) > 0) visits {1}, {0, 1, 2}, {0}, {1} again. The
// guard notices the repeat, switches to monotone updates (add the violated rows, release only
// the most negative force) and ends at the same answer as the dual solver, whose box QP on
// S = K⁻¹ cycles too and is guarded alike (solve_box_qp).
TEST(PrimalActiveSet, TheCyclingGuardEndsACycleAtTheDualAnswer) {
  Eigen::MatrixXd Kd(3, 3);
  Kd << 6.617, -2.169, -4.035, -2.169, 3.049, 2.483, -4.035, 2.483, 3.298;
  const SparseMatrix K = Kd.sparseView();
  const SparseMatrix N = Eigen::MatrixXd::Identity(3, 3).sparseView();
  const Vector F = (Vector(3) << 5.265, 0.379, -2.792).finished();
  const Vector g = (Vector(3) << 0.103, 0.175, 0.073).finished();
  Vector u[2], lambda[2];
  ContactReport rep[2];
  const char* names[] = {"active-set", "primal-active-set"};
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(names[s]);
    rep[s] = make_contact_solver(names[s], K, N, g)->solve(F, u[s], lambda[s]);
    ASSERT_TRUE(rep[s].converged) << rep[s].iterations << " iterations";
    EXPECT_LE(rep[s].residuals.max(), 1e-12);
  }
  EXPECT_GE(rep[0].cycles, 1);  // the dual's box QP (S = K⁻¹ here) cycles as well
  EXPECT_GE(rep[1].cycles, 1);
  EXPECT_LE((u[1] - u[0]).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((lambda[1] - lambda[0]).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(PrimalActiveSet, AutomaticChoiceSaysWhy) {
  EXPECT_EQ(pick_contact_solver("auto", 100, "cholmod", ContactNeeds{}).name, "active-set");
  EXPECT_EQ(pick_contact_solver("auto", kDualContactRows + 1, "mumps", ContactNeeds{}).name, "primal-active-set");
  EXPECT_EQ(pick_contact_solver("auto", 100, "cg-gamg", ContactNeeds{}).name, "primal-active-set");
  ContactNeeds power_law;
  power_law.nonlinear = "a power-law compliance";
  EXPECT_EQ(pick_contact_solver("auto", 100000, "cg-gamg", power_law).name, "active-set");  // only the dual has it
  EXPECT_EQ(pick_contact_solver("penalty-duality", 100000, "cg-gamg", ContactNeeds{}).name, "penalty-duality");
  const ContactSolverPick p = pick_contact_solver("auto", 5041, "cholmod", ContactNeeds{});
  EXPECT_NE(p.why.find("5041 contact nodes"), std::string::npos) << p.why;
}

// Rows spread over the ranks (remote pieces of a pair row at its masters' owners): the dual alone;
// on several ranks: mpi.spread_rows.
TEST(PrimalActiveSet, RefusesRowsSpreadOverRanks) {
  ContactNeeds spread;
  spread.spread_pairs = true;
  for (const std::string name : {"primal-active-set", "penalty-duality"}) {
    const std::string why = cannot_solve(name, spread);
    EXPECT_NE(why.find("contact solver '" + name + "': the rows of contact pairs are spread over the ranks"),
              std::string::npos) << why;
    EXPECT_NE(why.find("--contact-solver active-set solves them"), std::string::npos) << why;
  }
  EXPECT_EQ(cannot_solve("active-set", spread), "");
  const ContactSolverPick p = pick_contact_solver("auto", 100000, "cg-gamg", spread);
  EXPECT_EQ(p.name, "active-set");
  EXPECT_NE(p.why.find("spread over the ranks"), std::string::npos) << p.why;
}

TEST(PrimalActiveSet, RefusesAPowerLaw) {
  const SlantedBlock b = make_slanted_block();
  ContactConstraints c;
  c.m = static_cast<int>(b.N.rows());
  c.N = b.N;
  c.gap = b.g;
  for (int i = 0; i < c.m; ++i) c.rows.push_back(i);
  c.laws = {std::make_shared<const NormalComplianceLaw>(10.0, 2.0)};
  c.law.assign(static_cast<std::size_t>(c.m), 0);
  c.datum = Vector::Constant(c.m, 10.0);
  auto K = std::make_shared<const la::SparseOperator>(b.K);
  const SparseMatrix Q = contact_reflections(b.N);
  auto K_rot = std::make_shared<const la::SparseOperator>(SparseMatrix(Q * b.K * Q));
  const std::string msg =
      error_of([&] { make_primal_active_set_solver(K, K_rot, la::make_cholmod_factor("K"), c); });
  EXPECT_NE(msg.find("power-law compliance needs 'active-set'"), std::string::npos) << msg;
}

}  // namespace
}  // namespace vpc
