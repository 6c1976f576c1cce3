#pragma once
// Measures of a mesh for tests of meshes made or changed (generators, the Gmsh reader, refinement):
// the cells' total volume and a boundary part's measure.
#include "fem/cell_geometry.hpp"
#include "mesh/mesh.hpp"

#include <string>

namespace vpc {

inline double total_volume(const Mesh& m) {
  double v = 0;
  for (const CellGeometry& g : compute_geometry(m)) v += g.volume;
  return v;
}

inline double part_measure(const Mesh& m, const std::string& part) {
  double s = 0;
  for (const int f : m.facets_of_parts({part})) s += m.facet_measure(f);
  return s;
}

}  // namespace vpc
