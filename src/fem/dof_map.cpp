#include "fem/dof_map.hpp"

#include <cstddef>

namespace vpc {

DofMap::DofMap(int n_nodes, int dim, const std::vector<int>& clamped_nodes)
    : dim_(dim), free_(static_cast<std::size_t>(n_nodes) * dim, 0) {
  for (int n : clamped_nodes)
    for (int c = 0; c < dim; ++c) free_[n * dim + c] = -1;
  for (int& f : free_)
    if (f == 0) f = n_free_++;
}

}  // namespace vpc
