// Issue 50: Frémond's adhesion as a contact law's per-node state (contact/adhesion_law.hpp): α carried
// over a step by the exact solution of its rate law with the separation frozen, the bond it gives the
// step, the state after the step, and a node's start (bonded only across a closed gap).
#include "contact/adhesion_law.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace vpc {
namespace {

constexpr double kGamma = 50, kL = 0.1, kB = 0.2;

TEST(FremondAdhesion, TheBondingIsTheExactSolutionOfItsRateLawWithTheSeparationFrozen) {
  const Point x{0, 0, 0};
  for (const double energy : {0.0, 0.02}) {
    const FremondAdhesion law(kGamma, kL, kB, energy);
    for (const double s : {0.03, 0.5}) {  // below L, and beyond it (R = L)
      const double R = std::min(s, kL), c = kGamma * R * R;
      // b α̇ = −(c α − ε)₊: the derivative in k of the carried α is the rate at it, at every k.
      for (const double k : {0.0, 0.01, 0.3, 2.0}) {
        const double a = law.carried(0.9, s, x, k), h = 1e-6;
        const double rate = (law.carried(0.9, s, x, k + h) - law.carried(0.9, s, x, std::max(k - h, 0.0))) / (k > 0 ? 2 * h : h);
        const double exact = -std::max(c * a - energy, 0.0) / kB;  // (a one-sided difference at k = 0: O(h))
        EXPECT_NEAR(rate, exact, 1e-5 * std::max(std::abs(exact), 1.0)) << "s " << s << " k " << k;
        EXPECT_LE(a, 0.9);  // never grows
        EXPECT_GE(a, std::min(0.9, energy / c));  // never below its rest
      }
    }
    // Held: c α ≤ ε_a (or no separation) keeps α.
    EXPECT_EQ(law.carried(0.9, 0.0, x, 1.0), 0.9);
    if (energy > 0) {
      EXPECT_EQ(law.carried(0.9, 0.01, x, 1.0), 0.9);  // c α = 50 · 1e-4 · 0.9 < 0.02
    }
  }
}

TEST(FremondAdhesion, ItsBondIsTheCarriedBondingsAndTheStepKeepsItAndTheSeparation) {
  const FremondAdhesion law(kGamma, kL, kB);
  EXPECT_EQ(law.bond_length(), kL);
  ASSERT_EQ(law.surface_state().size(), 6u);
  std::array<double, 6> v = {0.8, 0.04, 0, 0, 0, 0.001};  // α, s, traction, debonded, stored, released
  std::array<double*, 6> p = {&v[0], &v[1], &v[2], &v[3], &v[4], &v[5]};
  std::array<const double*, 6> q = {&v[0], &v[1], &v[2], &v[3], &v[4], &v[5]};
  const Point x{1, 2, 0};
  const double k = 0.05, alpha = law.carried(0.8, 0.04, x, k);
  EXPECT_DOUBLE_EQ(law.bond(q, x, k), kGamma * alpha * alpha);
  SurfaceNode node;
  node.gap_left = 0.2;  // beyond L: the pull is γ α² L
  node.k = k;
  node.x = x;
  node.measure = 0.5;
  law.update_surface(node, p);
  EXPECT_EQ(v[0], alpha);
  EXPECT_EQ(v[1], 0.2);
  EXPECT_DOUBLE_EQ(v[2], kGamma * alpha * alpha * kL);
  EXPECT_EQ(v[3], 0.0);
  EXPECT_DOUBLE_EQ(v[4], kGamma * alpha * alpha * (kL * 0.2 - kL * kL / 2));
  EXPECT_NEAR(v[5], 0.001 + kGamma * (0.64 - alpha * alpha) * 0.04 * 0.04 / 2, 1e-16);
}

TEST(FremondAdhesion, ANodeStartsBondedOnlyAcrossAClosedGap) {
  const FremondAdhesion law(kGamma, kL, kB, 0, 0.7);
  std::array<double, 6> v = {1, 0, 0, 0, 0, 0};
  std::array<double*, 6> p = {&v[0], &v[1], &v[2], &v[3], &v[4], &v[5]};
  EXPECT_TRUE(law.initial_at(Point{0, 0, 0}, 0.0, p).text.empty());
  EXPECT_EQ(v[0], 0.7);
  const LawText open = law.initial_at(Point{0.5, 0, 0}, 0.01, p);
  EXPECT_EQ(open.key, "bonding");
  EXPECT_NE(open.text.find("where the initial gap is 0.01"), std::string::npos) << open.text;
  // Debonded from the start: any gap.
  const FremondAdhesion loose(kGamma, kL, kB, 0, 0.0);
  EXPECT_TRUE(loose.initial_at(Point{0.5, 0, 0}, 0.01, p).text.empty());
  EXPECT_EQ(v[0], 0.0);
  EXPECT_EQ(v[1], 0.01);
  EXPECT_EQ(v[3], 1.0);  // debonded
}

}  // namespace
}  // namespace vpc
