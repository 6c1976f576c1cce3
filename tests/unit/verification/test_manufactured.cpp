// The pieces of the convergence studies that can be checked exactly: the error
// quadrature (exact integrals of monomials), the dual-number derivatives of the
// manufactured fields (against finite differences), the properties the manufactured
// solution is built to have (boundary conditions, inactive constraints), the
// consistency of its forcing, and zero error for fields the discrete spaces contain.
#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "mesh/generators.hpp"
#include "verification/manufactured.hpp"
#include "verification/norms.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace vpc {
namespace {

double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

TEST(ErrorQuadrature, ConicalProductRuleIsExactToDegree2mMinus1) {
  // ∫_T λ1^a λ2^b λ3^c / |T| = d! a! b! c! / (d + a + b + c)!.
  for (int d = 1; d <= 3; ++d)
    for (int m = 1; m <= 4; ++m) {
      const auto rule = conical_product_rule(d, m);
      ASSERT_EQ(static_cast<int>(rule.size()), static_cast<int>(std::pow(m, d)));
      const int deg = 2 * m - 1;
      for (int a = 0; a <= deg; ++a)
        for (int b = 0; b <= (d >= 2 ? deg - a : 0); ++b)
          for (int c = 0; c <= (d == 3 ? deg - a - b : 0); ++c) {
            double q = 0;
            for (const auto& p : rule) q += p.weight * std::pow(p.lambda[1], a) * std::pow(p.lambda[2], b) *
                                            std::pow(p.lambda[3], c);
            const double exact = factorial(d) * factorial(a) * factorial(b) * factorial(c) / factorial(d + a + b + c);
            EXPECT_NEAR(q, exact, 1e-14) << "d = " << d << " m = " << m << " a b c = " << a << b << c;
          }
      for (const auto& p : rule) {
        EXPECT_GT(p.weight, 0);
        for (int j = 0; j <= d; ++j) EXPECT_GE(p.lambda[j], 0);
      }
    }
}

Elasticity elasticity_for(int d) {
  return d == 1 ? Elasticity(Elasticity::Kind::Uniaxial, 1.0, 0.0)
                : d == 2 ? Elasticity(Elasticity::Kind::PlaneStress, 1.0, 0.3)
                         : Elasticity(Elasticity::Kind::Isotropic, 1.0, 0.3);
}

const Point kPoints[] = {{0.3, 0.6, 0.2}, {0.71, 0.15, 0.9}, {0.05, 0.95, 0.5}};

TEST(ManufacturedSolution, DualDerivativesMatchFiniteDifferences) {
  const double h = 1e-5;
  for (int d = 1; d <= 3; ++d) {
    const ManufacturedSolution ms(d, true, elasticity_for(d), 0.7);
    for (const Point& x : kPoints)
      for (double t : {0.2, 0.8}) {
        auto shifted = [&](int j, double s) {
          Point y = x;
          y[j] += s;
          return y;
        };
        const auto g = ms.grad_u(x, t);
        for (int j = 0; j < d; ++j) {
          const Point up = ms.u(shifted(j, h), t), um = ms.u(shifted(j, -h), t);
          for (int i = 0; i < d; ++i) EXPECT_NEAR(g[i][j], (up[i] - um[i]) / (2 * h), 1e-8);
          EXPECT_NEAR(ms.grad_beta(x, t)[j], (ms.beta(shifted(j, h), t) - ms.beta(shifted(j, -h), t)) / (2 * h), 1e-8);
        }
        EXPECT_NEAR(ms.beta_dot(x, t), (ms.beta(x, t + h) - ms.beta(x, t - h)) / (2 * h), 1e-8);
        const SymTensor zd = ms.z_dot(x, t), zp = ms.z(x, t + h), zm = ms.z(x, t - h);
        for (int c = 0; c < 6; ++c) EXPECT_NEAR(zd[c], (zp[c] - zm[c]) / (2 * h), 1e-8);
        // Δβ and f0 = −Div σ by differences of the first derivatives.
        const double hh = 1e-4;
        double lap = 0;
        Point div{0, 0, 0};
        for (int j = 0; j < d; ++j) {
          lap += (ms.grad_beta(shifted(j, hh), t)[j] - ms.grad_beta(shifted(j, -hh), t)[j]) / (2 * hh);
          const SymTensor sp = ms.sigma(shifted(j, hh), t), sm = ms.sigma(shifted(j, -hh), t);
          for (int i = 0; i < d; ++i) div[i] += (sp(i, j) - sm(i, j)) / (2 * hh);
        }
        EXPECT_NEAR(ms.laplacian_beta(x, t), lap, 1e-6);
        const Point f0 = ms.body_force(x, t);
        for (int i = 0; i < d; ++i) EXPECT_NEAR(f0[i], -div[i], 1e-6);
      }
  }
}

TEST(ManufacturedSolution, SatisfiesTheBoundaryConditionsAndKeepsConstraintsInactive) {
  for (int d = 1; d <= 3; ++d) {
    const ManufacturedSolution ms(d, true, elasticity_for(d), 1.0);
    for (double t : {0.0, 0.37, 1.0})
      for (double s : {0.0, 0.25, 0.5, 0.75, 1.0})
        for (double r : {0.0, 0.4, 1.0}) {
          const Point on_clamped{0, s, r}, on_contact{1, s, r}, inside{s, r, 0.5 * (s + r)};
          for (int i = 0; i < 3; ++i) EXPECT_NEAR(ms.u(on_clamped, t)[i], 0, 1e-15);  // (2.4)
          const SymTensor sc = ms.sigma(on_contact, t);                                // σν = 0 on Γ3
          for (int i = 0; i < 6; ++i) EXPECT_NEAR(sc[i], 0, 1e-14);
          EXPECT_LT(ms.u(on_contact, t)[0], 0.5 - 0.4);  // u_ν well below the gap g = 0.5
          const double b = ms.beta(inside, t);
          EXPECT_GE(b, 0.3 - 1e-12);  // the bounds of K stay inactive
          EXPECT_LE(b, 0.9 + 1e-12);
          // ∂β/∂ν = 0 on every side of the unit box (2.7).
          for (int j = 0; j < d; ++j)
            for (double side : {0.0, 1.0}) {
              Point y = inside;
              y[j] = side;
              EXPECT_NEAR(ms.grad_beta(y, t)[j], 0, 1e-14);
            }
        }
    // u0 = 0 and σ0 = 0: the scheme's initial data.
    for (const Point& x : kPoints) {
      for (int i = 0; i < 3; ++i) EXPECT_EQ(ms.u(x, 0)[i], 0);
      for (int i = 0; i < 6; ++i) EXPECT_EQ(ms.sigma(x, 0)[i], 0);
    }
  }
}

TEST(ManufacturedSolution, ForcingMakesTheExactFieldsSolveTheEquations) {
  const int d = 2;
  ManufacturedOptions o;
  o.dim = d;
  o.kappa = 0.7;
  for (auto forcing : {ManufacturedForcing::Continuous, ManufacturedForcing::Discrete}) {
    o.forcing = forcing;
    const Mesh mesh = manufactured_base_mesh(o);
    const int n_steps = 8;
    const ManufacturedCase mc = make_manufactured_case(o, mesh, n_steps);
    const double k = mc.problem->step();
    const ManufacturedSolution& ms = *mc.exact;
    for (const Point& x : kPoints)
      for (double t : {0.25, 0.5}) {
        const PointState s = ms.exact_state(x, t);
        const SymTensor G = mc.problem->law->rate(s);
        const double phi = mc.problem->source->rate(s);
        if (forcing == ManufacturedForcing::Continuous) {
          // ż = G_m and β̇ − κΔβ = φ_m on the exact fields.
          const SymTensor zd = ms.z_dot(x, t);
          for (int c = 0; c < 6; ++c) EXPECT_NEAR(G[c], zd[c], 1e-13);
          EXPECT_NEAR(phi, ms.beta_dot(x, t) - o.kappa * ms.laplacian_beta(x, t), 1e-13);
        } else {
          // z(t + k) = z(t) + k G_m(t) and (β(t + k) − β(t))/k − κΔβ(t + k) = φ_m(t): the
          // time-discrete scheme, with G and φ lagged, holds exactly.
          const SymTensor zn = ms.z(x, t) + k * G, ze = ms.z(x, t + k);
          for (int c = 0; c < 6; ++c) EXPECT_NEAR(zn[c], ze[c], 1e-14);
          EXPECT_NEAR(phi, (ms.beta(x, t + k) - ms.beta(x, t)) / k - o.kappa * ms.laplacian_beta(x, t + k), 1e-12);
        }
      }
  }
}

/// An exact solution that the discrete spaces contain: u affine, σ constant, β affine.
class AffineSolution final : public ExactSolution {
 public:
  Point u(const Point& x, double t) const override { return {t * (0.1 * x[0] + 0.2 * x[1]), t * 0.3 * x[0], 0}; }
  std::array<Point, 3> grad_u(const Point&, double t) const override {
    return {Point{0.1 * t, 0.2 * t, 0}, Point{0.3 * t, 0, 0}, Point{0, 0, 0}};
  }
  SymTensor sigma(const Point& x, double t) const override { return el.apply(eps(x, t)); }
  double beta(const Point& x, double t) const override { return 0.5 + 0.1 * x[0] - 0.2 * x[1] * t; }
  Point grad_beta(const Point&, double t) const override { return {0.1, -0.2 * t, 0}; }
  SymTensor eps(const Point&, double t) const {
    SymTensor e;
    e[0] = 0.1 * t;
    e[5] = 0.5 * (0.2 + 0.3) * t;
    return e;
  }
  Elasticity el{Elasticity::Kind::PlaneStrain, 2.0, 0.3};
};

TEST(ErrorsAgainstExact, VanishForFieldsInTheDiscreteSpaces) {
  const Mesh m = make_rectangle({0, 0, 0}, {1, 2, 0}, 3, 4);
  const auto geo = compute_geometry(m);
  const AffineSolution ex;
  const double t = 0.6;
  State s;
  s.u.resize(2 * m.n_nodes());
  s.beta.resize(m.n_nodes());
  for (int i = 0; i < m.n_nodes(); ++i) {
    const Point u = ex.u(m.node(i), t);
    s.u[2 * i] = u[0];
    s.u[2 * i + 1] = u[1];
    s.beta[i] = ex.beta(m.node(i), t);
  }
  compute_strain(m, geo, s.u, s.eps);
  for (const auto& e : s.eps) s.sigma.push_back(ex.el.apply(e));
  const FieldErrors e = errors_against_exact(m, geo, ex.el, s, ex, t, conical_product_rule(2, 3));
  EXPECT_LT(e.u_energy, 1e-14);
  EXPECT_LT(e.u_l2, 1e-14);
  EXPECT_LT(e.sigma_l2, 1e-14);
  EXPECT_LT(e.beta_l2, 1e-14);
  EXPECT_LT(e.beta_grad, 1e-14);
  // ... and measure a known perturbation exactly: β_h = β + 1 has |e_β|_L2 = |Ω|^{1/2}.
  s.beta.array() += 1.0;
  EXPECT_NEAR(errors_against_exact(m, geo, ex.el, s, ex, t, conical_product_rule(2, 3)).beta_l2, std::sqrt(2.0),
              1e-13);
}

TEST(ManufacturedCaseNames, ParseAndReject) {
  EXPECT_TRUE(is_manufactured_case_name("mms-elastic-2d"));
  EXPECT_FALSE(is_manufactured_case_name("paper-2d"));
  const auto o = manufactured_options_from_name("mms-maxwell-3d");
  EXPECT_EQ(o.dim, 3);
  EXPECT_EQ(o.law, "maxwell-damage");
  EXPECT_EQ(manufactured_options_from_name("mms-perzyna-1d").law, "perzyna");
  const auto ps = manufactured_options_from_name("mms-perzyna-von-mises-2d-plane-strain");
  EXPECT_EQ(ps.dim, 2);
  EXPECT_TRUE(ps.plane_strain);
  EXPECT_EQ(ps.law, "perzyna-von-mises");
  EXPECT_FALSE(manufactured_options_from_name("mms-perzyna-von-mises-2d").plane_strain);
  EXPECT_THROW(manufactured_options_from_name("mms-maxwell-3d-plane-strain"), Error);
  EXPECT_THROW(manufactured_options_from_name("mms-maxwell-4d"), Error);
  EXPECT_THROW(manufactured_options_from_name("mms-foo-2d"), Error);
  EXPECT_THROW(manufactured_forcing_from_name("implicit"), Error);
}


// Issue 11 item 5: the plane-strain manufactured solution carries z33 and σ33 =
// λ(ε11 + ε22) + z33, and its base laws have a nonzero 33 rate (the part of G that
// the scheme dropped before σ33 was carried).
TEST(ManufacturedSolution, PlaneStrainCarriesSigma33AndA33Rate) {
  ManufacturedOptions o;
  o.dim = 2;
  o.plane_strain = true;
  for (const std::string law : {"perzyna", "perzyna-von-mises", "maxwell-damage"}) {
    SCOPED_TRACE(law);
    o.law = law;
    const Mesh m = manufactured_base_mesh(o);
    const ManufacturedCase c = make_manufactured_case(o, m, 4);
    EXPECT_EQ(c.problem->name, "mms-" + std::string(law == "maxwell-damage" ? "maxwell" : law) + "-2d-plane-strain");
    EXPECT_EQ(c.problem->elasticity.kind(), Elasticity::Kind::PlaneStrain);
    const Point x{0.3, 0.6, 0};
    const double t = 0.7, lambda = 0.3 / (1.3 * 0.4);  // E = 1, ν = 0.3
    const PointState st = c.exact->exact_state(x, t);
    EXPECT_EQ(st.dim, 3);
    EXPECT_GT(std::abs(c.exact->z(x, t)[2]), 1e-3);
    EXPECT_NEAR(st.sigma[2], lambda * (st.eps[0] + st.eps[1]) + c.exact->z(x, t)[2], 1e-15);
    EXPECT_EQ(c.exact->sigma(x, t)[2], st.sigma[2]);
    EXPECT_EQ(c.exact->z(x, t)[3], 0.0);
    EXPECT_EQ(c.exact->z(x, t)[4], 0.0);
    const auto base = make_viscoplastic_law(law, law == "maxwell-damage"
                                                     ? Parameters{}
                                                     : Parameters{{"E", 1.0}, {"lambda", 1.0}, {"sigma_y", 0.05}});
    EXPECT_GT(std::abs(base->rate(st)[2]), 1e-4);
  }
}

}  // namespace
}  // namespace vpc
