// Issue 50: Archard's wear as a contact law's per-node state (contact/wear_law.hpp): its update from a
// node's pressure and whole slip, the share of its per-step cap and of its warning threshold, the gap it
// adds, and its data checked at a node.
#include "contact/wear_law.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace vpc {
namespace {

SurfaceNode node(double lambda_nu, double slip, double measure, double stiffness, double size) {
  SurfaceNode n;
  n.lambda_nu = lambda_nu;
  n.slip = slip;
  n.measure = measure;
  n.normal_stiffness = stiffness;
  n.size = size;
  n.k = 0.1;
  return n;
}

TEST(ArchardWear, TheIncrementIsTheCoefficientTimesThePressureTimesTheSlip) {
  const ArchardWear wear(2e-3, 0.5, 0.1);
  ASSERT_EQ(wear.surface_state().size(), 1u);
  EXPECT_EQ(wear.surface_state()[0].name, "wear");
  EXPECT_EQ(wear.surface_state()[0].history, "worn_volume");
  double omega = 0.01;
  double* values[] = {&omega};
  // λ_ν = 4 on |Γ3| = 0.5: p = 8; slip 0.3: Δω = 2e-3 · 8 · 0.3 = 4.8e-3, whatever the step's size.
  const SurfaceUpdate u = wear.update_surface(node(4.0, 0.3, 0.5, 1000.0, 0.5), values);
  EXPECT_DOUBLE_EQ(omega, 0.01 + 4.8e-3);
  // Its cap: Δω / (0.5 λ_ν / k_ν) = 4.8e-3 / (0.5 · 4 / 1000) = 2.4.
  EXPECT_NEAR(u.step_share, 2.4, 1e-12);
  // Its warning: ω / (0.1 · 0.5) = 0.0148 / 0.05.
  EXPECT_NEAR(u.warn_share, 0.0148 / 0.05, 1e-12);
  const double* now[] = {&omega};
  EXPECT_DOUBLE_EQ(wear.gap_shift(now), omega);  // u_ν ≤ g + ω
}

TEST(ArchardWear, ANodeThatDoesNotPressOrDoesNotSlideDoesNotWear) {
  const ArchardWear wear(2e-3);
  for (const SurfaceNode& n : {node(0.0, 0.3, 0.5, 1000.0, 0.5), node(-1.0, 0.3, 0.5, 1000.0, 0.5),
                               node(4.0, 0.0, 0.5, 1000.0, 0.5)}) {
    double omega = 0.002;
    double* values[] = {&omega};
    const SurfaceUpdate u = wear.update_surface(n, values);
    EXPECT_EQ(omega, 0.002);
    EXPECT_EQ(u.step_share, 0.0);
  }
}

TEST(ArchardWear, ItsDataAreCheckedAtTheNodesAndItsBoundsOnConstruction) {
  EXPECT_TRUE(ArchardWear(0.0).check_at({0, 0, 0}).text.empty());
  EXPECT_THROW(ArchardWear(-1.0), std::exception);
  EXPECT_THROW(ArchardWear(1.0, 0.0), std::exception);
  EXPECT_THROW(ArchardWear(1.0, 1.5), std::exception);
  EXPECT_THROW(ArchardWear(1.0, 0.5, 0.0), std::exception);
  EXPECT_EQ(ArchardWear(1.0).step_limit().key, "wear_cap");
  EXPECT_EQ(ArchardWear(1.0).warning().key, "wear_warning");
  EXPECT_EQ(wear_law_keys("archard"), wear_keys());
  EXPECT_TRUE(wear_law_keys("none").empty());
}

}  // namespace
}  // namespace vpc
