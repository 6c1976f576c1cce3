// Each rank's part cut from its own block of a generated mesh (parallel/block_part.hpp) against
// the part rank 0 cuts from the whole mesh with the same cells per rank (distribute_mesh):
//   mpirun -np P vpcontact_mpi_block_parts CASE [--n N]
// Every piece must be equal, numbers and values bit for bit (so the runs are the same run), and
// no rank's block may hold more than its cells and a layer of cells around them.
#include "petsc_main.hpp"
#include "cases/builtin_cases.hpp"
#include "la/petsc.hpp"
#include "parallel/block_part.hpp"
#include "parallel/distributed_mesh.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace {

int differences = 0;

template <typename T>
void expect_equal(int rank, const char* what, const T& a, const T& b) {
  if (a == b) return;
  ++differences;
  fmt::print("rank {}: {} differs\n", rank, what);
}

void compare(int rank, const vpc::MeshPart& a, const vpc::MeshPart& b) {
  expect_equal(rank, "n_owned_nodes", a.n_owned_nodes, b.n_owned_nodes);
  expect_equal(rank, "global_node", a.global_node, b.global_node);
  expect_equal(rank, "original_node", a.original_node, b.original_node);
  expect_equal(rank, "first_dof", a.first_dof, b.first_dof);
  expect_equal(rank, "original_cell", a.original_cell, b.original_cell);
  expect_equal(rank, "cell_material", a.cell_material, b.cell_material);
  expect_equal(rank, "cell_body", a.cell_body, b.cell_body);
  expect_equal(rank, "traction_facets", a.traction_facets, b.traction_facets);
  expect_equal(rank, "pressure_facets", a.pressure_facets, b.pressure_facets);
  expect_equal(rank, "dirichlet", a.dirichlet, b.dirichlet);
  expect_equal(rank, "dirichlet_on_parts", a.dirichlet_on_parts, b.dirichlet_on_parts);
  expect_equal(rank, "dirichlet_components", a.dirichlet_components, b.dirichlet_components);
  expect_equal(rank, "dirichlet_nodes", a.dirichlet_nodes, b.dirichlet_nodes);
  expect_equal(rank, "global_dof", a.global_dof, b.global_dof);
  expect_equal(rank, "n_contact", a.n_contact, b.n_contact);
  expect_equal(rank, "n_global_nodes", a.n_global_nodes, b.n_global_nodes);
  expect_equal(rank, "n_global_dofs", a.n_global_dofs, b.n_global_dofs);
  expect_equal(rank, "n_global_cells", a.n_global_cells, b.n_global_cells);
  expect_equal(rank, "contact nodes", a.contact.size(), b.contact.size());
  for (std::size_t k = 0; k < std::min(a.contact.size(), b.contact.size()); ++k) {
    const vpc::PartContactNode &x = a.contact[k], &y = b.contact[k];
    const bool same = x.row == y.row && x.local_node == y.local_node && x.owned == y.owned && x.direction == y.direction &&
                      x.gap == y.gap && x.measure == y.measure && x.law == y.law && x.datum == y.datum &&
                      x.obstacles == y.obstacles && x.masters == y.masters && x.pair == y.pair;
    if (!same) {
      ++differences;
      fmt::print("rank {}: contact node {} (row {} / {}) differs\n", rank, k, x.row, y.row);
      break;
    }
  }
  const vpc::Mesh &m = a.mesh(), &n = b.mesh();
  expect_equal(rank, "mesh nodes", m.nodes(), n.nodes());
  expect_equal(rank, "mesh cells", m.cell_array(), n.cell_array());
  std::vector<int> fa, fb;
  for (int f = 0; f < m.n_facets(); ++f) fa.insert(fa.end(), m.facet(f), m.facet(f) + m.nodes_per_facet());
  for (int f = 0; f < n.n_facets(); ++f) fb.insert(fb.end(), n.facet(f), n.facet(f) + n.nodes_per_facet());
  expect_equal(rank, "mesh facets", fa, fb);
}

int run(int argc, char** argv) {
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const vpc::la::Comm c = vpc::la::make_mpi_comm(comm);
  const int rank = c.rank(), size = c.size();
  vpc::require(argc >= 2, "usage: vpcontact_mpi_block_parts CASE [--n N]");
  vpc::MeshRequest whole, block;
  for (int i = 2; i + 1 < argc; i += 2)
    if (std::string(argv[i]) == "--n") whole.cells = block.cells = std::stoi(argv[i + 1]);
  block.build = false;
  block.block = vpc::MeshRequest::Block{rank, size};
  // The whole mesh on rank 0 (as distribute_mesh has it), every rank's block.
  const vpc::Case b = vpc::load_case(argv[1], {}, block);
  const vpc::Case w =
      vpc::load_case(argv[1], {}, rank == 0 ? whole : vpc::MeshRequest{false, b.problem->mesh.dim(), whole.cells, {}});
  vpc::require(b.problem->block != nullptr, "{}: no block was built (a generated mesh of one body is expected)", argv[1]);
  vpc::validate_blocks(c, *b.problem);
  const vpc::MeshBlock& mb = *b.problem->block;

  // Rank 0's cells per rank, from the blocks: each rank's own cells.
  std::vector<std::vector<long long>> own(static_cast<std::size_t>(size));
  for (std::size_t k = 0; k < mb.cell_id.size(); ++k)
    if (mb.cell_rank[k] == rank) own[0].push_back(mb.cell_id[k]);
  const std::vector<std::vector<long long>> at_root = c.exchange(own);
  std::vector<int> cell_rank;
  if (rank == 0) {
    cell_rank.assign(static_cast<std::size_t>(w.problem->mesh.n_cells()), -1);
    for (int r = 0; r < size; ++r)
      for (const long long id : at_root[static_cast<std::size_t>(r)]) cell_rank[static_cast<std::size_t>(id)] = r;
  }
  const vpc::MeshPart from_whole = vpc::distribute_mesh(comm, *w.problem, cell_rank);
  const vpc::MeshPart from_block = vpc::make_mesh_part(vpc::block_part_pieces(comm, *b.problem));
  compare(rank, from_whole, from_block);

  // The block: the part's cells and at most a layer around them (a layer of the grid's boxes on
  // each side: at most 3^d times the part's cells, far less on a real split).
  const long long part_cells = from_block.mesh().n_cells(), block_cells = b.problem->mesh.n_cells();
  const long long total = c.sum(part_cells);
  fmt::print("rank {}: {} of {} cells ({:.1f} %), block {} cells\n", rank, part_cells, from_block.n_global_cells,
             100.0 * static_cast<double>(part_cells) / static_cast<double>(from_block.n_global_cells), block_cells);
  if (total != from_block.n_global_cells) {
    ++differences;
    fmt::print("rank {}: the parts' cells sum to {}, not {}\n", rank, total, from_block.n_global_cells);
  }
  // Each part near 1/P of the cells (whole slabs of the grid: within 30 % here), each block far
  // from the whole mesh.
  const double share = static_cast<double>(total) / size;
  if (static_cast<double>(part_cells) > 1.3 * share || (size > 1 && 2.0 * static_cast<double>(block_cells) >= (size + 2) * share)) {
    ++differences;
    fmt::print("rank {}: part of {} cells and block of {} cells, against {} cells a rank: FAILED\n", rank, part_cells,
               block_cells, share);
  }
  const int failed = static_cast<int>(c.sum(static_cast<long long>(differences)));
  if (rank == 0) fmt::print("{}\n", failed == 0 ? "PASSED" : "FAILED");
  return failed == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return vpc::test::petsc_main(argc, argv, "vpcontact_mpi_block_parts", run); }
