#pragma once
// 2D mortar segments (Yang, Laursen & Meng 2005; Popp, Gee & Wall 2009): which part of
// a slave segment a master segment covers, and the master's shape functions at the
// slave's integration points. Both follow the slave's interpolated nodal normal field
//   x(ξ) = N_1(ξ) x_1 + N_2(ξ) x_2,   n(ξ) = N_1(ξ) n_1 + N_2(ξ) n_2,   ξ ∈ [−1, 1]:
// a master node y lies on the slave's normal line at ξ when (x(ξ) − y) × n(ξ) = 0, a
// quadratic in ξ (solved by Newton); a slave point x(ξ) meets the master segment on
// the line x(ξ) + α n(ξ), which is linear in the master's η. Adjacent master segments
// share their projected node, so their overlaps tile the slave segment without gap.
#include "mortar/mortar_point.hpp"

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

namespace vpc::mortar {

/// A slave segment: its nodes and unit nodal normals.
struct SlaveSegment {
  Eigen::Vector2d x1, x2;
  Eigen::Vector2d n1, n2;
};

/// The ξ (any real) at which master point y lies on the slave's normal line,
/// (x(ξ) − y) × n(ξ) = 0, by Newton from ξ = 0 (from 1/2 where the derivative vanishes
/// at 0); nullopt when no normal line passes through y (the quadratic has no real root:
/// y lies beyond the point where the normals of a concave slave cross). Throws
/// vpc::Error when Newton does not converge (|Δξ| ≤ 1e-13) in 60 steps or meets a zero or
/// non-finite derivative (a real root exists, so that takes non-finite input).
std::optional<double> project_to_slave(const SlaveSegment& s, const Eigen::Vector2d& y);

/// The η (any real) of master segment (y1, y2), y(η) = N_1(η) y1 + N_2(η) y2, on the
/// line x + α n; nullopt when n is parallel to the segment (to 1e-12).
std::optional<double> project_to_master(const Eigen::Vector2d& x, const Eigen::Vector2d& n, const Eigen::Vector2d& y1,
                                        const Eigen::Vector2d& y2);

/// The interval [ξ_a, ξ_b] ⊂ [−1, 1] of the slave segment that master segment (y1, y2)
/// covers. Its ends are found as in Popp, Gee & Wall (2009): the slave's ends whose
/// nodal normal line meets the master segment, and the master nodes that project into
/// the slave (project_to_slave), so a master node that no normal line reaches (across a
/// concave corner) leaves the pair coupled over the rest. nullopt when fewer than two
/// ends are found or they lie closer than tol.
std::optional<std::array<double, 2>> segment_overlap(const SlaveSegment& s, const Eigen::Vector2d& y1,
                                                     const Eigen::Vector2d& y2, double tol);

/// The integration points of the overlap: 4-point Gauss–Legendre on [ξ_a, ξ_b] (the
/// integrands Φ_j N_k^m are quadratic where the nodal normals are equal and rational
/// where they are not, so the project's 2-point rule is exact only in the first case),
/// each projected onto the master along n(ξ); the weights carry the slave's length
/// element |x_2 − x_1|/2. Empty when they do not overlap, or when some n(ξ) is parallel
/// to the master segment (a pair meeting at a right angle).
std::vector<MortarPoint> segment_pair_points(const SlaveSegment& s, const Eigen::Vector2d& y1,
                                             const Eigen::Vector2d& y2, double tol);

}  // namespace vpc::mortar
