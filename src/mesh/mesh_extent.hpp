#pragma once
// The sizes of mesh double precision can carry through the method (issue 26 item 9).
#include "mesh/mesh.hpp"

namespace vpc {

/// The extents (largest side of the bounding box) a mesh may have. The method forms products
/// of up to about five lengths: cell measures h^d (d ≤ 3) times the data (loads f h^d), and
/// products of forces and displacements (λ (g − Nu) ~ f² L^{d+2} / E in the residuals, σ·σ h^d
/// in the norms). Within 1e±30 those powers (≤ 1e±150) leave about 1e±150 of double's 1e±308
/// for the data; at 1e120 a 2D run's reactions and norms overflowed and its step failed.
constexpr double kMinMeshExtent = 1e-30, kMaxMeshExtent = 1e30;

/// Throws vpc::Error unless every coordinate is finite and the extent lies in
/// [kMinMeshExtent, kMaxMeshExtent]: names the coordinate range and the supported one.
void check_mesh_extent(const Mesh& mesh);

}  // namespace vpc
