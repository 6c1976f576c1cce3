// Whole steps of the scheme on small built-in cases: plane strain's out-of-plane
// stress (issue 11 item 5).
#include "cases/builtin_cases.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace vpc {
namespace {

/// paper-2d on 10 × 10 squares with 4 steps, in plane strain with law `law`.
std::shared_ptr<Problem> plane_strain_block(const std::string& law) {
  auto p = load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem;
  p->elasticity = Elasticity(Elasticity::Kind::PlaneStrain, 1000.0, 0.3);
  p->law = make_viscoplastic_law(law, {});
  return p;
}

/// The in-plane part of the von Mises norm: what was reported before σ33 was carried.
double in_plane_von_mises(SymTensor s) {
  s[2] = 0;
  return s.von_mises();
}

// Elastic plane strain: σ33 = ν(σ11 + σ22) in every cell to round-off, the 13/23
// components vanish, and the reported von Mises norm is that of the full tensor
// (about 20 % above the in-plane formula here).
TEST(PlaneStrain, ElasticBodyHasSigma33EqualToNuTimesInPlaneTrace) {
  TimeStepper s(plane_strain_block("elastic"));
  StepReport rep;
  while (!s.done()) rep = s.step();
  ASSERT_TRUE(rep.ok);
  const double nu = 0.3;
  double max_vm = 0, max_in_plane = 0, scale = 0;
  for (const SymTensor& t : s.state().sigma) scale = std::max(scale, t.norm());
  ASSERT_GT(scale, 0);
  for (const SymTensor& t : s.state().sigma) {
    EXPECT_NEAR(t[2], nu * (t[0] + t[1]), 1e-13 * scale);
    EXPECT_EQ(t[3], 0.0);
    EXPECT_EQ(t[4], 0.0);
    const double a = t[0] - t[1], b = t[1] - t[2], c = t[2] - t[0];
    const double vm = std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * t[5] * t[5]);
    EXPECT_NEAR(t.von_mises(), vm, 1e-13 * scale);
    max_vm = std::max(max_vm, vm);
    max_in_plane = std::max(max_in_plane, in_plane_von_mises(t));
  }
  EXPECT_NEAR(rep.max_von_mises, max_vm, 1e-13 * scale);
  EXPECT_GT(max_in_plane, 1.05 * max_vm);  // the in-plane formula was far off
}

// A viscoplastic law in plane strain evolves z33 with G: σ33 − λ(ε11 + ε22) = z33 ≠ 0,
// while z13 = z23 = 0; plane stress keeps σ33 = 0.
TEST(PlaneStrain, ViscoplasticLawEvolvesZ33) {
  TimeStepper s(plane_strain_block("maxwell-damage"));
  while (!s.done()) ASSERT_TRUE(s.step().ok);
  const double lambda = 1000.0 * 0.3 / (1.3 * 0.4);
  double max_z33 = 0;
  for (std::size_t c = 0; c < s.state().z.size(); ++c) {
    const SymTensor &z = s.state().z[c], &sig = s.state().sigma[c], &e = s.state().eps[c];
    EXPECT_EQ(z[3], 0.0);
    EXPECT_EQ(z[4], 0.0);
    EXPECT_EQ(e[2], 0.0);
    EXPECT_NEAR(sig[2] - lambda * (e[0] + e[1]), z[2], 1e-12 * std::abs(sig[2]) + 1e-300);
    max_z33 = std::max(max_z33, std::abs(z[2]));
  }
  EXPECT_GT(max_z33, 0.0);

  TimeStepper stress(load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem);
  while (!stress.done()) ASSERT_TRUE(stress.step().ok);
  for (std::size_t c = 0; c < stress.state().z.size(); ++c) {
    EXPECT_EQ(stress.state().sigma[c][2], 0.0);
    EXPECT_EQ(stress.state().z[c][2], 0.0);
  }
}

}  // namespace
}  // namespace vpc
