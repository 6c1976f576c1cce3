#pragma once
// Friction's tangents at the contact nodes in global coordinates, for the outputs (VTU
// fields, history.csv's tangential forces): the frame of the contact solver's T
// (ContactConstraints::T, set_tangents), so that λ_τ,j and the slip increments of
// State (along the node's tangents t_j) become vectors Σ_j x_j t_j.
#include "core/sym_tensor.hpp"
#include "part/mesh_part.hpp"

#include <span>
#include <vector>

namespace vpc {

/// The block − 1 unit tangents t_j of every contact node the part knows (`nodes`: ContactSet::nodes,
/// ghosts included: set_tangents' frame depends on the node's own normal and free components
/// only) over its free dofs `dofs`, tangent after tangent; a zero vector where the node has fewer
/// free tangents (a symmetry plane). Empty for block 1 (no friction).
std::vector<Point> contact_tangents(const DofMap& dofs, std::span<const PartContactNode> nodes, int block);

/// Σ_j x[j] t_j over the block − 1 tangents of the k-th contact node (`tangents`:
/// contact_tangents), as a vector of 3 components (unused ones 0).
Point along_tangents(std::span<const Point> tangents, std::size_t k, int block, const double* x);

}  // namespace vpc
