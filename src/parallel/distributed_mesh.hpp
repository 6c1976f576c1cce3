#pragma once
// One rank's part of a mesh partitioned over an MPI communicator.
//
// Rank 0 holds the mesh as read (or generated), partitions its cells with PTScotch
// (PETSc's MatPartitioning on the dual graph: cells sharing a facet), numbers the
// nodes so that each rank owns a contiguous range (a node belongs to the lowest
// rank among its cells; the nodes of contact pairs' rows are owned together:
// own_pairs_together), and sends each rank its cells and every node they touch.
// The nodes a rank does not own form its ghost layer; with spread_pairs, the masters of its
// spread pair rows join it too, cell-less. The free displacement dofs
// (V^h: clamped nodes dropped, (2.4)) are numbered node by node in that order, so
// each rank's owned dofs are contiguous too.
//
// Locally a part is an ordinary vpc::Mesh (owned nodes first, then ghosts; owned
// cells in their original order; the Γ2 facets of owned cells), so the element
// kernels and assembly loops run on it unchanged (part/mesh_part.hpp).
#include "part/mesh_part.hpp"
#include "problem/problem.hpp"

#include <mpi.h>

namespace vpc {

/// Partitions problem.mesh (read on rank 0, where the problem is validated; other
/// ranks' meshes are ignored) and gives every rank its part, with the contact rows
/// and Γ2 facets of the one-process part: rank 0 cuts every part from the whole problem
/// (cut_part) and each rank finishes its own (make_mesh_part). Collective on comm.
/// `cell_rank`: each cell's rank, instead of PTScotch's partition (rank 0's; the blocks of a
/// generated mesh, block_part.hpp, cut the same parts from their blocks). `rows`: rank 0's problem
/// validated, with the contact rows its validation built (Case::contact_rows); null: validated here.
/// `spread_pairs` (--spread-pairs, SolverChoice::spread_pairs): the pairs' rows are not owned
/// together with their masters; each goes with its slave node's owner, which holds the row's master
/// nodes it does not own as ghosts with no cell (PartPieces::pairs_spread), and for a large-sliding
/// pair every node of its piece of the surfaces (sliding_band, PartPieces::sliding).
MeshPart distribute_mesh(MPI_Comm comm, const Problem& problem, const std::vector<int>& cell_rank = {},
                         ContactRows rows = nullptr, bool spread_pairs = false);

}  // namespace vpc
