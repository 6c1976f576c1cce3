// Assembly: exact integrals of the P1 matrices and loads, and patch tests — a
// constant strain state is reproduced exactly in 2D and 3D on distorted meshes.
#include "fem/assembly.hpp"
#include "../solve_with.hpp"
#include "mesh/generators.hpp"
#include "la/linear_solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vpc {
namespace {

/// Moves interior nodes randomly (boundary nodes stay, so the domain is unchanged).
void distort(Mesh& m, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-amount, amount);
  std::vector<char> on_boundary(m.n_nodes(), 0);
  for (int f = 0; f < m.n_facets(); ++f)
    for (int a = 0; a < m.nodes_per_facet(); ++a) on_boundary[m.facet(f)[a]] = 1;
  for (int i = 0; i < m.n_nodes(); ++i)
    if (!on_boundary[i])
      for (int j = 0; j < m.dim(); ++j) m.nodes()[i][j] += U(rng);
}

TEST(Assembly, MassAndLaplacianIntegrals) {
  Mesh m = make_rectangle({0, 0, 0}, {2, 3, 0}, 6, 5);
  distort(m, 0.05, 1);
  const auto geo = compute_geometry(m);
  const SparseMatrix M = assemble_mass(m, geo), A = assemble_laplacian(m, geo);
  const Vector one = Vector::Ones(m.n_nodes());
  EXPECT_NEAR(one.dot(M * one), 6.0, 1e-12);            // ∫ 1 = |Ω|
  EXPECT_NEAR((A * one).cwiseAbs().maxCoeff(), 0, 1e-12);  // ∇1 = 0
  Vector x(m.n_nodes());
  for (int i = 0; i < m.n_nodes(); ++i) x[i] = m.node(i)[0];
  EXPECT_NEAR(x.dot(A * x), 6.0, 1e-12);                 // ∫ |∇x|² = |Ω|
  EXPECT_NEAR(x.dot(M * x), 6.0 * 4.0 / 3.0, 1e-12);     // ∫ x² = 3 · 8/3
}

TEST(Assembly, LoadIntegratesLinearFieldsExactly) {
  Mesh m = make_box({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  distort(m, 0.05, 2);
  const auto geo = compute_geometry(m);
  const VectorField f0 = [](const Point& x, double t) { return Point{t * x[0], 1.0, x[2]}; };
  const Vector F = assemble_load(m, geo, {}, f0, nullptr, 2.0);
  // Σ_i F_(i, c) = ∫ f_c: ∫ 2x = 1, ∫ 1 = 1, ∫ z = 1/2.
  double s[3] = {0, 0, 0};
  for (int i = 0; i < m.n_nodes(); ++i)
    for (int c = 0; c < 3; ++c) s[c] += F[i * 3 + c];
  EXPECT_NEAR(s[0], 1.0, 1e-13);
  EXPECT_NEAR(s[1], 1.0, 1e-13);
  EXPECT_NEAR(s[2], 0.5, 1e-13);
  // Σ_i x_i F_(i, 1) = ∫ x · 1 = 1/2 (exact: the rule integrates x·λ_a exactly).
  double mx = 0;
  for (int i = 0; i < m.n_nodes(); ++i) mx += m.node(i)[0] * F[i * 3 + 1];
  EXPECT_NEAR(mx, 0.5, 1e-13);
}

TEST(Assembly, TractionOnBoundaryPart) {
  const Mesh m = make_rectangle({0, 0, 0}, {2, 1, 0}, 4, 2);
  const auto geo = compute_geometry(m);
  const VectorField f2 = [](const Point& x, double) { return Point{0, x[0], 0}; };
  const Vector F = assemble_load(m, geo, m.facets_of_parts({"top"}), nullptr, f2, 0.0);
  double s = 0;
  for (int i = 0; i < m.n_nodes(); ++i) s += F[i * 2 + 1];
  EXPECT_NEAR(s, 2.0, 1e-14);  // ∫_0^2 x dx
}

/// Patch test: clamp the face {x_d = 0} (last coordinate), apply the tractions of
/// a constant stress σ̄ = ℰε̄ on the other faces and check that u = G x_d is
/// reproduced exactly, G chosen so that u vanishes on the clamped face.
void patch_test(Mesh m, const Elasticity& E, const std::string& clamped, const std::vector<double>& g) {
  const int d = m.dim();
  distort(m, 0.3 / 4, 7);
  const auto geo = compute_geometry(m);
  const DofMap dofs(m.n_nodes(), d, m.nodes_of_parts({clamped}));
  const SparseMatrix K = assemble_stiffness(m, geo, E, dofs);
  // ε̄ = sym(g ⊗ e_d).
  SymTensor eps;
  const int last = d - 1;
  for (int i = 0; i < d; ++i) {
    if (i == last) {
      eps[last] = g[i];
    } else {
      const int k = 3 - i - last;  // index of the shear component (i, last)
      eps[3 + k] = 0.5 * g[i];
    }
  }
  const SymTensor sig = E.apply(eps);
  std::vector<int> traction;
  for (int f = 0; f < m.n_facets(); ++f)
    if (m.part_names()[m.facet_part(f)] != clamped) traction.push_back(f);
  // f2 = σ̄ ν, with ν from the facet containing x: found by the face the point lies on.
  const Point lo{0, 0, 0}, hi{2, 2, 2};
  const VectorField f2 = [&](const Point& x, double) {
    Point n{0, 0, 0};
    for (int a = 0; a < d; ++a) {
      if (std::abs(x[a] - lo[a]) < 1e-12) n[a] = -1;
      if (std::abs(x[a] - hi[a]) < 1e-12) n[a] = 1;
    }
    Point t{0, 0, 0};
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) t[i] += sig(i, j) * n[j];
    return t;
  };
  const Vector F = restrict_to_free(dofs, assemble_load(m, geo, traction, nullptr, f2, 0.0));
  auto solver = la::make_cholmod_factor();
  solver->factorize(la::SparseOperator(K), "K");
  const Vector u = extend_from_free(dofs, solve_with(*solver, F));
  for (int i = 0; i < m.n_nodes(); ++i)
    for (int c = 0; c < d; ++c) ASSERT_NEAR(u[i * d + c], g[c] * m.node(i)[last], 1e-11) << "node " << i;
  std::vector<SymTensor> strain;
  compute_strain(m, geo, u, strain);
  for (const auto& e : strain)
    for (int k = 0; k < 6; ++k) ASSERT_NEAR(e[k], eps[k], 1e-11);
}

TEST(Assembly, PatchTestPlaneStress) {
  patch_test(make_rectangle({0, 0, 0}, {2, 2, 0}, 4, 4), Elasticity(Elasticity::Kind::PlaneStress, 1000, 0.3),
             "bottom", {0.3, -0.2});
}

TEST(Assembly, PatchTestPlaneStrain) {
  patch_test(make_rectangle({0, 0, 0}, {2, 2, 0}, 4, 4), Elasticity(Elasticity::Kind::PlaneStrain, 7, 0.45),
             "bottom", {-0.1, 0.25});
}

TEST(Assembly, PatchTest3D) {
  patch_test(make_box({0, 0, 0}, {2, 2, 2}, 4, 4, 4), Elasticity(Elasticity::Kind::Isotropic, 1000, 0.3), "bottom",
             {0.1, -0.2, 0.3});
}

TEST(Assembly, StressDivergenceIsTransposeOfStrain) {
  // (τ, ε(v)) assembled as a vector equals τ : ε(v) integrated, for any v.
  Mesh m = make_rectangle({0, 0, 0}, {1, 1, 0}, 3, 3);
  distort(m, 0.05, 3);
  const auto geo = compute_geometry(m);
  std::vector<SymTensor> tau(m.n_cells());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  for (auto& t : tau) t = SymTensor{{U(rng), U(rng), 0, 0, 0, U(rng)}};
  Vector v(m.n_nodes() * 2);
  for (int i = 0; i < v.size(); ++i) v[i] = U(rng);
  std::vector<SymTensor> ev;
  compute_strain(m, geo, v, ev);
  double direct = 0;
  for (int c = 0; c < m.n_cells(); ++c) direct += geo[c].volume * tau[c].dot(ev[c]);
  EXPECT_NEAR(assemble_stress_divergence(m, geo, tau).dot(v), direct, 1e-13);
}

TEST(Assembly, DegenerateCellIsAnError) {
  Mesh m(2);
  m.add_node({0, 0, 0});
  m.add_node({1, 0, 0});
  m.add_node({2, 0, 0});
  const int c[3] = {0, 1, 2};
  m.add_cell(c);
  EXPECT_THROW(compute_geometry(m), std::runtime_error);
}

}  // namespace
}  // namespace vpc
