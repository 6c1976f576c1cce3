#pragma once
// An integration point of the mortar integrals on the part of a slave facet that one
// master facet covers: the P1 shape functions of both facets there (barycentric
// coordinates; the third is 0 on a segment) and the weight (the slave facet's
// length or area element times the rule's weight). segment_projection (2D) and
// polygon_clip (3D) produce them; dual_basis and mortar_coupling consume them.
#include <array>

namespace vpc::mortar {

struct MortarPoint {
  std::array<double, 3> slave{};   // N_j of the slave facet at the point
  std::array<double, 3> master{};  // N_k of the master facet at the point's projection
  double weight = 0;
};

}  // namespace vpc::mortar
