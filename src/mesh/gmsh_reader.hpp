#pragma once
// Meshes from Gmsh files, read through Gmsh's own library: a mesh file (.msh, any
// version Gmsh reads) is taken as it is; a geometry file (.geo, or anything else
// Gmsh opens that holds no mesh of the needed dimension) is meshed first.
// Physical groups of dimension d − 1 become the mesh's boundary parts.
#include "mesh/mesh.hpp"

#include <cstddef>
#include <filesystem>
#include <string>

namespace vpc {

struct GmshOptions {
  /// Scales the element sizes when the mesh is generated here (Gmsh's
  /// Mesh.MeshSizeFactor, multiplying whatever the file sets); ignored when the
  /// file already holds the mesh. 0.5 halves the element size.
  double size_factor = 1.0;
  /// Dimension d of the cells: 1, 2 or 3; 0 takes the highest dimension of the model.
  int dim = 0;
  /// A script (.geo) that runs programs or writes files (mesh/gmsh_script.hpp) is
  /// refused unless trusted; `trust_how` says how its user trusts it.
  bool trust_script = false;
  std::string trust_how = "GmshOptions::trust_script";
  /// Seconds Gmsh may take (wall clock) before it is stopped; 0: no limit. A
  /// script can loop for ever (`For i In {1:1e15}`) or ask for billions of
  /// elements (a tiny size factor).
  double time_limit = 600;
  /// Bytes Gmsh may allocate to mesh a script (its address space beyond what the
  /// process maps when it starts); 0: no limit. A .msh file is read within a
  /// budget of its own (a small multiple of its size).
  std::size_t memory_limit = 0;
  /// Where the limits are set, for the messages when one is reached.
  std::string time_limit_how = "GmshOptions::time_limit", memory_limit_how = "GmshOptions::memory_limit";
};

/// Reads (or generates) the mesh of `file`. Cells are the linear simplices of
/// dimension d (lines, triangles, tetrahedra); nodes are those the cells use,
/// numbered in increasing Gmsh node tag. Every boundary facet of the cell complex
/// exists; those in a physical group of dimension d − 1 carry its name as their
/// part ("group<tag>" for an unnamed group), the others are untagged. In d < 3 the
/// mesh must lie in the plane z = 0 (d = 2) or on the x axis (d = 1).
/// Throws vpc::Error, naming the file, when the file is missing or unreadable,
/// when it is an untrusted script that runs programs or writes files,
/// when Gmsh reports an error or crashes, when there are no cells of dimension d,
/// when they are not linear simplices, when a cell is degenerate, or when a
/// physical group holds a facet that is not on the boundary or that another
/// group also holds.
/// Gmsh runs in a child process (fork), which sends back the model: a crash of
/// Gmsh on a malformed file, or `Exit;` in a .geo script, becomes an error here,
/// and this process never initializes Gmsh (no global state; calls may overlap).
Mesh read_gmsh(const std::filesystem::path& file, const GmshOptions& options = {});

/// The parts of a mesh with their sizes, for error messages:
/// "bottom (12 facets), top (12 facets), contact (4 facets)"; "no parts" if none.
std::string describe_parts(const Mesh& mesh);

}  // namespace vpc
