#pragma once
// Candidate slave-master facet pairs for the mortar integrals: the pairs whose
// axis-aligned bounding boxes come within a search margin of each other. The master
// boxes go into a uniform bucket grid (a hash of the nonempty cells, cell size the mean
// master box extent), each slave box widened by the margin looks up the cells it
// meets, so the cost is about linear in the facets rather than in all pairs.
#include "mortar/surface.hpp"

#include <span>
#include <vector>

namespace vpc::mortar {

/// An axis-aligned box.
struct Box {
  Eigen::Vector3d lo, hi;
  /// Whether the boxes come within `margin` of each other along every axis.
  bool near(const Box& o, double margin) const {
    return (lo.array() <= o.hi.array() + margin).all() && (o.lo.array() <= hi.array() + margin).all();
  }
};

Box facet_box(const Surface& s, int f);

/// For each slave facet, the master facets (ascending) whose boxes are near its own.
class FacetPairs {
 public:
  std::span<const int> of(int slave_facet) const {
    return {master_.data() + offset_[slave_facet], master_.data() + offset_[slave_facet + 1]};
  }
  int n_pairs() const { return static_cast<int>(master_.size()); }

 private:
  friend FacetPairs candidate_pairs(const Surface&, const Surface&, double);
  std::vector<int> offset_{0};
  std::vector<int> master_;
};

/// The candidate pairs; margin ≥ 0 is the largest distance that must still pair
/// (at least the largest open gap the constraints should see).
FacetPairs candidate_pairs(const Surface& slave, const Surface& master, double margin);

}  // namespace vpc::mortar
