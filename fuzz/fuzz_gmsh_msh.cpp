// Fuzz target: the Gmsh reader, vpc::read_gmsh, on mesh files (.msh).
//
// The input is written to a .msh file and read; a mesh that is accepted then
// goes through what the solver computes from it (cell geometry, facet normals
// and measures, parts). A vpc::Error is a correct rejection; anything else
// escaping, a crash, a hang, a leak or a sanitizer report is a bug.
//
// Only .msh: Gmsh runs a .geo file (and any file it does not recognise) as a
// script, which can end the process (Exit;) or run commands (System).
#include "core/error.hpp"
#include "fem/cell_geometry.hpp"
#include "fuzz_common.hpp"
#include "mesh/gmsh_reader.hpp"

#include <cstdint>
#include <fstream>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path file = vpc::fuzz::scratch_dir() / "fuzz.msh";
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const vpc::Mesh mesh = vpc::read_gmsh(file);
    (void)vpc::compute_geometry(mesh);
    (void)vpc::describe_parts(mesh);
    (void)mesh.size_range();
    for (int f = 0; f < mesh.n_facets(); ++f) {
      (void)mesh.facet_normal(f);
      (void)mesh.facet_measure(f);
    }
    (void)mesh.nodes_of_parts(mesh.part_names());
  } catch (const vpc::Error&) {
  }
  return 0;
}
