#pragma once
// The built-in cases: the paper's two examples (SPEC §4) and a 3D block.
#include "cases/case.hpp"

#include <optional>
#include <string>
#include <vector>

namespace vpc {

/// Overrides of a case's discretization and data; unset means the case's default.
struct CaseOverrides {
  std::optional<int> mesh_cells{};   // cells per unit edge count n (1D: n segments; 2D: n × n; 3D: n³ cubes)
  std::optional<double> kappa{};
  std::optional<int> steps{};      // N, so k = T / N
  std::optional<double> time_step{};// k; N = T / k must be an integer
  bool build_mesh = true;            // false: an empty mesh (a rank > 0 of a distributed run; MeshRequest)
};

/// Applies κ, N or k overrides to a problem (built-in or from a case file);
/// the mesh size is the case's business (built-ins: `n`; files: mesh.cells).
void apply_case_overrides(Problem& p, const CaseOverrides& overrides);

std::vector<std::string> builtin_case_names();
/// Builds a built-in case; throws vpc::Error for an unknown name or a bad override.
Case make_builtin_case(const std::string& name, const CaseOverrides& overrides = {});

}  // namespace vpc
