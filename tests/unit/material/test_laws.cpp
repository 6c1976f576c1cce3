// Elasticity tensors, the laws G and the sources φ, and the registry.
#include "material/damage_source.hpp"
#include "material/elasticity.hpp"
#include "material/viscoplastic_law.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

namespace vpc {
namespace {

TEST(Elasticity, VoigtMatrixAgreesWithApply) {
  const SymTensor e{{0.1, -0.3, 0.2, 0.05, -0.07, 0.11}};
  for (auto kind : {Elasticity::Kind::Uniaxial, Elasticity::Kind::PlaneStress, Elasticity::Kind::PlaneStrain,
                    Elasticity::Kind::Isotropic}) {
    const Elasticity E(kind, 210, 0.3);
    const int d = E.dim();
    const Eigen::MatrixXd D = E.voigt();
    const SymTensor s = E.apply(e);
    Eigen::VectorXd ev;
    std::vector<int> comp;
    if (d == 1) comp = {0};
    if (d == 2) comp = {0, 1, 5};
    if (d == 3) comp = {0, 1, 2, 3, 4, 5};
    ev.resize(comp.size());
    for (size_t i = 0; i < comp.size(); ++i) ev[i] = comp[i] >= 3 ? 2 * e[comp[i]] : e[comp[i]];
    const Eigen::VectorXd sv = D * ev;
    for (size_t i = 0; i < comp.size(); ++i) EXPECT_NEAR(sv[i], s[comp[i]], 1e-12) << E.name() << " " << i;
  }
}

TEST(Elasticity, PlaneStressMatchesPaperFormula) {
  // (4.7): (ℰτ)_ab = Eν/(1−ν²)(τ11+τ22)δ_ab + E/(1+ν) τ_ab
  const double E = 1000, nu = 0.3;
  const Elasticity el(Elasticity::Kind::PlaneStress, E, nu);
  const SymTensor t{{0.2, -0.1, 0, 0, 0, 0.05}};
  const SymTensor s = el.apply(t);
  const double a = E * nu / (1 - nu * nu) * (0.2 - 0.1);
  EXPECT_NEAR(s[0], a + E / (1 + nu) * 0.2, 1e-12);
  EXPECT_NEAR(s[1], a + E / (1 + nu) * -0.1, 1e-12);
  EXPECT_NEAR(s[5], E / (1 + nu) * 0.05, 1e-12);
  EXPECT_EQ(s[2], 0.0);
}

TEST(Elasticity, InvalidDataIsAnError) {
  EXPECT_THROW(Elasticity(Elasticity::Kind::Isotropic, -1, 0.3), std::runtime_error);
  EXPECT_THROW(Elasticity(Elasticity::Kind::Isotropic, 1, 0.5), std::runtime_error);
  EXPECT_THROW(Elasticity::from_name("hyperelastic", 1, 0.3), std::runtime_error);
}

// Issue 11 item 5: plane strain carries σ33 = λ(ε11 + ε22) = ν(σ11 + σ22).
TEST(Elasticity, PlaneStrainCarriesSigma33) {
  const double E = 210, nu = 0.3;
  const Elasticity ps(Elasticity::Kind::PlaneStrain, E, nu), iso(Elasticity::Kind::Isotropic, E, nu);
  const SymTensor e{{0.1, -0.03, 0, 0, 0, 0.02}};
  const SymTensor s = ps.apply(e);
  EXPECT_NEAR(s[2], nu * (s[0] + s[1]), 1e-13);
  EXPECT_NEAR(s[2], E * nu / ((1 + nu) * (1 - 2 * nu)) * (0.1 - 0.03), 1e-13);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(s[i], iso.apply(e)[i], 1e-13) << i;  // the 3D law at ε33 = 0
  EXPECT_EQ(ps.stress_dim(), 3);
  EXPECT_EQ(ps.stress_components(), (std::vector<int>{0, 1, 2, 5}));
  SymTensor g{{1, 2, 3, 4, 5, 6}};
  ps.restrict_stress(g);  // P_Q keeps 11, 22, 33, 12
  EXPECT_EQ(g.c, (std::array<double, 6>{1, 2, 3, 0, 0, 6}));
  // Plane stress, 1D and 3D: as before (S_d).
  const Elasticity pst(Elasticity::Kind::PlaneStress, E, nu);
  EXPECT_EQ(pst.apply(e)[2], 0.0);
  EXPECT_EQ(pst.stress_dim(), 2);
  EXPECT_EQ(pst.stress_components(), (std::vector<int>{0, 1, 5}));
  g = SymTensor{{1, 2, 3, 4, 5, 6}};
  pst.restrict_stress(g);
  EXPECT_EQ(g.c, (std::array<double, 6>{1, 2, 0, 0, 0, 6}));
  g = SymTensor{{1, 2, 3, 4, 5, 6}};
  Elasticity(Elasticity::Kind::Uniaxial, E, 0).restrict_stress(g);
  EXPECT_EQ(g.c, (std::array<double, 6>{1, 0, 0, 0, 0, 0}));
  g = SymTensor{{1, 2, 3, 4, 5, 6}};
  iso.restrict_stress(g);
  EXPECT_EQ(g.c, (std::array<double, 6>{1, 2, 3, 4, 5, 6}));
}

/// What the stepper hands a law in plane strain: σ = ℰε + z with σ33, dim = 3.
PointState plane_strain_state(const SymTensor& eps, const SymTensor& z, double beta) {
  const Elasticity ps(Elasticity::Kind::PlaneStrain, 1, 0.3);
  PointState s;
  s.eps = eps;
  s.sigma = ps.apply(eps) + z;
  s.beta = beta;
  s.dim = ps.stress_dim();
  return s;
}

// Every law and source sees the full 3D tensor in plane strain: it gives what the 3D
// law gives on the same state (ε33 = 0), and the 33 rate is that of σ33.
TEST(Laws, PlaneStrainLawsAndSourcesUseTheFull3DTensor) {
  const SymTensor eps{{0.2, 0.1, 0, 0, 0, 0.05}}, z{{0.01, -0.02, 0.03, 0, 0, 0.01}};
  PointState s = plane_strain_state(eps, z, 0.8);
  ASSERT_GT(s.sigma[2], 0.05);  // σ33 = λ(ε11 + ε22) + z33 matters here
  PointState s3 = s;
  s3.sigma = Elasticity(Elasticity::Kind::Isotropic, 1, 0.3).apply(eps) + z;
  const Parameters yield{{"E", 1.0}, {"lambda", 1.0}, {"sigma_y", 0.1}};  // yields: |σ|, |σ|_VM > 0.08
  for (const auto& name : viscoplastic_law_names()) {
    SCOPED_TRACE(name);
    auto law = make_viscoplastic_law(name, name.rfind("perzyna", 0) == 0 ? yield : Parameters{});
    const SymTensor g = law->rate(s), g3 = law->rate(s3);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(g[i], g3[i], 1e-15) << i;
    if (name != "elastic") {
      EXPECT_NE(g[2], 0.0);
    }
    EXPECT_EQ(g[3], 0.0);
    EXPECT_EQ(g[4], 0.0);
  }
  for (const auto& name : damage_source_names()) {
    SCOPED_TRACE(name);
    auto phi = make_damage_source(name, {});
    EXPECT_NEAR(phi->rate(s), phi->rate(s3), 1e-15);
  }
  EXPECT_NEAR(make_damage_source("von-mises", {})->rate(s), -0.01 * s3.sigma.von_mises(), 1e-16);
}

// The yield checks and the von Mises source with a σ33 component, by hand.
TEST(Laws, NormsIncludeSigma33) {
  // Perzyna (Euclidean): |σ| = |(0.3, 0, 0.4)| = 0.5 > β σ_Y = 0.4 > 0.3 (in-plane part).
  auto perzyna = make_viscoplastic_law("perzyna", {{"E", 2}, {"lambda", 1}, {"sigma_y", 0.4}});
  PointState s;
  s.dim = 3;
  s.sigma = SymTensor{{0.3, 0, 0.4, 0, 0, 0}};
  const SymTensor g = perzyna->rate(s);  // −(σ − 0.8σ) = −0.2σ
  EXPECT_NEAR(g[0], -0.06, 1e-15);
  EXPECT_NEAR(g[2], -0.08, 1e-15);
  // Von Mises: σ = 2I is pure pressure and never yields; without σ33 it would (|σ|_VM = 2).
  auto vm = make_viscoplastic_law("perzyna-von-mises", {{"E", 2}, {"lambda", 1}, {"sigma_y", 1}});
  s.sigma = SymTensor{{2, 2, 2, 0, 0, 0}};
  EXPECT_NEAR(vm->rate(s).norm(), 0.0, 1e-15);
  EXPECT_NEAR(make_damage_source("von-mises", {{"c", 1.0}})->rate(s), 0.0, 1e-15);
  // σ = (1, 0, 3): |σ|_VM = √7 > 1: the mean stress 4/3 is kept, the deviator scaled to 1.
  s.sigma = SymTensor{{1, 0, 3, 0, 0, 0}};
  EXPECT_NEAR(make_damage_source("von-mises", {{"c", 1.0}})->rate(s), -std::sqrt(7.0), 1e-14);
  const SymTensor p = s.sigma + vm->rate(s);  // E/(2λ) = 1: Pσ = σ + G
  EXPECT_NEAR(p.von_mises(), 1.0, 1e-14);
  EXPECT_NEAR(p.trace(), 4.0, 1e-14);
  EXPECT_NEAR(p[2] - p.trace() / 3, (3 - 4.0 / 3) / std::sqrt(7.0), 1e-14);
}

TEST(SymTensor, VonMisesReducesToPaperNormIn2D) {
  const SymTensor t{{3, -1, 0, 0, 0, 2}};
  // (4.10): τ11² + τ22² − τ11τ22 + 3τ12²
  EXPECT_NEAR(t.von_mises(), std::sqrt(9 + 1 + 3 + 12), 1e-14);
  // Uniaxial: |σ|_VM = |σ11|.
  EXPECT_NEAR((SymTensor{{-5, 0, 0, 0, 0, 0}}).von_mises(), 5, 1e-14);
  // Pressure has no von Mises norm.
  EXPECT_NEAR((4.0 * SymTensor::identity()).von_mises(), 0, 1e-14);
}

TEST(Laws, PerzynaIsZeroInsideTheYieldSetAndProjectsOutside) {
  auto G = make_viscoplastic_law("perzyna", {{"E", 2}, {"lambda", 10}, {"sigma_y", 1}});
  PointState s;
  s.dim = 1;
  s.beta = 0.5;
  s.sigma[0] = 0.4;  // |σ| ≤ β σ_Y = 0.5
  EXPECT_EQ(G->rate(s)[0], 0.0);
  s.sigma[0] = 1.5;  // P σ = 0.5: G = −E/(2λ)(1.5 − 0.5) = −0.1
  EXPECT_NEAR(G->rate(s)[0], -0.1, 1e-15);
  s.sigma[0] = -1.5;
  EXPECT_NEAR(G->rate(s)[0], 0.1, 1e-15);
  s.beta = 0;  // fully damaged: R = {0}
  EXPECT_NEAR(G->rate(s)[0], 2.0 / 20 * 1.5, 1e-15);
}

TEST(Laws, PerzynaVonMisesKeepsMeanStressIn3D) {
  auto G = make_viscoplastic_law("perzyna-von-mises", {{"E", 1}, {"lambda", 0.5}, {"sigma_y", 1}});
  PointState s;
  s.dim = 3;
  s.beta = 1;
  s.sigma = SymTensor{{3, 0, 0, 0, 0, 0}};  // |σ|_VM = 3, mean 1
  const SymTensor g = G->rate(s);           // −(σ − Pσ), Pσ = I + dev σ / 3
  EXPECT_NEAR(g.trace(), 0, 1e-14);
  const SymTensor p = s.sigma + g;  // E/(2λ) = 1
  EXPECT_NEAR(p.von_mises(), 1.0, 1e-14);
  EXPECT_NEAR(p.trace(), 3.0, 1e-14);
  // Pure pressure never yields.
  s.sigma = 10.0 * SymTensor::identity();
  EXPECT_NEAR(G->rate(s).norm(), 0, 1e-14);
}

TEST(Laws, MaxwellDamage) {
  auto G = make_viscoplastic_law("maxwell-damage", {});
  PointState s;
  s.sigma = SymTensor{{2, -4, 0, 0, 0, 6}};
  s.beta = 0.75;
  const SymTensor g = G->rate(s);
  EXPECT_NEAR(g[0], -0.5, 1e-15);
  EXPECT_NEAR(g[1], 1.0, 1e-15);
  EXPECT_NEAR(g[5], -1.5, 1e-15);
  s.beta = 1;
  EXPECT_EQ(G->rate(s).norm(), 0.0);
}

TEST(Sources, PaperSources) {
  PointState s;
  s.eps[0] = 0.3;
  EXPECT_NEAR(make_damage_source("strain", {})->rate(s), -0.6, 1e-15);  // −2ε (4.4)
  s.sigma = SymTensor{{3, -1, 0, 0, 0, 2}};
  EXPECT_NEAR(make_damage_source("von-mises", {})->rate(s), -std::sqrt(25.0) / 100, 1e-15);  // (4.9)
  EXPECT_EQ(make_damage_source("zero", {})->rate(s), 0.0);
}

TEST(Registry, ErrorsNameTheLawAndTheProblem) {
  try {
    make_viscoplastic_law("perzina", {});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown viscoplastic law 'perzina'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("perzyna"), std::string::npos);
  }
  try {
    make_viscoplastic_law("perzyna", {{"E", 1}, {"lambda", 1}, {"sigma_y", 1}, {"sigma_Y", 2}});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown parameter 'sigma_Y'"), std::string::npos) << e.what();
  }
  try {
    make_viscoplastic_law("perzyna", {{"E", 1}, {"sigma_y", 1}});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing parameter 'lambda'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_viscoplastic_law("perzyna", {{"E", 1}, {"lambda", -1}, {"sigma_y", 1}}), std::runtime_error);
  EXPECT_THROW(make_damage_source("entropy", {}), std::runtime_error);
}

}  // namespace
}  // namespace vpc
