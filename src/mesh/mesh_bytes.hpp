#pragma once
// A mesh as bytes and back: what rank 0 sends the other ranks of the file's mesh that each refines
// its own part of (`[mesh] refine`, mesh/refine.hpp), so that no other rank reads the file or runs
// Gmsh on it. Nodes, cells, boundary facets with their parts, regions; one body.
#include "mesh/mesh.hpp"

#include <string>
#include <string_view>

namespace vpc {

std::string mesh_bytes(const Mesh& mesh);

/// The mesh of mesh_bytes. Throws vpc::Error on bytes that are not a whole mesh.
Mesh mesh_from_bytes(std::string_view bytes);

}  // namespace vpc
