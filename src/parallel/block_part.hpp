#pragma once
// A rank's part of a generated mesh cut from the rank's own block (issue 30): no rank holds
// the whole mesh. Each rank builds its block of the grid with a layer of cells around it
// (MeshBlock, made by the case loader), computes there what rank 0 computes on the whole
// mesh (Dirichlet components, contact rows, Γ3 measures: WholeMeshData, whose values at the
// block's own nodes are the whole mesh's, to the bit), numbers its own nodes and free dofs
// after the lower ranks' and asks the owners of its ghost nodes for theirs. The part is the
// one distribute_mesh sends for the same cells per rank, piece for piece.
#include "la/comm.hpp"
#include "part/mesh_part.hpp"
#include "problem/problem.hpp"
#include "run/solver_plan.hpp"

#include <mpi.h>

namespace vpc {

/// Problem::validate where the problem's mesh is a block (Problem::block), with the checks that
/// need the whole mesh made on all blocks together: every block's own checks, the parts the case
/// names have facets somewhere, a symmetry plane has one axis, Γ3 has a free node, the body is
/// held. Collective; every rank throws the error of the lowest rank that found one. Returns the
/// block's contact rows, which the checks build (Problem::validate), for the sizes and the part.
ContactRows validate_blocks(const la::Comm& comm, const Problem& p);

/// The sizes the solver plan takes (problem_size on the whole mesh), summed over the blocks; the
/// factor estimates (rank 0's only) from the generator's grid coarsened to at most about 30,000
/// nodes (scale_factors; the whole grid below that, as problem_size). Collective. `rows`: the
/// block's contact rows (validate_blocks'); null: built here.
ProblemSize block_problem_size(const la::Comm& comm, const Problem& p, const ContactRows& rows = nullptr);

/// The rank's part, from its block (Problem::block): the part distribute_mesh gives it for the
/// cells per rank of MeshBlock::cell_rank. Collective. `rows`: as block_problem_size.
PartPieces block_part_pieces(MPI_Comm comm, const Problem& p, ContactRows rows = nullptr);

}  // namespace vpc
