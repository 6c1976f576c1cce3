// Issue 49: a friction law is a per-node block. The disc of Coulomb and Tresca (FrictionLaw's
// defaults) and the test-only elliptic law (tests/support/test_laws.hpp): the projection onto the
// set is the nearest point on its boundary, and its derivative is the finite differences'.
#include "test_laws.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace vpc {
namespace {

using Block = std::array<double, 2>;

/// ∂p/∂z and ∂p/∂s of `law` at (z, s) by central differences (h relative to |z| and s).
void finite_differences(const FrictionLaw& law, const Block& z, int t, double s, double* dp_dz, double* dp_ds) {
  const double h = 1e-6 * std::max(std::hypot(z[0], z[1]), s);
  for (int l = 0; l < t; ++l) {
    Block zp = z, zm = z, pp{}, pm{};
    zp[l] += h, zm[l] -= h;
    law.project(zp.data(), t, s, pp.data());
    law.project(zm.data(), t, s, pm.data());
    for (int j = 0; j < t; ++j) dp_dz[j * t + l] = (pp[j] - pm[j]) / (2 * h);
  }
  Block pp{}, pm{};
  const double hs = 1e-6 * s;
  law.project(z.data(), t, s + hs, pp.data());
  law.project(z.data(), t, s - hs, pm.data());
  for (int j = 0; j < t; ++j) dp_ds[j] = (pp[j] - pm[j]) / (2 * hs);
}

void expect_derivative_matches_differences(const FrictionLaw& law, const Block& z, int t, double s) {
  double dz[4], ds[2], fz[4], fs[2];
  law.project_derivative(z.data(), t, s, dz, ds);
  finite_differences(law, z, t, s, fz, fs);
  for (int k = 0; k < t * t; ++k) EXPECT_NEAR(dz[k], fz[k], 1e-7) << law.describe() << " dp/dz entry " << k;
  for (int j = 0; j < t; ++j) EXPECT_NEAR(ds[j], fs[j], 1e-7) << law.describe() << " dp/ds entry " << j;
}

TEST(LawBlocks, DiscProjectsRadiallyAndItsDerivativeIsTheDifferences) {
  const FrictionLaw& disc = disc_friction();
  const Block z{3.0, -4.0};
  Block p{};
  disc.project(z.data(), 2, 2.5, p.data());
  EXPECT_DOUBLE_EQ(disc.gauge(p.data(), 2), 2.5);
  EXPECT_DOUBLE_EQ(p[0], 1.5);
  EXPECT_DOUBLE_EQ(p[1], -2.0);
  EXPECT_DOUBLE_EQ(disc.dual_gauge(z.data(), 2), 5.0);
  expect_derivative_matches_differences(disc, z, 2, 2.5);
  expect_derivative_matches_differences(disc, {-0.7, 0}, 1, 0.3);
}

TEST(LawBlocks, TheBoundIsWrittenOnceWithTheShearLimit) {
  const FrictionBound b{0.1, 0.5, 0.6};
  bool capped = true;
  EXPECT_DOUBLE_EQ(b.at(-1.0, &capped), 0.1);  // λ_ν < 0 counts as 0
  EXPECT_FALSE(capped);
  EXPECT_DOUBLE_EQ(b.at(0.8, &capped), 0.5);
  EXPECT_FALSE(capped);
  EXPECT_DOUBLE_EQ(b.at(2.0, &capped), 0.6);
  EXPECT_TRUE(capped);
  EXPECT_DOUBLE_EQ((FrictionBound{0, 0.3}.at(2.0)), 0.6);  // no limit
}

TEST(LawBlocks, EllipseWithEqualAxesIsTheDisc) {
  const test::EllipticCoulomb round(0.3, 1, 1);
  for (const Block z : {Block{3.0, -4.0}, Block{1e-3, 2.0}, Block{-5.0, 0.0}}) {
    Block p{}, q{};
    round.project(z.data(), 2, 1.7, p.data());
    disc_friction().project(z.data(), 2, 1.7, q.data());
    EXPECT_NEAR(p[0], q[0], 1e-14);
    EXPECT_NEAR(p[1], q[1], 1e-14);
    double dz[4], ds[2], ez[4], es[2];
    round.project_derivative(z.data(), 2, 1.7, dz, ds);
    disc_friction().project_derivative(z.data(), 2, 1.7, ez, es);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(dz[k], ez[k], 1e-14);
    for (int j = 0; j < 2; ++j) EXPECT_NEAR(ds[j], es[j], 1e-14);
  }
}

TEST(LawBlocks, EllipseProjectsOntoTheNearestPointOfItsBoundary) {
  const test::EllipticCoulomb law(0.3, 2.0, 0.5);
  for (const Block z : {Block{3.0, -4.0}, Block{0.1, 2.0}, Block{-5.0, 0.2}, Block{0.0, 1.0}}) {
    Block p{};
    const double r = 0.8;
    law.project(z.data(), 2, r, p.data());
    EXPECT_NEAR(law.gauge(p.data(), 2), r, 1e-14 * r);
    // Nearest point: z − p along the outward normal ∇|·|_C at p, (p_j / a_j²).
    const double n0 = p[0] / 4.0, n1 = p[1] / 0.25;
    EXPECT_NEAR((z[0] - p[0]) * n1 - (z[1] - p[1]) * n0, 0.0, 1e-12);
    EXPECT_GE((z[0] - p[0]) * n0 + (z[1] - p[1]) * n1, 0.0);
    // The dual gauge: p·z/|p|_C at the projection of a far z along it is |z|_C*'s bound from below.
    EXPECT_LE(p[0] * z[0] + p[1] * z[1], r * law.dual_gauge(z.data(), 2) * (1 + 1e-14));
    expect_derivative_matches_differences(law, z, 2, r);
  }
  expect_derivative_matches_differences(law, {-0.7, 0}, 1, 0.3);  // 2D: an interval [−a_1 s, a_1 s]
  Block p{};
  law.project(Block{-0.7, 0}.data(), 1, 0.3, p.data());
  EXPECT_NEAR(p[0], -0.6, 1e-15);
}

TEST(LawBlocks, EllipseAtZeroBoundGrowsTowardsTheSupportPoint) {
  const test::EllipticCoulomb law(0.3, 2.0, 0.5);
  const Block z{1.0, 1.0};
  double dz[4], ds[2];
  law.project_derivative(z.data(), 2, 0.0, dz, ds);
  Block p{};
  const double h = 1e-8;
  law.project(z.data(), 2, h, p.data());  // one-sided: s ≥ 0
  EXPECT_NEAR(ds[0], p[0] / h, 1e-6);
  EXPECT_NEAR(ds[1], p[1] / h, 1e-6);
  for (double v : dz) EXPECT_EQ(v, 0.0);
}

}  // namespace
}  // namespace vpc
