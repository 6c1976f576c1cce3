// Contact solvers (solvers/contact_solver): a spring system whose contact force is
// known by hand, a 2D elastic block touching a sloped obstacle on part of its
// base (active-set vs penalty–duality), warm starts, and the error paths.
#include "../error_of.hpp"
#include "../solve_with.hpp"
#include "contact/normal_compliance.hpp"
#include "solvers/compliance_dual.hpp"
#include "solvers/contact_solver.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "material/elasticity.hpp"
#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace vpc {
namespace {

/// One law on every row of `cc`, with the datum k of each row (its compliance is 1/k).
void set_law(ContactConstraints& cc, std::shared_ptr<const ContactLaw> law, const Vector& datum) {
  cc.laws = {std::move(law)};
  cc.law.assign(static_cast<std::size_t>(datum.size()), 0);
  cc.datum = datum;
}

const char* const kSolvers[] = {"active-set", "penalty-duality"};

/// The residuals of (3.9) on one process (rows 0..m−1, N whole).
ContactResiduals residuals(const SparseMatrix& K, const SparseMatrix& N, const Vector& F, const Vector& g,
                           const Vector& u, const Vector& lambda) {
  ContactConstraints c;
  c.m = static_cast<int>(N.rows());
  c.N = N;
  c.gap = g;
  for (int i = 0; i < c.m; ++i) c.rows.push_back(i);
  return contact_residuals(la::SparseOperator(K), c, F, u, lambda);
}

SparseMatrix sparse(const Eigen::MatrixXd& D) { return D.sparseView(); }

/// Wall — k1 — node 1 — k2 — node 2 → obstacle at distance g from node 2.
/// K = [[k1 + k2, −k2], [−k2, k2]], N = [0 1] (u2 ≤ g), load F on node 2.
struct Springs {
  double k1 = 2, k2 = 3, g = 0.5;
  SparseMatrix K, N;
  Springs() {
    K = sparse((Eigen::MatrixXd(2, 2) << k1 + k2, -k2, -k2, k2).finished());
    N = sparse((Eigen::MatrixXd(1, 2) << 0, 1).finished());
  }
  double k_series() const { return k1 * k2 / (k1 + k2); }  // 1.2
};

// F = 0.3: u2 = F/k_series = 0.25 < g, no contact: λ = 0 and u the free solution.
TEST(ContactSolver, SpringsWithoutContact) {
  const Springs s;
  const Vector F = (Vector(2) << 0, 0.3).finished(), g = Vector::Constant(1, s.g);
  for (const char* name : kSolvers) {
    SCOPED_TRACE(name);
    auto solver = make_contact_solver(name, s.K, s.N, g);
    EXPECT_EQ(solver->name(), name);
    Vector u, lambda;
    const ContactReport rep = solver->solve(F, u, lambda);
    ASSERT_TRUE(rep.converged);
    ASSERT_EQ(u.size(), 2);
    ASSERT_EQ(lambda.size(), 1);
    EXPECT_EQ(rep.n_active, lambda[0] > 0 ? 1 : 0);
    EXPECT_NEAR(lambda[0], 0.0, 1e-12);
    EXPECT_NEAR(u[0], 0.3 / s.k1, 1e-12);
    EXPECT_NEAR(u[1], 0.3 / s.k_series(), 1e-12);
    EXPECT_LE(rep.residuals.max(), 1e-10);
    EXPECT_LE(residuals(s.K, s.N, F, g, u, lambda).max(), 1e-10);
  }
}

// F = 1.5: free u2 = 1.25 > g, so u2 = g, u1 = k2 g/(k1 + k2) = 0.3 and the contact
// force is λ = F − k_series g = 0.9.
TEST(ContactSolver, SpringsInContactGiveHandComputedForce) {
  const Springs s;
  const Vector F = (Vector(2) << 0, 1.5).finished(), g = Vector::Constant(1, s.g);
  for (const char* name : kSolvers) {
    SCOPED_TRACE(name);
    auto solver = make_contact_solver(name, s.K, s.N, g);
    Vector u, lambda;
    const ContactReport rep = solver->solve(F, u, lambda);
    ASSERT_TRUE(rep.converged);
    EXPECT_EQ(rep.n_active, 1);
    EXPECT_NEAR(lambda[0], 0.9, 1e-12);
    EXPECT_NEAR(rep.total_force, 0.9, 1e-12);
    EXPECT_NEAR(u[0], 0.3, 1e-12);
    // The active-set solution is exact up to the two solves with K; penalty–duality
    // approaches the obstacle to its tolerance.
    EXPECT_NEAR(u[1], s.g, std::string(name) == "active-set" ? 1e-15 : 1e-11);
    EXPECT_LE(rep.residuals.max(), 1e-10);
    const ContactResiduals r = residuals(s.K, s.N, F, g, u, lambda);
    EXPECT_LE(r.max(), 1e-10);
    EXPECT_NEAR(r.equilibrium, rep.residuals.equilibrium, 1e-16);
  }
}

// contact_residuals must actually detect each violated condition (else the ≤ 1e-10
// checks above and below would be vacuous).
TEST(ContactSolver, ResidualsDetectEachViolation) {
  const Springs s;
  const Vector F = (Vector(2) << 0, 1.5).finished(), g = Vector::Constant(1, s.g);
  const Vector u = (Vector(2) << 0.3, 0.5).finished();
  const Vector lambda = Vector::Constant(1, 0.9);
  EXPECT_LE(residuals(s.K, s.N, F, g, u, lambda).max(), 1e-14);
  EXPECT_GT(residuals(s.K, s.N, F, g, u, Vector::Constant(1, 1.0)).equilibrium, 1e-3);
  const Vector u_pen = (Vector(2) << 0.3, 0.6).finished();
  EXPECT_GT(residuals(s.K, s.N, F, g, u_pen, lambda).penetration, 1e-3);
  EXPECT_GT(residuals(s.K, s.N, F, g, u, Vector::Constant(1, -0.9)).negative_force, 1e-3);
  // λ > 0 with a gap left: complementarity fails.
  const Vector u_gap = (Vector(2) << 0.3, 0.4).finished();
  EXPECT_GT(residuals(s.K, s.N, F, g, u_gap, lambda).complementarity, 1e-3);
}

// Normal compliance λ = c (u2 − g)₊ on the springs: with F pushing the tip past g,
// k_s u2 = F − λ gives u2 = (F + c g) / (k_s + c), λ = c (F/k_s − g) k_s / (k_s + c);
// as c → ∞ it tends to Signorini's λ = F − k_s g.
TEST(ContactSolver, NormalComplianceSprings) {
  const Springs s;
  const Vector F = (Vector(2) << 0, 1.5).finished();
  const double ks = s.k_series();
  auto K = std::make_shared<const la::SparseOperator>(s.K);
  std::shared_ptr<la::LinearSolver> factor = la::make_cholmod_factor();
  factor->factorize(*K, "springs");
  for (double c : {0.5, 10.0, 1e12}) {
    SCOPED_TRACE(c);
    ContactConstraints cc;
    cc.m = 1;
    cc.rows = {0};
    cc.N = s.N;
    cc.gap = Vector::Constant(1, s.g);
    set_law(cc, std::make_shared<const NormalComplianceLaw>(c, 1.0), Vector::Constant(1, c));
    auto solver = make_contact_solver("active-set", K, factor, cc, la::make_cholmod_factor);
    Vector u, lambda;
    const ContactReport rep = solver->solve(F, u, lambda);
    ASSERT_TRUE(rep.converged);
    EXPECT_LE(rep.residuals.max(), 1e-12);
    EXPECT_NEAR(u[1], (F[1] + c * s.g) / (ks + c), 1e-12);
    EXPECT_NEAR(lambda[0], c * (F[1] - ks * s.g) / (ks + c), 1e-10);
    EXPECT_GT(u[1], s.g);  // the law lets the tip in
  }
  ContactConstraints cc;
  cc.m = 1;
  cc.rows = {0};
  cc.N = s.N;
  cc.gap = Vector::Constant(1, s.g);
  set_law(cc, std::make_shared<const NormalComplianceLaw>(1.0, 1.0), Vector::Constant(1, 1.0));
  const std::string msg = error_of([&] { make_contact_solver("penalty-duality", K, factor, cc, la::make_cholmod_factor); });
  EXPECT_NE(msg.find("normal compliance needs 'active-set'"), std::string::npos) << msg;
}

// A power law λ = c (u2 − g)₊^e on the springs (semismooth Newton on the dual,
// solve_compliance_dual): k_s u2 + c (u2 − g)^e = F, solved here by bisection; the
// residuals measure the gap left as g − u2 + (λ/c)^{1/e}.
TEST(ContactSolver, PowerLawComplianceSprings) {
  const Springs s;
  const Vector F = (Vector(2) << 0, 1.5).finished();
  const double ks = s.k_series();
  auto K = std::make_shared<const la::SparseOperator>(s.K);
  std::shared_ptr<la::LinearSolver> factor = la::make_cholmod_factor();
  factor->factorize(*K, "springs");
  for (double e : {1.5, 2.0, 3.0})
    for (double c : {0.5, 10.0, 1e8}) {
      SCOPED_TRACE(fmt::format("e = {}, c = {}", e, c));
      double lo = s.g, hi = F[1] / ks;  // ks u + c (u − g)^e − F changes sign on [g, F/ks]
      for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        (ks * mid + c * std::pow(mid - s.g, e) > F[1] ? hi : lo) = mid;
      }
      ContactConstraints cc;
      cc.m = 1;
      cc.rows = {0};
      cc.N = s.N;
      cc.gap = Vector::Constant(1, s.g);
      set_law(cc, std::make_shared<const NormalComplianceLaw>(c, e), Vector::Constant(1, c));
      auto solver = make_contact_solver("active-set", K, factor, cc, la::make_cholmod_factor);
      EXPECT_NE(solver->describe().find("semismooth Newton"), std::string::npos);
      Vector u, lambda;
      const ContactReport rep = solver->solve(F, u, lambda);
      ASSERT_TRUE(rep.converged);
      EXPECT_LE(rep.residuals.max(), 1e-12);
      EXPECT_NEAR(u[1], lo, 1e-12);
      EXPECT_NEAR(lambda[0], c * std::pow(u[1] - s.g, e), 1e-10 * lambda[0]);
      // A wrong λ is seen: the gap left (λ/c)^{1/e} − (u2 − g) is not 0.
      cc.gap = Vector::Constant(1, s.g);
      EXPECT_GT(contact_residuals(*K, cc, F, u, Vector(1.01 * lambda)).max(), 1e-6);
    }
}

// solve_compliance_dual with Signorini, linear and power-law rows together agrees
// with the box QP where every row is linear or Signorini, and meets each row's law.
TEST(ComplianceDual, MixedRowsMeetTheirLaws) {
  const int m = 6;
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(m, m);
  const Eigen::MatrixXd S = A * A.transpose() + m * Eigen::MatrixXd::Identity(m, m);
  const Vector b = (Vector(m) << 1.0, -0.5, 2.0, 0.3, -1.0, 1.5).finished();
  const Vector compliance = (Vector(m) << 0, 0.1, 0.2, 0, 0.5, 0.05).finished();
  Vector lambda_qp = Vector::Zero(m), lambda = Vector::Zero(m);
  // Each row's law: Signorini where the compliance is 0, else normal compliance of exponent e_i.
  std::vector<std::shared_ptr<const ContactLaw>> owned;
  auto laws = [&](const Vector& e) {
    std::vector<const ContactLaw*> l;
    for (int i = 0; i < m; ++i)
      l.push_back(compliance[i] == 0 ? signorini_law().get()
                                     : owned.emplace_back(std::make_shared<const NormalComplianceLaw>(1 / compliance[i], e[i])).get());
    return l;
  };
  Eigen::MatrixXd H = S;
  H.diagonal() += compliance;
  DenseBoxQpOperator op(H);
  ASSERT_TRUE(solve_box_qp(op, b, Vector::Zero(m), Vector::Constant(m, INFINITY), lambda_qp).converged);
  ASSERT_TRUE(solve_compliance_dual(S, b, laws(Vector::Ones(m)), compliance, lambda).converged);
  EXPECT_LE((lambda - lambda_qp).cwiseAbs().maxCoeff(), 1e-12);
  const Vector exponent = (Vector(m) << 1, 2, 1.5, 1, 3, 2.5).finished();
  const BoxQpResult r = solve_compliance_dual(S, b, laws(exponent), compliance, lambda);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.iterations, 30);
  const Vector d = b - S * lambda;  // the penetration
  for (int i = 0; i < m; ++i) {
    SCOPED_TRACE(i);
    EXPECT_GE(lambda[i], 0);
    if (compliance[i] == 0) {
      EXPECT_LE(d[i], 1e-13);
      EXPECT_LE(std::abs(lambda[i] * d[i]), 1e-13);
    } else {
      EXPECT_NEAR(lambda[i], std::pow(std::max(d[i], 0.0), exponent[i]) / compliance[i], 1e-12 * (1 + lambda[i]));
    }
  }
  EXPECT_GT((lambda.array() > 0).count(), 1);
  EXPECT_LT((lambda.array() > 0).count(), m);
}

// ---------------------------------------------------------------- 2D elastic block

/// (0, 2) × (0, 1), plane strain E = 1, ν = 0.3, clamped on "top", body force
/// (0, −1): the base moves down. One contact row per "bottom" node, direction
/// (0, −1); the gap grows linearly in x, so the left part of the base touches.
struct Block {
  Mesh mesh;
  DofMap dofs;
  SparseMatrix K, N;
  Vector F, g;
  std::vector<int> bottom;
};

Block make_block() {
  Block b;
  b.mesh = make_rectangle({0, 0, 0}, {2, 1, 0}, 16, 8);
  const auto geo = compute_geometry(b.mesh);
  b.dofs = DofMap(b.mesh.n_nodes(), 2, b.mesh.nodes_of_parts({"top"}));
  b.K = assemble_stiffness(b.mesh, geo, Elasticity(Elasticity::Kind::PlaneStrain, 1, 0.3), b.dofs);
  const VectorField f0 = [](const Point&, double) { return Point{0, -1, 0}; };
  b.F = restrict_to_free(b.dofs, assemble_load(b.mesh, geo, {}, f0, nullptr, 0.0));
  b.bottom = b.mesh.nodes_of_parts({"bottom"});
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < static_cast<int>(b.bottom.size()); ++r)
    t.emplace_back(r, b.dofs.free_index(b.dofs.full_index(b.bottom[r], 1)), -1.0);
  b.N.resize(static_cast<Eigen::Index>(b.bottom.size()), b.dofs.n_free());
  b.N.setFromTriplets(t.begin(), t.end());
  // Gap from the free deflection d: from 0.2 d (x = 0) to 1.2 d (x = 2).
  auto f = la::make_cholmod_factor();
  f->factorize(la::SparseOperator(b.K), "block stiffness");
  const double d = (b.N * solve_with(*f, b.F)).maxCoeff();
  b.g.resize(static_cast<Eigen::Index>(b.bottom.size()));
  for (int r = 0; r < b.g.size(); ++r) b.g[r] = d * (0.2 + 0.5 * b.mesh.node(b.bottom[r])[0]);
  return b;
}

// Both methods solve the same inequality: same u and λ to 1e-8, residuals ≤ 1e-10,
// and a genuine free boundary (active set a strict, non-empty subset of the base).
TEST(ContactSolver, ElasticBlockActiveSetAndPenaltyDualityAgree) {
  const Block b = make_block();
  const int m = static_cast<int>(b.N.rows());
  Vector u[2], lambda[2];
  ContactReport rep[2];
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(kSolvers[s]);
    auto solver = make_contact_solver(kSolvers[s], b.K, b.N, b.g);
    rep[s] = solver->solve(b.F, u[s], lambda[s]);
    ASSERT_TRUE(rep[s].converged) << rep[s].iterations << " iterations";
    EXPECT_LE(rep[s].residuals.max(), 1e-10);
    EXPECT_LE(residuals(b.K, b.N, b.F, b.g, u[s], lambda[s]).max(), 1e-10);
  }
  EXPECT_GT(rep[0].n_active, 0);
  EXPECT_LT(rep[0].n_active, m);
  const double us = u[0].cwiseAbs().maxCoeff(), ls = lambda[0].cwiseAbs().maxCoeff();
  EXPECT_LE((u[1] - u[0]).cwiseAbs().maxCoeff(), 1e-8 * us);
  EXPECT_LE((lambda[1] - lambda[0]).cwiseAbs().maxCoeff(), 1e-8 * ls);
  EXPECT_NEAR(rep[1].total_force, rep[0].total_force, 1e-8 * std::abs(rep[0].total_force));
  // Active-set: exact complementarity — touching nodes sit on the obstacle (to the
  // round-off of two solves with K), the others carry exactly λ = 0.
  const Vector s = b.g - b.N * u[0];
  int n_touching = 0;
  for (int i = 0; i < m; ++i) {
    EXPECT_GE(lambda[0][i], 0.0);
    if (lambda[0][i] > 0) {
      EXPECT_NEAR(s[i], 0.0, 1e-12 * us);
      ++n_touching;
    } else {
      EXPECT_GE(s[i], -1e-14 * us);
    }
  }
  EXPECT_EQ(n_touching, rep[0].n_active);
  // The gap grows with x: the touching part is on the left.
  EXPECT_GT(lambda[0][0], 0.0);
  EXPECT_EQ(lambda[0][m - 1], 0.0);
}

// Issue 26 item 4: a layer one element thick, clamped on top, pressed onto a zero gap: every
// free node is a contact node, all of them touch, and the exact u is 0. The dual solver's u =
// K⁻¹(F − Nᵀλ) is 0 to round-off; measured against max(‖u‖, ‖g‖), that round-off itself, its
// penetration and complementarity were ~1 and the step failed. It must agree with the primal
// solver (which fixes the touching dofs exactly) to round-off, residuals included.
TEST(ContactSolver, EveryFreeNodeInContactDualAgreesWithPrimal) {
  const Mesh mesh = make_rectangle({0, 0, 0}, {10, 0.1, 0}, 100, 1);
  const auto geo = compute_geometry(mesh);
  const DofMap dofs(mesh.n_nodes(), 2, mesh.nodes_of_parts({"top"}));
  const SparseMatrix K = assemble_stiffness(mesh, geo, Elasticity(Elasticity::Kind::PlaneStrain, 100, 0.3), dofs);
  const VectorField f0 = [](const Point&, double) { return Point{0, -0.5, 0}; };
  const Vector F = restrict_to_free(dofs, assemble_load(mesh, geo, {}, f0, nullptr, 0.0));
  const std::vector<int> bottom = mesh.nodes_of_parts({"bottom"});
  ASSERT_EQ(2 * static_cast<int>(bottom.size()), dofs.n_free());  // every free node is a contact node
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < static_cast<int>(bottom.size()); ++r)
    t.emplace_back(r, dofs.free_index(dofs.full_index(bottom[r], 1)), -1.0);
  SparseMatrix N(static_cast<Eigen::Index>(bottom.size()), dofs.n_free());
  N.setFromTriplets(t.begin(), t.end());
  const Vector g = Vector::Zero(N.rows());
  const char* const names[] = {"primal-active-set", "active-set", "penalty-duality"};
  Vector u[3], lambda[3];
  for (int s = 0; s < 3; ++s) {
    SCOPED_TRACE(names[s]);
    const ContactReport rep = make_contact_solver(names[s], K, N, g)->solve(F, u[s], lambda[s]);
    ASSERT_TRUE(rep.converged);
    EXPECT_EQ(rep.n_active, N.rows());
    EXPECT_LE(rep.residuals.max(), s == 2 ? 1e-10 : 1e-13) << contact_failure(rep, 0);
    EXPECT_EQ(contact_failure(rep, 1e-8), "");
  }
  // The primal solution: u = 0 exactly, λ the nodal loads.
  EXPECT_EQ(u[0].cwiseAbs().maxCoeff(), 0.0);
  const double ls = lambda[0].cwiseAbs().maxCoeff(), us = ls / K.diagonal().maxCoeff();
  for (int s = 1; s < 3; ++s) {
    EXPECT_LE((lambda[s] - lambda[0]).cwiseAbs().maxCoeff(), (s == 1 ? 1e-13 : 1e-9) * ls) << names[s];
    EXPECT_LE(u[s].cwiseAbs().maxCoeff(), (s == 1 ? 1e-13 : 1e-9) * us) << names[s];
  }
}

// A moving obstacle: after set_gap, a solver answers as one made with that gap
// (nothing it set up from K and N depends on g), for both methods.
TEST(ContactSolver, SetGapSolvesWithTheNewGap) {
  const Block b = make_block();
  const Vector g2 = 0.5 * b.g;  // the obstacle moved up: more of the base touches
  for (const char* name : kSolvers) {
    SCOPED_TRACE(name);
    auto moved = make_contact_solver(name, b.K, b.N, b.g);
    auto fresh = make_contact_solver(name, b.K, b.N, g2);
    Vector u0, l0, u1, l1;
    const ContactReport before = moved->solve(b.F, u0, l0);
    moved->set_gap(g2);
    const ContactReport after = moved->solve(b.F, u0, l0);
    const ContactReport ref = fresh->solve(b.F, u1, l1);
    ASSERT_TRUE(after.converged && ref.converged);
    EXPECT_LE(after.residuals.max(), 1e-10);
    EXPECT_GT(after.n_active, before.n_active);
    EXPECT_LE((u0 - u1).cwiseAbs().maxCoeff(), 1e-8 * u1.cwiseAbs().maxCoeff());
    EXPECT_LE((l0 - l1).cwiseAbs().maxCoeff(), 1e-8 * l1.cwiseAbs().maxCoeff());
    EXPECT_THROW(moved->set_gap(Vector::Zero(3)), Error);
  }
}

/// The nodes counted as active: λ_i above the report's threshold.
std::vector<int> active_nodes(const Vector& lambda, const ContactReport& rep) {
  std::vector<int> a;
  for (int i = 0; i < lambda.size(); ++i)
    if (lambda[i] > rep.active_threshold) a.push_back(i);
  return a;
}

// Issue 11 item 12: penalty–duality's multiplier is small but not zero off the
// contact zone; counted against its own tolerance, both solvers report the same set.
TEST(ContactSolver, BothSolversReportTheSameActiveSet) {
  const Block b = make_block();
  Vector u[2], lambda[2];
  ContactReport rep[2];
  for (int s = 0; s < 2; ++s) {
    auto solver = make_contact_solver(kSolvers[s], b.K, b.N, b.g);
    rep[s] = solver->solve(b.F, u[s], lambda[s]);
    ASSERT_TRUE(rep[s].converged);
  }
  EXPECT_EQ(rep[0].active_threshold, 0.0);
  EXPECT_GT(rep[1].active_threshold, 0.0);
  EXPECT_LT(rep[1].active_threshold, 1e-10 * lambda[1].cwiseAbs().maxCoeff());
  EXPECT_GT(rep[0].n_active, 0);
  EXPECT_EQ(rep[1].n_active, rep[0].n_active);
  EXPECT_EQ(active_nodes(lambda[1], rep[1]), active_nodes(lambda[0], rep[0]));
}

// The active-set method keeps Y = L⁻¹PNᵀ (one solve per step, in two halves)
// unless it is too large; without it a step costs two full solves. Both give the
// same contact solution to round-off.
TEST(ContactSolver, ActiveSetWithAndWithoutCachedForwardSolvesAgree) {
  const Block b = make_block();
  ContactSolverOptions uncached;
  uncached.max_cached_share = 0;
  Vector u[2], lambda[2];
  int k = 0;
  for (const ContactSolverOptions& opt : {ContactSolverOptions{}, uncached}) {
    auto solver = make_contact_solver("active-set", b.K, b.N, b.g, opt);
    const ContactReport rep = solver->solve(b.F, u[k], lambda[k]);
    ASSERT_TRUE(rep.converged);
    EXPECT_LE(rep.residuals.max(), 1e-11);
    ++k;
  }
  EXPECT_GT(lambda[0].maxCoeff(), 0.0);
  EXPECT_LE((u[1] - u[0]).cwiseAbs().maxCoeff(), 1e-12 * u[0].cwiseAbs().maxCoeff());
  EXPECT_LE((lambda[1] - lambda[0]).cwiseAbs().maxCoeff(), 1e-10 * lambda[0].cwiseAbs().maxCoeff());
}

// The two halves of a CHOLMOD solve: A⁻¹ = backward ∘ forward, and
// B₁ᵀA⁻¹B₂ = forward(B₁)ᵀ forward(B₂) (what S = N K⁻¹Nᵀ = YᵀY relies on).
TEST(CholmodFactor, ForwardAndBackwardHalvesComposeToTheSolve) {
  const Block b = make_block();
  const auto factor = la::make_cholmod_factor();
  factor->factorize(la::SparseOperator(b.K), "test stiffness");
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(b.K.rows(), 3);
  const Eigen::MatrixXd X = factor->solve(B);
  EXPECT_LE((factor->backward(factor->forward(B)) - X).norm(), 1e-12 * X.norm());
  const Eigen::MatrixXd Y = factor->forward(B);
  const Eigen::MatrixXd G = B.transpose() * X;
  EXPECT_LE((Y.transpose() * Y - G).norm(), 1e-12 * G.norm());
  EXPECT_LE((b.K * X - B).norm(), 1e-10 * B.norm());
}

// Warm start: solving again from the returned λ does no reduced solve at all
// (its dual box QP is already at KKT), and gives the same u and λ.
TEST(ContactSolver, ActiveSetWarmStartStopsAtOnce) {
  const Block b = make_block();
  auto solver = make_contact_solver("active-set", b.K, b.N, b.g);
  Vector u, lambda;
  const ContactReport cold = solver->solve(b.F, u, lambda);
  ASSERT_TRUE(cold.converged);
  EXPECT_GT(cold.iterations, 1);
  const Vector l0 = lambda, u0 = u;
  const ContactReport warm = solver->solve(b.F, u, lambda);
  EXPECT_TRUE(warm.converged);
  EXPECT_EQ(warm.iterations, 0);
  EXPECT_EQ(lambda, l0);
  EXPECT_EQ(u, u0);
  EXPECT_EQ(warm.n_active, cold.n_active);
}

// Regression: the solvers once kept a reference to the caller's K (for the
// reported residuals); a caller reusing or destroying its matrix corrupted the
// report or left the reference dangling. They now own a copy.
TEST(ContactSolver, DoesNotDependOnCallersStiffnessAfterConstruction) {
  const Springs s;
  const Vector F = (Vector(2) << 0, 1.5).finished(), g = Vector::Constant(1, s.g);
  for (const char* name : kSolvers) {
    SCOPED_TRACE(name);
    SparseMatrix K = s.K;
    auto solver = make_contact_solver(name, K, s.N, g);
    K = 2.0 * s.K;  // the caller's variable is reused; the solver was built for s.K
    Vector u, lambda;
    const ContactReport rep = solver->solve(F, u, lambda);
    ASSERT_TRUE(rep.converged);
    EXPECT_NEAR(lambda[0], 0.9, 1e-10);  // the solution itself is right...
    EXPECT_LE(rep.residuals.max(), 1e-10) << "equilibrium residual " << rep.residuals.equilibrium
                                          << ": the report was computed with the caller's new K";
  }
}

/// CHOLMOD with its triangular halves hidden, as MUMPS and CG are: the active-set
/// solver must then take its block-solve path (W = K⁻¹Nᵀ kept, or two solves).
class FactorWithoutHalves final : public la::LinearSolver {
 public:
  void factorize(const la::SpdOperator& A, const char* what) override { f_->factorize(A, what); }
  void solve(const Vector& b, Vector& x) const override { f_->solve(b, x); }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const override { return f_->solve(B); }
  int n_factorizations() const override { return f_->n_factorizations(); }

 private:
  std::unique_ptr<la::LinearSolver> f_ = la::make_cholmod_factor();
};

/// The block's contact problem over la/ on one process, with the given factor of K.
std::unique_ptr<ContactSolver> block_solver(const Block& b, std::shared_ptr<la::LinearSolver> factor,
                                            const ContactSolverOptions& opt = {}) {
  auto K = std::make_shared<const la::SparseOperator>(b.K);
  factor->factorize(*K, "block stiffness");
  ContactConstraints c;
  c.m = static_cast<int>(b.N.rows());
  c.N = b.N;
  c.gap = b.g;
  for (int i = 0; i < c.m; ++i) c.rows.push_back(i);
  return make_contact_solver("active-set", K, std::move(factor), std::move(c), la::make_cholmod_factor, opt);
}

// Without halves (MUMPS, CG): S from block solves, a step u = u_free − Wλ (W kept)
// or two solves; the same solution as the halves' path to round-off, each path
// saying what it does.
TEST(ContactSolver, ActiveSetWithoutHalvesAgreesWithTheHalves) {
  const Block b = make_block();
  ContactSolverOptions uncached;
  uncached.max_cached_share = 0;
  struct Path {
    std::unique_ptr<ContactSolver> solver;
    const char* says;
  } paths[] = {{block_solver(b, la::make_cholmod_factor()), "one solve per step (K's halves)"},
               {block_solver(b, std::make_shared<FactorWithoutHalves>()), "one solve per step (K⁻¹Nᵀ kept)"},
               {block_solver(b, std::make_shared<FactorWithoutHalves>(), uncached), "two solves per step"}};
  Vector u[3], lambda[3];
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(paths[k].says);
    EXPECT_EQ(paths[k].solver->describe(), paths[k].says);
    const ContactReport rep = paths[k].solver->solve(b.F, u[k], lambda[k]);
    ASSERT_TRUE(rep.converged);
    EXPECT_LE(rep.residuals.max(), 1e-11);
    EXPECT_LE((u[k] - u[0]).cwiseAbs().maxCoeff(), 1e-12 * u[0].cwiseAbs().maxCoeff());
    EXPECT_LE((lambda[k] - lambda[0]).cwiseAbs().maxCoeff(), 1e-10 * lambda[0].cwiseAbs().maxCoeff());
  }
  EXPECT_GT(lambda[0].maxCoeff(), 0.0);
}

// Penalty–duality's warm state is its multiplier, m numbers: a solver given another's
// state starts where that one stopped (one iteration), an empty state starts cold.
TEST(ContactSolver, PenaltyDualityWarmStateCarriesTheMultiplier) {
  const Block b = make_block();
  auto first = make_contact_solver("penalty-duality", b.K, b.N, b.g);
  EXPECT_EQ(first->warm_state().size(), 0);
  Vector u, lambda;
  const ContactReport cold = first->solve(b.F, u, lambda);
  ASSERT_TRUE(cold.converged);
  EXPECT_GT(cold.iterations, 5);
  ASSERT_EQ(first->warm_state().size(), b.N.rows());
  auto second = make_contact_solver("penalty-duality", b.K, b.N, b.g);
  second->set_warm_state(first->warm_state());
  Vector u2, lambda2;
  const ContactReport warm = second->solve(b.F, u2, lambda2);
  ASSERT_TRUE(warm.converged);
  EXPECT_LE(warm.iterations, 2);
  EXPECT_LE((lambda2 - lambda).cwiseAbs().maxCoeff(), 1e-9 * lambda.cwiseAbs().maxCoeff());
}

// ---------------------------------------------------------------- error paths

TEST(ContactSolverErrors, UnknownNameIsNamed) {
  const Springs s;
  const std::string msg = error_of([&] { make_contact_solver("magic", s.K, s.N, Vector::Constant(1, s.g)); });
  EXPECT_NE(msg.find("unknown contact solver 'magic'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("active-set"), std::string::npos) << msg;
}

TEST(ContactSolverErrors, NoContactRowsIsAnError) {
  const Springs s;
  const SparseMatrix N0(0, 2);
  for (const char* name : kSolvers) {
    const std::string msg = error_of([&] { make_contact_solver(name, s.K, N0, Vector()); });
    EXPECT_NE(msg.find("no contact unknowns"), std::string::npos) << name << ": " << msg;
  }
}

// CHOLMOD must refuse a matrix that is not positive definite — singular (a body
// not clamped) or indefinite — with a vpc::Error naming the matrix.
TEST(ContactSolverErrors, CholmodRejectsNonPositiveDefinite) {
  const SparseMatrix singular = sparse((Eigen::MatrixXd(2, 2) << 1, -1, -1, 1).finished());
  const SparseMatrix indefinite = sparse((Eigen::MatrixXd(2, 2) << 1, 0, 0, -1).finished());
  for (const SparseMatrix* A : {&singular, &indefinite}) {
    auto f = la::make_cholmod_factor();
    const std::string msg = error_of([&] { f->factorize(la::SparseOperator(*A), "unclamped stiffness"); });
    EXPECT_NE(msg.find("unclamped stiffness"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not positive definite"), std::string::npos) << msg;
    EXPECT_EQ(f->n_factorizations(), 0);
  }
}

// Regression: a singular positive semidefinite matrix (the P1 Laplacian of an
// unclamped bar, kernel = constants) factorizes with a round-off-sized positive
// last pivot, which CHOLMOD's "pivot <= 0" test accepts; solves then return
// values of order 1e15. factorize also rejects a tiny cholmod_rcond. (Which
// sizes slip through the positivity test depends on round-off, hence several.)
TEST(ContactSolverErrors, CholmodRejectsRoundoffSingularMatrix) {
  for (int n : {20, 40, 80, 160, 320}) {
    const Mesh m = make_interval(0, 1, n);
    const SparseMatrix A = assemble_laplacian(m, compute_geometry(m));  // no boundary row dropped
    auto f = la::make_cholmod_factor();
    const std::string msg = error_of([&] { f->factorize(la::SparseOperator(A), "free bar"); });
    EXPECT_NE(msg.find("not positive definite"), std::string::npos) << "n = " << n << ": " << msg;
  }
}

}  // namespace
}  // namespace vpc
