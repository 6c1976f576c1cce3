#pragma once
// P1 shape functions and the biorthogonal dual basis of a slave facet (Wohlmuth 2000;
// Popp, Gitterle, Gee & Wall 2010, §3): Φ_j = Σ_k a_jk N_k with
//   A_e = D_e M_e⁻¹,  D_e = diag(∫_C N_j),  M_e = (∫_C N_j N_k),
// integrated over the part C of the facet that the master covers (Cichosz & Bischoff
// 2011), so that ∫_C Φ_j N_k = δ_jk ∫_C N_k holds on C even where C is a part of the
// facet. On a fully covered facet this is the classical basis: a segment's
// Φ_1 = 2N_1 − N_2, a triangle's Φ_1 = 3N_1 − N_2 − N_3 (= 4N_1 − 1).
//
// A barely covered facet: when C is a sliver near a node or edge, or a tiny patch, M_e is
// nearly singular and A_e grows without bound (a segment covered over a share s at one
// end has |a_jk| ≈ 6/s). Then the node with the least covered weight ∫_C Ñ_j is merged:
// its shape function is shared equally among the kept nodes, Ñ_k = N_k + (1/r) Σ_merged N_l
// (r kept nodes; Σ Ñ_k = 1 still), it gets no multiplier on this facet (Φ_j = 0), and the
// dual basis of the Ñ_k is formed on C; repeated until every |a_jk| ≤ coefficient_bound
// (one node left: Φ = 1 on C). This is the boundary modification of Wohlmuth (2000),
// applied per facet. It keeps Σ_j Φ_j = 1, hence Σ_j ∫_C Φ_j = |C| and Σ_k M_jk = D_jj
// (constant gaps and rigid motions exact), and never yields NaN or a coefficient above
// the bound; what it gives up is linear reproduction at the merged facet's nodes, and
// ∫_C Φ_j N_l for a merged node l is then not 0 (it is O(∫_C N_l): mortar_coupling lumps
// it onto D_jj = ∫_C Φ_j).
#include "mortar/mortar_point.hpp"

#include <Eigen/Core>
#include <array>
#include <span>

namespace vpc::mortar {

/// The default bound on |a_jk|: a full facet has 2 (segment) or 3 (triangle). Measured
/// (tests/unit/mortar/test_dual_basis.cpp's cases): partial covers keep their exact dual
/// basis down to ≈ 6 % of a segment at one end (|a| ≈ 6/share), a strip along a
/// triangle's edge ≈ 1/18 of its height, a triangle's corner ≈ 1/10 of its edges.
inline constexpr double kDualCoefficientBound = 100;

/// Segment, ξ ∈ [−1, 1]: N_1 = (1 − ξ)/2, N_2 = (1 + ξ)/2 (third entry 0).
std::array<double, 3> segment_shape(double xi);
/// Triangle, reference (r, s): N_1 = 1 − r − s, N_2 = r, N_3 = s.
std::array<double, 3> triangle_shape(double r, double s);

/// Adds ∫_C N_j N_k over the points (their slave shape functions and weights) to `mass`;
/// its row sums are ∫_C N_j, its total |C|.
void add_covered_mass(std::span<const MortarPoint> points, Eigen::Matrix3d& mass);

struct DualBasis {
  int n = 0;                                    // nodes of the facet: 2 or 3
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();  // Φ_j = Σ_k a(j, k) N_k; zero rows for merged nodes
  std::array<double, 3> weight{};               // ∫_C Φ_j (= ∫_C Φ_j N_j unless a node was merged)
  std::array<bool, 3> merged{};                 // node j has no multiplier on this facet
  double phi(int j, const std::array<double, 3>& N) const { return a(j, 0) * N[0] + a(j, 1) * N[1] + a(j, 2) * N[2]; }
};

/// The dual basis of an n-node facet (n = 2, 3) from the covered mass ∫_C N_j N_k.
/// C of zero measure gives every node merged and no weight.
DualBasis dual_basis(int n, const Eigen::Matrix3d& mass, double coefficient_bound = kDualCoefficientBound);

}  // namespace vpc::mortar
