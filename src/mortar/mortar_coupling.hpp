#pragma once
// The dual-mortar coupling of a slave and a master contact surface (SPEC §8; Wohlmuth
// 2000; Popp, Gitterle, Gee & Wall 2010), in the reference configuration:
//   D_jj = Σ_e ∫_{C_e} Φ_j N_j        (diagonal: ∫_C Φ_j N_k = 0 for j ≠ k, dual_basis;
//                                      ∫_C Φ_j on a facet where it merged a barely covered node)
//   M_jk = Σ_e ∫_{C_e} Φ_j N_k^m      (slave node j, master node k)
//   g̃_j  = Σ_k M_jk n_j·x_k^m − D_jj n_j·x_j^s     (> 0 open, < 0 penetrating)
// with C_e the part of slave facet e that the master covers, Φ_j the dual basis on it
// and n_j the slave's nodal normal. The contact constraint of slave node j is then
//   D_jj n_j·u_j^s − Σ_k M_jk n_j·u_k^m ≤ g̃_j.
// Σ_k M_jk = D_jj for every node (both are ∫ Φ_j), so rigid motions and constant gaps are
// exact; where no node was merged, Σ_k M_jk f(x_k^m) = D_jj f(x_j^s) for f linear on flat
// surfaces. Slave nodes no master covers have D_jj = 0 and no row of M: they take no
// constraint. Facet pairs whose normals do not face each other (n_s·n_m ≥ −1e-8: back
// faces of the master, faces edge-on to the slave) are left out: on a convex master the
// facing facets' projections tile the slave without overlap.
#include "mortar/dual_basis.hpp"
#include "mortar/facet_search.hpp"
#include "mortar/mortar_point.hpp"
#include "mortar/surface.hpp"

#include <Eigen/SparseCore>
#include <span>
#include <vector>

namespace vpc::mortar {

struct MortarOptions {
  double search_margin = 0;                          // facet boxes this close pair up: ≥ the largest open gap to see
  double coefficient_bound = kDualCoefficientBound;  // dual_basis: merge barely covered nodes above it (≥ 3)
  double clip_tolerance = 1e-10;                     // relative to a slave facet's size (polygon_clip, segment ξ)
};

struct SlaveNodeCoupling {
  int id = 0;      // the node's global id
  double d = 0;    // D_jj; 0 where no master covers the node (then it has no row of M)
  Point normal{};  // n_j, unit, pointing out of the slave body
  double gap = 0;  // g̃_j (0 where d = 0)
};

struct MortarCoupling {
  std::vector<SlaveNodeCoupling> nodes;   // every node of the slave surface, in its order
  std::vector<Eigen::Triplet<double>> m;  // M_jk as (slave id, master id, value), sorted, one per pair
  double covered_area = 0;                // Σ_j D_jj: the length/area of the slave surface the master covers
};

/// The integration points of slave facet e, one list per covering master facet.
struct FacetCover {
  int master_facet = 0;
  std::vector<MortarPoint> points;
};

/// The covers of slave facet e by the facing master facets among `candidates`; in 2D the
/// projections follow the interpolated field of `slave_normals` (nodal_normals(slave)).
std::vector<FacetCover> facet_cover(const Surface& slave, const std::vector<Point>& slave_normals, int e,
                                    const Surface& master, std::span<const int> candidates, double tol);

/// The coupling. Throws vpc::Error when the surfaces' dimensions differ, an option is out
/// of range, a 2D projection fails (segment_projection), or every candidate pair faces the
/// same way (one surface's facets are ordered with their normals into its body).
MortarCoupling mortar_coupling(const Surface& slave, const Surface& master, const MortarOptions& options = {});

/// How many times mortar_coupling has run in this process: a set-up runs it once per contact pair
/// (tests count it; a large-sliding pair runs it again at every step).
long long mortar_coupling_builds();

}  // namespace vpc::mortar
