#pragma once
// One rank's block of a generated or refined mesh (issue 30): what a rank builds of a mesh that no
// rank holds whole. The block's cells are those of its rank's part of the grid (split_grid,
// mesh/generators.hpp) or the children of its coarse cells (split_cells, mesh/refine.hpp), and a
// layer of cells around them, so that every node
// of the rank's own cells has all its cells and boundary facets here: what is computed at
// a node from its cells and facets (its Dirichlet components, its contact row, its share of
// Γ3) comes out as on the whole mesh.
#include "mesh/generators.hpp"
#include "mesh/mesh.hpp"

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace vpc {

struct MeshBlock {
  int rank = 0, ranks = 1;
  std::vector<int> node_id, cell_id;  // numbers in the whole mesh, increasing
  std::vector<int> cell_rank;         // per cell: the rank whose part of the grid holds it
  long long whole_nodes = 0, whole_cells = 0;
  Point lo{0, 0, 0}, hi{0, 0, 0};     // the whole mesh's bounding box (a generator's box)
  std::array<int, 3> cells{0, 0, 0};  // a generator's cells per axis (0 beyond the dimension)
  Diagonal diagonal = Diagonal::right;
  std::shared_ptr<const Mesh> coarse;  // a refined file's mesh as read, the same on every rank
  int levels = 0;                      // and its refinements
  /// A check of the case that needs the whole mesh, which the loader leaves to all ranks together
  /// (validate_blocks), in the loader's order: that a part (a [[mesh.part]] predicate's, or one the
  /// case names) has facets, or a material's region cells, somewhere; else the loader's message (a
  /// named part's followed by the parts the mesh has).
  struct Check {
    enum class Of { part, region } of = Of::part;
    std::string name, message;
    bool list_parts = false;
  };
  std::vector<Check> checks;
  std::vector<std::pair<Point, std::string>> probes;  // [output] probes, each with its key's location
  std::string source;                                 // the case file, as its messages name it
};

/// Node i of a mesh that may be `block` as messages name it: its number in the whole mesh.
inline long long node_number(const MeshBlock* block, int i) {
  return block && !block->node_id.empty() ? block->node_id[static_cast<std::size_t>(i)] : i;
}

}  // namespace vpc
