#pragma once
// Algebraic multigrid whose aggregates stay within one field (a body of a contact pair):
// the transfers are built on the matrix with the couplings between fields dropped, the
// level operators are the whole matrix's Galerkin products (segregated transfers, Wiesner,
// Mayr, Popp, Gee & Wall, IJNME 2021). Across a frictionless contact interface the tangential
// displacement jumps; an aggregate on both sides moves them together and its coarse space
// misses the sliding motion.
#include "la/petsc_util.hpp"

#include <vector>

namespace vpc::la {

/// Whether the owned rows' fields take more than one value over the communicator.
bool several_fields(MPI_Comm comm, const std::vector<int>& field);

/// A copy of A without its entries that couple rows of different fields (`field`: of each owned
/// row). Collective.
PMat within_fields(Mat A, const std::vector<int>& field);

/// After a PCMG's set-up on another matrix: A on its finest level, and on each coarser one
/// the Galerkin product Pᵀ A P of the next finer one by that level's interpolation P.
void galerkin_levels(PC pc, Mat A);

}  // namespace vpc::la
