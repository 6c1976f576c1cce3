#pragma once
// A contact surface of one body for dual mortar (SPEC §8): P1 facets (segments of
// 2 nodes in 2D, triangles of 3 nodes in 3D), their nodes (3D points, z = 0 in 2D),
// each node's global id and each facet's outward unit normal.
//
// Orientation convention (FacetOrder::Outward): a 2D segment (a, b) has the body on
// its left, i.e. the boundary is walked counter-clockwise and the outward normal is
// the tangent b − a turned clockwise, n = (t_y, −t_x)/|t|; a 3D triangle (a, b, c)
// is counter-clockwise seen from outside, n = (b − a) × (c − a)/|…|. FacetOrder::Inward
// states the opposite order; the normals still come out pointing out of the body.
// Neighbouring facets must be ordered alike (checked: a shared node or edge is walked
// in opposite directions); orient_away_from() orders facets from points inside the body
// (e.g. the centroids of the cells that own them), which is how a Mesh knows outward.
#include "core/sym_tensor.hpp"

#include <Eigen/Core>
#include <vector>

namespace vpc::mortar {

enum class FacetOrder { Outward, Inward };

class Surface {
 public:
  Surface() = default;
  /// `facets` holds dim node indices (into x) per facet. Throws vpc::Error for a
  /// dimension other than 2 or 3, a node index out of range or repeated in a facet,
  /// a degenerate facet, a 2D node with z ≠ 0, repeated global ids, or neighbouring
  /// facets ordered inconsistently (or more than two facets on an edge).
  Surface(int dim, std::vector<Point> x, std::vector<int> ids, std::vector<int> facets,
          FacetOrder order = FacetOrder::Outward);

  int dim() const { return dim_; }
  int nodes_per_facet() const { return dim_; }
  int n_nodes() const { return static_cast<int>(x_.size()); }
  int n_facets() const { return static_cast<int>(normal_.size()); }

  const Point& node(int i) const { return x_[i]; }
  const std::vector<Point>& nodes() const { return x_; }
  /// The caller's global id of node i (keys the mortar matrix M).
  int id(int i) const { return id_[i]; }
  /// Node indices of facet f (dim of them), ordered as given.
  const int* facet(int f) const { return &facets_[static_cast<size_t>(f) * dim_]; }
  /// Outward unit normal of facet f.
  const Point& normal(int f) const { return normal_[f]; }
  /// Length (2D) or area (3D) of facet f.
  double measure(int f) const { return measure_[f]; }
  /// The longest edge of any facet (a contact pair's default search distance).
  double longest_edge() const;

 private:
  void check_orientation() const;

  int dim_ = 0;
  std::vector<Point> x_;
  std::vector<int> id_;
  std::vector<int> facets_;
  std::vector<Point> normal_;
  std::vector<double> measure_;
};

/// Reorders each facet (dim node indices per facet, into x) so that its normal by the
/// Outward convention points away from inside[f], a point of the body behind facet f.
/// Throws vpc::Error when inside[f] lies in the facet's line or plane.
void orient_away_from(int dim, const std::vector<Point>& x, std::vector<int>& facets, const std::vector<Point>& inside);

inline Eigen::Vector3d vec(const Point& p) { return {p[0], p[1], p[2]}; }
inline Point point(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

}  // namespace vpc::mortar
