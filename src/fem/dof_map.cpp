#include "fem/dof_map.hpp"

#include <cstddef>

namespace vpc {

DofMap::DofMap(int n_nodes, int dim, const std::vector<int>& clamped_nodes) : dim_(dim) {
  std::vector<int> prescribed(static_cast<std::size_t>(n_nodes) * dim, -1);
  for (int n : clamped_nodes)
    for (int c = 0; c < dim; ++c) prescribed[static_cast<std::size_t>(n) * dim + c] = 0;
  *this = DofMap(dim, prescribed);
}

DofMap::DofMap(int dim, const std::vector<int>& prescribed) : dim_(dim), free_(prescribed.size(), -1) {
  for (std::size_t i = 0; i < prescribed.size(); ++i)
    if (prescribed[i] < 0) free_[i] = n_free_++;
}

}  // namespace vpc
