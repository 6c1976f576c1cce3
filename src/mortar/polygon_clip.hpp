#pragma once
// 3D mortar segments (Puso 2004; Popp, Gitterle, Gee & Wall 2010, §4): the master
// triangle is projected along the slave facet's normal onto the slave facet's plane
// (for a flat P1 slave facet that plane is the auxiliary plane), the two convex
// polygons are clipped (Sutherland–Hodgman), the clip polygon is split into a fan of
// triangles about its centroid, and each gets the degree-2 triangle rule of
// fem/quadrature.hpp. The projection is affine, so the master's shape functions are
// affine on the plane and the integrands Φ_j N_k^m are of degree 2: the rule is exact.
#include "mortar/mortar_point.hpp"

#include <Eigen/Core>
#include <array>
#include <vector>

namespace vpc::mortar {

/// The intersection of two convex polygons in the plane, both counter-clockwise, by
/// Sutherland–Hodgman (`subject` clipped by each edge of `clip` in turn). A vertex
/// within `tol` of a clip edge's line counts as on it: it is kept and no intersection
/// is computed with it, so nearly parallel or collinear edges never divide by a
/// near-zero difference (an intersection is only formed between points more than tol
/// on either side, where the divisor exceeds 2 tol). Consecutive vertices closer than
/// tol are merged. The result is counter-clockwise; empty when fewer than 3 vertices remain.
std::vector<Eigen::Vector2d> clip_convex(const std::vector<Eigen::Vector2d>& subject,
                                         const std::vector<Eigen::Vector2d>& clip, double tol);

/// Signed area of a polygon (> 0 counter-clockwise).
double polygon_area(const std::vector<Eigen::Vector2d>& p);

/// The integration points of the part of slave triangle s (unit normal n_s, either
/// orientation) that master triangle m covers along n_s. `tol` is relative to the
/// slave's longest edge (distances) and area (a clip polygon smaller than tol |s| is
/// dropped). Empty when they do not overlap, or when m is (to tol) perpendicular to the
/// slave plane.
std::vector<MortarPoint> triangle_pair_points(const std::array<Eigen::Vector3d, 3>& s, const Eigen::Vector3d& n_s,
                                              const std::array<Eigen::Vector3d, 3>& m, double tol);

}  // namespace vpc::mortar
