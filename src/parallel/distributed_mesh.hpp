#pragma once
// One rank's part of a mesh partitioned over an MPI communicator.
//
// Rank 0 holds the mesh as read (or generated), partitions its cells with PTScotch
// (PETSc's MatPartitioning on the dual graph: cells sharing a facet), numbers the
// nodes so that each rank owns a contiguous range (a node belongs to the lowest
// rank among its cells), and sends each rank its cells and every node they touch.
// The nodes a rank does not own form its ghost layer. The free displacement dofs
// (V^h: clamped nodes dropped, (2.4)) are numbered node by node in that order, so
// each rank's owned dofs are contiguous too.
//
// Locally a part is an ordinary vpc::Mesh (owned nodes first, then ghosts; owned
// cells in their original order; the Γ2 facets of owned cells), so the serial
// element kernels and assembly loops run on it unchanged, and its DofMap numbers
// the local free dofs exactly as PETSc's ghosted vectors lay them out (owned, then
// ghosts).
#include "fem/dof_map.hpp"
#include "mesh/mesh.hpp"
#include "scheme/problem.hpp"

#include <mpi.h>
#include <petscsys.h>

#include <Eigen/Dense>
#include <vector>

namespace vpc {

/// A contact node (a row of N) that this part touches.
struct LocalContactNode {
  int row = 0;         // index of the row in the serial numbering (TimeStepper::contact_nodes order)
  int local_node = 0;  // in the local mesh
  bool owned = false;  // the row lives on this rank (its node is owned)
  Point direction{};   // ν, unit
  double gap = 0;      // g at the node
  double measure = 0;  // its tributary measure on Γ3 (tributary_measures, scheme/problem.hpp)
};

struct DistributedMesh {
  MPI_Comm comm = MPI_COMM_WORLD;
  Mesh mesh;                          // owned cells; owned nodes first, then the ghost layer
  int n_owned_nodes = 0;
  std::vector<PetscInt> global_node;  // global (partitioned) node number per local node
  std::vector<int> original_node;     // node number in the mesh as read, per local node
  std::vector<int> original_cell;     // cell number in the mesh as read, per owned cell
  DofMap dofs;                        // local free dofs: owned first, then ghosts (= VecGhost local form)
  int n_owned_dofs = 0;
  std::vector<PetscInt> global_dof;   // global free dof per local free dof
  std::vector<LocalContactNode> contact;  // owned and ghost contact nodes
  int n_contact = 0;                  // m: rows of N over all ranks
  PetscInt n_global_nodes = 0, n_global_dofs = 0;
  long long n_global_cells = 0;
  PetscInt node_begin = 0, dof_begin = 0;  // first owned global node and dof

  int n_local_nodes() const { return mesh.n_nodes(); }
  int n_ghost_nodes() const { return n_local_nodes() - n_owned_nodes; }
  int n_ghost_dofs() const { return dofs.n_free() - n_owned_dofs; }
  /// Global node numbers of the ghost nodes (for VecCreateGhost).
  std::vector<PetscInt> ghost_nodes() const;
  std::vector<PetscInt> ghost_dofs() const;
};

/// Partitions problem.mesh (read on rank 0; other ranks' meshes are ignored) and
/// gives every rank its part, with the contact rows and Γ2 facets of the serial
/// TimeStepper. Collective on comm.
DistributedMesh distribute_mesh(MPI_Comm comm, const Problem& problem);

}  // namespace vpc

namespace vpc {

/// Rank 0 gets the values of every rank's items (`ids`: their numbers in the mesh
/// as read, n_components values each), placed at those numbers in a vector of
/// n_global items; other ranks get an empty vector. Collective.
Vector gather_to_root(MPI_Comm comm, const std::vector<int>& ids, const double* values, int n_components,
                      long long n_global);

}  // namespace vpc
