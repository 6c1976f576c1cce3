#pragma once
// The cells around each node of a mesh, in CSR form: the cells of node i are
// list[start[i] .. start[i + 1]), in increasing order. 4 bytes a cell's node.
#include "mesh/mesh.hpp"

#include <cstddef>
#include <vector>

namespace vpc {

struct NodeCells {
  std::vector<int> start, list;
  explicit NodeCells(const Mesh& mesh) : start(static_cast<std::size_t>(mesh.n_nodes()) + 1, 0) {
    const int npc = mesh.nodes_per_cell();
    for (int c = 0; c < mesh.n_cells(); ++c)
      for (int a = 0; a < npc; ++a) ++start[static_cast<std::size_t>(mesh.cell(c)[a]) + 1];
    for (std::size_t i = 0; i + 1 < start.size(); ++i) start[i + 1] += start[i];
    list.resize(static_cast<std::size_t>(start.back()));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int c = 0; c < mesh.n_cells(); ++c)
      for (int a = 0; a < npc; ++a) list[static_cast<std::size_t>(fill[static_cast<std::size_t>(mesh.cell(c)[a])]++)] = c;
  }
};

}  // namespace vpc
