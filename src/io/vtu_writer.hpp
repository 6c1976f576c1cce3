#pragma once
// VTK XML unstructured grid (.vtu) with raw appended binary data (no per-value
// formatting) and the ParaView collection (.pvd) that indexes them over time.
#include "mesh/mesh.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace vpc {

struct VtuField {
  std::string name;
  int n_components = 1;       // 1 scalar, 3 vector, 6 symmetric tensor (XX YY ZZ XY YZ XZ)
  std::vector<double> values;  // n_components per node or per cell
};

/// A cell field of symmetric tensors, in VTK's component order (XX, YY, ZZ, XY, YZ, XZ).
VtuField tensor_field(const std::string& name, const std::vector<SymTensor>& t);

/// Writes mesh + point and cell fields atomically.
void write_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<VtuField>& point_data,
               const std::vector<VtuField>& cell_data);

/// The .pvd collection: (time, file name relative to the .pvd) pairs, rewritten atomically.
void write_pvd(const std::filesystem::path& path, const std::vector<std::pair<double, std::string>>& entries);

}  // namespace vpc
