// The dual basis of a slave facet (mortar/dual_basis): the classical basis on a full
// segment and triangle, biorthogonality on partly covered ones, and bounded, finite
// coefficients with the covered weight kept when a facet is barely covered.
#include "fem/quadrature.hpp"
#include "mortar/dual_basis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace vpc::mortar {
namespace {

/// Points of [a, b] ⊂ [−1, 1] on a segment of length 2 (so ∫ dξ is the measure).
std::vector<MortarPoint> segment_points(double a, double b) {
  std::vector<MortarPoint> p;
  for (const auto& q : simplex_rule(1))
    p.push_back({segment_shape(q.lambda[0] * a + q.lambda[1] * b), {}, q.weight * (b - a)});
  return p;
}

/// Points of a convex polygon (r, s) in the reference triangle: a fan about vertex 0.
std::vector<MortarPoint> polygon_points(const std::vector<std::array<double, 2>>& poly) {
  std::vector<MortarPoint> p;
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    const auto &a = poly[0], &b = poly[i], &c = poly[i + 1];
    const double area = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2;
    for (const auto& q : simplex_rule(2)) {
      const double r = q.lambda[0] * a[0] + q.lambda[1] * b[0] + q.lambda[2] * c[0];
      const double s = q.lambda[0] * a[1] + q.lambda[1] * b[1] + q.lambda[2] * c[1];
      p.push_back({triangle_shape(r, s), {}, q.weight * area});
    }
  }
  return p;
}

DualBasis basis_of(int n, const std::vector<MortarPoint>& p) {
  Eigen::Matrix3d mass = Eigen::Matrix3d::Zero();
  add_covered_mass(p, mass);
  return dual_basis(n, mass);
}

/// ∫_C Φ_j f_k over the points, f_k given at each point.
double integral(const DualBasis& b, const std::vector<MortarPoint>& p, int j,
                const std::function<double(const MortarPoint&)>& f) {
  double s = 0;
  for (const auto& q : p) s += q.weight * b.phi(j, q.slave) * f(q);
  return s;
}

/// ∫_C Φ_j N_k = δ_jk ∫_C N_k for every pair of nodes; true when none was merged.
void expect_biorthogonal(const DualBasis& b, const std::vector<MortarPoint>& p, double tol = 1e-13) {
  for (int j = 0; j < b.n; ++j) {
    ASSERT_FALSE(b.merged[j]) << "node " << j;
    double nj = 0;
    for (const auto& q : p) nj += q.weight * q.slave[j];
    for (int k = 0; k < b.n; ++k)
      EXPECT_NEAR(integral(b, p, j, [k](const MortarPoint& q) { return q.slave[k]; }), j == k ? nj : 0.0, tol)
          << "j = " << j << ", k = " << k;
    EXPECT_NEAR(b.weight[j], nj, tol);
  }
}

/// What holds in every case: finite, bounded coefficients; weights ≥ 0 summing to |C|;
/// Σ_j Φ_j = 1 on C.
void expect_sane(const DualBasis& b, const std::vector<MortarPoint>& p) {
  ASSERT_TRUE(b.a.allFinite());
  EXPECT_LE(b.a.cwiseAbs().maxCoeff(), kDualCoefficientBound);
  double area = 0, wsum = 0;
  for (const auto& q : p) area += q.weight;
  for (int j = 0; j < b.n; ++j) {
    EXPECT_GE(b.weight[j], 0);
    wsum += b.weight[j];
  }
  EXPECT_NEAR(wsum, area, 1e-14 * area + 1e-300);
  for (const auto& q : p) {
    double one = 0;
    for (int j = 0; j < b.n; ++j) one += b.phi(j, q.slave);
    EXPECT_NEAR(one, 1.0, 1e-9);
  }
}

TEST(MortarDualBasis, FullSegmentIsTheClassicalBasis) {
  const auto p = segment_points(-1, 1);
  const DualBasis b = basis_of(2, p);
  // Φ_1 = 2N_1 − N_2, Φ_2 = 2N_2 − N_1.
  EXPECT_NEAR(b.a(0, 0), 2, 1e-14);
  EXPECT_NEAR(b.a(0, 1), -1, 1e-14);
  EXPECT_NEAR(b.a(1, 0), -1, 1e-14);
  EXPECT_NEAR(b.a(1, 1), 2, 1e-14);
  expect_biorthogonal(b, p);
  expect_sane(b, p);
}

TEST(MortarDualBasis, FullTriangleIsTheClassicalBasis) {
  const auto p = polygon_points({{0, 0}, {1, 0}, {0, 1}});
  const DualBasis b = basis_of(3, p);
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(b.a(j, k), j == k ? 3 : -1, 1e-13) << j << ", " << k;
  // Φ_1 = 3N_1 − N_2 − N_3 = 4N_1 − 1.
  const auto N = triangle_shape(0.2, 0.3);
  EXPECT_NEAR(b.phi(0, N), 4 * N[0] - 1, 1e-14);
  expect_biorthogonal(b, p);
  expect_sane(b, p);
}

TEST(MortarDualBasis, PartlyCoveredSegmentStaysBiorthogonalOnItsCoveredPart) {
  for (const auto& [a, c] : std::vector<std::array<double, 2>>{{-0.3, 0.8}, {0.5, 1}, {-1, -0.2}, {-0.7, -0.1}}) {
    SCOPED_TRACE(testing::Message() << "covered [" << a << ", " << c << "]");
    const auto p = segment_points(a, c);
    const DualBasis b = basis_of(2, p);
    expect_biorthogonal(b, p);
    expect_sane(b, p);
    // Not the full facet's basis (which is not biorthogonal here).
    EXPECT_GT(std::abs(b.a(0, 0) - 2), 0.1);
  }
}

TEST(MortarDualBasis, PartlyCoveredTriangleStaysBiorthogonalOnItsCoveredPart) {
  for (const auto& poly :
       std::vector<std::vector<std::array<double, 2>>>{{{0.1, 0.1}, {0.7, 0.1}, {0.3, 0.6}, {0.05, 0.5}},
                                                       {{0, 0}, {0.5, 0}, {0, 0.5}},
                                                       {{0.2, 0}, {1, 0}, {0.2, 0.8}},
                                                       {{0, 0}, {1, 0}, {0.6, 0.4}, {0, 0.3}}}) {
    SCOPED_TRACE(testing::Message() << "polygon from (" << poly[1][0] << ", " << poly[1][1] << ")");
    const auto p = polygon_points(poly);
    const DualBasis b = basis_of(3, p);
    expect_biorthogonal(b, p);
    expect_sane(b, p);
  }
}

TEST(MortarDualBasis, BarelyCoveredSegmentMergesItsFarNodeAndStaysFinite) {
  // Covered over a share s at the end of node 2: the exact basis has |a| ≈ 6/s.
  for (double s = 0.5; s > 1e-17; s /= 10) {
    SCOPED_TRACE(testing::Message() << "share " << s);
    const auto p = segment_points(1 - 2 * s, 1);
    const DualBasis b = basis_of(2, p);
    expect_sane(b, p);
    if (s >= 0.1) expect_biorthogonal(b, p, 1e-13 * s);
    if (s <= 1e-2) {
      EXPECT_TRUE(b.merged[0]);  // Φ_1 = 0, Φ_2 = 1 on C: D_22 = |C|
      EXPECT_FALSE(b.merged[1]);
      double area = 0;
      for (const auto& q : p) area += q.weight;
      EXPECT_NEAR(b.weight[1], area, 1e-14 * area);
    }
  }
  // A tiny share in the middle: both nodes' weights are alike; one is kept, with all of it.
  const auto p = segment_points(0.1, 0.1 + 1e-9);
  const DualBasis b = basis_of(2, p);
  expect_sane(b, p);
  EXPECT_NE(b.merged[0], b.merged[1]);
}

TEST(MortarDualBasis, BarelyCoveredTriangleStaysFiniteAndBounded) {
  for (double h = 1e-1; h > 1e-13; h /= 10) {
    SCOPED_TRACE(testing::Message() << "size " << h);
    const std::vector<std::vector<std::array<double, 2>>> polys{
        {{1 - h, 0}, {1, 0}, {1 - h, h}},              // at vertex 2
        {{0.5 - h, 0}, {0.5 + h, 0}, {0.5, h}},        // at the middle of edge 1-2
        {{0, 0}, {1, 0}, {1 - h, h}, {0, h}},          // a strip along edge 1-2
        {{0.3, 0.3}, {0.3 + h, 0.3}, {0.3, 0.3 + h}},  // a speck inside
        {{0, 1 - h}, {h, 1 - h}, {0, 1}}};             // at vertex 3
    for (const auto& poly : polys) {
      const auto p = polygon_points(poly);
      const DualBasis b = basis_of(3, p);
      expect_sane(b, p);
    }
  }
}

TEST(MortarDualBasis, KeepsTheExactBasisDownToTheSharesItsHeaderStates) {
  const auto merges = [](int n, const std::vector<MortarPoint>& p) {
    const DualBasis b = basis_of(n, p);
    return b.merged[0] || b.merged[1] || (n == 3 && b.merged[2]);
  };
  EXPECT_FALSE(merges(2, segment_points(1 - 2 * 0.06, 1)));  // 6 % of a segment at one end
  EXPECT_TRUE(merges(2, segment_points(1 - 2 * 0.05, 1)));
  const auto strip = [](double h) { return polygon_points({{0, 0}, {1, 0}, {1 - h, h}, {0, h}}); };
  EXPECT_FALSE(merges(3, strip(1.0 / 17)));  // a strip along an edge, 1/18 of the height
  EXPECT_TRUE(merges(3, strip(1.0 / 19)));
  const auto corner = [](double h) { return polygon_points({{1 - h, 0}, {1, 0}, {1 - h, h}}); };
  EXPECT_FALSE(merges(3, corner(0.11)));  // a corner, 1/10 of the edges
  EXPECT_TRUE(merges(3, corner(0.09)));
}

TEST(MortarDualBasis, AMergedNodeLeavesTheOthersBiorthogonalToTheMergedShapes) {
  // A thin strip along edge 1-2: node 3 is merged, Ñ_k = N_k + N_3/2 for k = 1, 2, and
  // ∫ Φ_j Ñ_k = δ_jk ∫ Ñ_k.
  const double h = 1e-3;
  const auto p = polygon_points({{0, 0}, {1, 0}, {1 - h, h}, {0, h}});
  const DualBasis b = basis_of(3, p);
  ASSERT_TRUE(b.merged[2]);
  ASSERT_FALSE(b.merged[0] || b.merged[1]);
  EXPECT_EQ(b.a.row(2).norm(), 0);
  for (int j = 0; j < 2; ++j)
    for (int k = 0; k < 2; ++k) {
      const auto merged_shape = [k](const MortarPoint& q) { return q.slave[k] + q.slave[2] / 2; };
      const double want = j == k ? b.weight[j] : 0.0;
      EXPECT_NEAR(integral(b, p, j, merged_shape), want, 1e-15) << j << ", " << k;
    }
}

TEST(MortarDualBasis, NothingCoveredGivesNoBasis) {
  const DualBasis zero = dual_basis(3, Eigen::Matrix3d::Zero());
  const DualBasis nan = dual_basis(2, Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (const DualBasis& b : {zero, nan}) {
    EXPECT_TRUE(b.merged[0] && b.merged[1] && b.merged[2]);
    EXPECT_EQ(b.a.norm(), 0);
    EXPECT_EQ(b.weight[0] + b.weight[1] + b.weight[2], 0);
  }
}

}  // namespace
}  // namespace vpc::mortar
