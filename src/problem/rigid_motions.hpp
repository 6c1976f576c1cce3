#pragma once
// The rigid motions of a body and which of them its supports stop (issue 50): what check_body_held
// reads to refuse a body nothing holds, and, for a body its bonds alone hold (`held_by_bond`, SPEC §9),
// the motions K is singular on, which the primal contact solver's pull-off test reads
// (ContactConstraints::free_motions).
#include "mesh/mesh.hpp"

#include <Eigen/Dense>

#include <functional>

namespace vpc {

/// The rigid motions of a body in coordinates centred at the middle of its box [lo, hi] and scaled
/// by its largest side, so that their values at its nodes are O(1): d = 1 a translation; d = 2 two
/// translations and the rotation about e_z; d = 3 three translations and the rotations about e_x,
/// e_y, e_z.
class RigidMotions {
 public:
  RigidMotions(int dim, const Point& lo, const Point& hi);
  int count() const { return dim_ == 1 ? 1 : dim_ == 2 ? 3 : 6; }
  int dim() const { return dim_; }
  /// r[k] = the value of motion k at x along the unit vector v (a dof's axis or a contact direction).
  Eigen::VectorXd along(const Point& x, const Point& v) const;
  /// The motion with coefficients `a` (count() numbers) in words: a translation along ..., a rotation
  /// about the point / the axis ...
  std::string describe(const Eigen::VectorXd& a) const;

 private:
  int dim_;
  Point centre_{0, 0, 0};
  double scale_ = 1;
};

/// G = Σ r rᵀ over the directions that hold a body (its prescribed dofs, with `held_by_bond` the
/// directions of its bonded contact nodes): a motion in G's kernel moves none of them.
class RigidHold {
 public:
  explicit RigidHold(const RigidMotions& motions);
  void add(const Point& x, const Point& v);
  /// A prescribed component c at x (the unit vector along axis c).
  void add_axis(const Point& x, int c);
  /// The coefficients of the motions nothing stops, as columns (none: the body is held); `sum` adds
  /// G over the ranks where the body's nodes are spread (collective; G itself stays this rank's).
  Eigen::MatrixXd free_motions(const std::function<void(double*, int)>& sum = {}) const;

 private:
  const RigidMotions& motions_;
  Eigen::MatrixXd G_;
};

}  // namespace vpc
