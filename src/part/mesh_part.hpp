#pragma once
// This process's part of the discretization: its cells, the nodes they touch
// (owned first, then the ghost layer owned by other processes), the free
// displacement dofs of those nodes (V^h, (2.4)) in the same order, the Γ2 facets
// of its cells and the contact rows (3.9) it touches, with the global numbering
// of nodes and dofs as la::Layouts. The scheme (scheme/time_stepper.hpp) runs on
// a part; on one process the part is the whole mesh in its own numbering
// (whole_mesh_part), on many it comes from distribute_mesh (parallel/). Both
// cut it from the whole problem with cut_part (part/part_cut.hpp) and finish
// it with make_mesh_part, so that a field of a part is filled in one place.
#include "contact/contact_node.hpp"
#include "contact/shared_contact_rows.hpp"
#include "contact/sliding_surface.hpp"
#include "fem/dof_map.hpp"
#include "la/layout.hpp"
#include "mesh/mesh.hpp"

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace vpc {

struct Problem;

/// A contact node (a row of N) that the part touches (made by part_contact_node): the row's
/// block, its masters numbered as the part's nodes (on an owned row, whose rank owns its master
/// nodes too or, where the pairs are spread (PartPieces::pairs_spread), holds them as ghosts:
/// cut_part; else empty).
struct PartContactNode : ContactNode {
  int row = 0;         // the row of N, in the numbering of the whole mesh (increasing node order)
  int local_node = 0;  // in the part's mesh
  bool owned = false;  // the row lives on this process (its node is owned)
};

/// What a part takes from the whole mesh and problem, which it cannot compute from
/// its own cells: its numbering in the whole, its share of the problem's data and
/// the global sizes. On many processes this is what rank 0 sends each rank.
struct PartPieces {
  la::Comm comm;
  std::shared_ptr<const Mesh> mesh_ptr;  // owned cells; owned nodes first, then the ghost layer
  int n_owned_nodes = 0;
  std::vector<long long> global_node;  // global (partitioned) number per local node
  std::vector<int> original_node;      // number in the mesh as read, per local node
  /// Per local node: the global number of its first free dof (its other free
  /// components follow it), −1 where it has none.
  std::vector<long long> first_dof;
  std::vector<int> original_cell;      // number in the mesh as read, per cell
  std::vector<int> cell_material;      // per cell: its index in Problem::material_list()
  std::vector<int> cell_body;          // per cell: its body (Mesh::cell_body; SPEC §8)
  std::vector<int> traction_facets;    // Γ2 facets of the part's mesh
  std::vector<std::vector<int>> pressure_facets;  // per Problem::pressure load, facets of the part's mesh
  /// Per local full dof (node · d + component): the condition prescribing it
  /// (DirichletDofs::condition: −1 free, 0 zero, k ≥ 1 Problem::displacement[k − 1]).
  std::vector<int> dirichlet;
  /// Per local node, a bit for each Dirichlet part it lies on (DirichletDofs::on_parts).
  std::vector<std::uint64_t> dirichlet_on_parts;
  /// Per Dirichlet part, the components it prescribes (DirichletDofs::components).
  std::vector<unsigned> dirichlet_components;
  /// Owned and ghost contact nodes, by row, as cut: the discrete system's contact set takes them
  /// at set-up (DiscreteSystem::contact, ContactSet::nodes: empty here after), and is where they live.
  std::vector<PartContactNode> contact;
  std::vector<SlidingPairPiece> sliding;  // the large-sliding pairs' surfaces (none without owned slave nodes)
  int n_contact = 0;                     // m: rows of N over all processes
  /// The pairs' rows spread over the ranks (--spread-pairs, distribute_mesh): an owned
  /// row's master nodes may be ghosts, its entries there other ranks' remote pieces (the same on every
  /// rank; false on one process, where nothing is spread).
  bool pairs_spread = false;
  long long n_global_nodes = 0, n_global_dofs = 0, n_global_cells = 0;
};

/// A part: its pieces and what follows from them on the process itself.
struct MeshPart : PartPieces {
  DofMap dofs;                         // local free dofs: owned first, then ghosts
  /// The local nodes on a Dirichlet part, each with its bits of DirichletDofs::on_parts
  /// (for the reactions).
  std::vector<std::pair<int, std::uint64_t>> dirichlet_nodes;
  int n_owned_dofs = 0;
  std::vector<long long> global_dof;   // global free dof per local free dof
  std::shared_ptr<const la::Layout> node_layout, dof_layout;

  const Mesh& mesh() const { return *mesh_ptr; }
  int n_local_nodes() const { return mesh().n_nodes(); }
};

/// Makes the part of `pieces`: its free dofs (owned first: the owned nodes come
/// first), their global numbers, its Dirichlet nodes and its layouts. Collective
/// on pieces.comm (the layouts).
MeshPart make_mesh_part(PartPieces pieces);

/// One process: the problem's mesh as it is (shared, not copied), every node
/// owned, Γ2 and the contact rows of the problem: `rows`, as its validation built them
/// (Problem::validate), or built here (null). Throws vpc::Error for a contact direction into the
/// body or a Γ3 without a free node (contact_rows).
MeshPart whole_mesh_part(std::shared_ptr<const Problem> problem, ContactRows rows = nullptr);

}  // namespace vpc
