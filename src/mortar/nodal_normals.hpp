#pragma once
// The slave side's nodal normals n_j: the area-weighted (length-weighted in 2D) average
// of the outward normals of the facets at node j, normalized. The weighted gap and the
// constraint of node j are taken along n_j; in 2D the projections of segment_projection
// follow the field Σ_j N_j n_j interpolated from them (Yang, Laursen & Meng 2005).
#include "mortar/surface.hpp"

#include <vector>

namespace vpc::mortar {

/// One unit normal per node of the surface. Throws vpc::Error for a node on no facet, or
/// one whose facets' weighted normals cancel (a knife edge: facets facing opposite ways).
std::vector<Point> nodal_normals(const Surface& s);

}  // namespace vpc::mortar
