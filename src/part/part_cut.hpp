#pragma once
// Cutting parts from the whole problem: its derived data (Dirichlet conditions,
// materials, loaded facets, contact rows (3.9)) computed once on the whole mesh,
// the global numbering of nodes and free dofs, and the share of one part. One
// process cuts one part, the whole mesh (whole_mesh_part); under MPI rank 0 cuts
// one per rank and sends it (parallel/distributed_mesh.cpp).
#include "part/mesh_part.hpp"
#include "problem/contact_pairs.hpp"
#include "problem/contact_rows.hpp"
#include "problem/problem.hpp"

#include <functional>
#include <vector>

namespace vpc {

/// The problem's data on the whole mesh, computed once, from which parts are cut.
struct WholeMeshData {
  std::vector<int> cell_material;  // cell_materials
  std::vector<int> cell_body;      // cell_bodies
  std::vector<int> traction_facets;
  std::vector<std::vector<int>> pressure_facets;
  DirichletDofs dirichlet;
  ContactRows shared_rows;              // the contact rows, shared with the set-up that built them
  const std::vector<ContactRow>& rows;  // *shared_rows
  std::vector<int> row_of;       // per node: its contact row, −1 off Γ3
  /// The large-sliding pairs' sides (surface_facets), from which each part takes its piece.
  struct SlidingPair {
    int pair = 0;
    SurfaceFacets slave, master;
  };
  std::vector<SlidingPair> sliding;
  /// Throws vpc::Error as the functions of problem/problem.hpp it calls. `rows`: the problem's
  /// contact rows as its validation built them (Problem::validate); null: built here.
  explicit WholeMeshData(const Problem& p, ContactRows rows = nullptr);
};

/// The free components of `node` (DirichletDofs::condition −1).
int free_components(const DirichletDofs& dirichlet, int node, int dim);

/// The global numbering of the whole mesh's nodes and free dofs: the nodes of
/// `owned[0]` (in its order), then of `owned[1]`, ...; the free components of a
/// node numbered together, in order. Numbers start at `first_node` and `first_free`
/// (a block's own nodes after the lower ranks': parallel/block_part.cpp).
struct WholeNumbering {
  std::vector<long long> node;       // global number per node
  std::vector<long long> first_dof;  // per node: its first free dof, −1 where none
  long long n_dofs = 0;              // the last number given + 1
  WholeNumbering(const std::vector<std::vector<int>>& owned, const DirichletDofs& dirichlet, int dim,
                 long long first_node = 0, long long first_free = 0);
};

/// The contact node of `row` (the row numbered `k`) in a part, at its local node.
/// The one place a contact row's law and geometry reach the scheme.
PartContactNode part_contact_node(int k, const ContactRow& row, int local_node, bool owned);

/// Adds a loaded facet of the part (its nodes in `mesh`, the part's): `load` 0 on Γ2, k under
/// pressure load k − 1, into pieces.traction_facets or pieces.pressure_facets[k − 1].
void add_loaded_facet(PartPieces& pieces, Mesh& mesh, const int* nodes, int load);

/// The nodes (the whole mesh's, sorted) that a part owning the nodes `owns` accepts needs for its
/// pieces of the large-sliding pairs (MeshPart::sliding): those of the cells behind the slave facets
/// with a node it owns and behind every master facet, where it owns a slave node. Under MPI they
/// join the part, as ghosts where it does not own them (distribute_mesh).
std::vector<int> sliding_band(const Mesh& mesh, const WholeMeshData& whole, const std::function<bool(int)>& owns);

/// The pieces of the part whose local nodes are `nodes` (numbers of the whole mesh:
/// its `n_owned` owned nodes first, then the ghosts) and whose cells are `cells`:
/// everything but the communicator, the mesh and the loaded facets, which are in
/// the part's own mesh (the caller's).
PartPieces cut_part(const Problem& p, const WholeMeshData& whole, const WholeNumbering& numbering,
                    const std::vector<int>& nodes, int n_owned, const std::vector<int>& cells);

}  // namespace vpc
