#include "mesh/mesh_extent.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

void check_mesh_extent(const Mesh& mesh) {
  if (mesh.n_nodes() == 0) return;
  const int d = mesh.dim();
  for (int i = 0; i < mesh.n_nodes(); ++i)
    for (int a = 0; a < d; ++a) {
      const double x = mesh.node(i)[a];
      require(std::isfinite(x), "node {} has the coordinate {}: expected finite coordinates", i, x);
    }
  const auto [lo, hi] = mesh.bounding_box();
  double extent = 0, largest = 0;
  for (int a = 0; a < d; ++a) {
    extent = std::max(extent, hi[a] - lo[a]);
    largest = std::max({largest, std::abs(lo[a]), std::abs(hi[a])});
  }
  static const char* axis[3] = {"x", "y", "z"};
  std::string range;
  for (int a = 0; a < d; ++a) range += fmt::format("{}{} in [{:.3g}, {:.3g}]", a ? ", " : "", axis[a], lo[a], hi[a]);
  require(extent >= kMinMeshExtent && extent <= kMaxMeshExtent && largest <= kMaxMeshExtent,
          "the mesh's coordinates ({}) span {:.3g}; supported: extents and coordinates within [{:.0e}, {:.0e}] "
          "(the method forms products of up to five lengths, which double precision cannot hold beyond that): "
          "change the unit of length",
          range, extent, kMinMeshExtent, kMaxMeshExtent);
}

}  // namespace vpc
