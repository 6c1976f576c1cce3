#pragma once
// N of (3.9) on a part: each contact node's free dofs and its row's entries ν_i on them. The
// discrete system keeps them over the part's local dofs (the reflections of K_rot's local
// matrix), its N is their owned rows (owned_rows) over the owned dofs, with, where the pairs are
// spread over the ranks, the rows' entries at ghost masters sent to their owners (remote_pieces),
// and the outputs' tangents take them over the contact nodes' own dofs; set_tangents takes the
// nodes' dofs.
#include "la/linear_solver.hpp"
#include "part/mesh_part.hpp"
#include "solvers/contact_solver.hpp"

#include <span>
#include <vector>

namespace vpc {

/// Which numbering the columns have (every contact node the part touches is a row, ghosts included).
enum class ContactColumns {
  local,    // the part's local free dofs (owned, then ghosts)
  compact,  // every node the part touches over those nodes' free dofs alone, numbered node after
            // node in component order: O(contact nodes) however large the part (the outputs' tangents)
};

struct ContactMatrix {
  SparseMatrix N;                           // a row per node, in the nodes' order (owned_rows: the owned ones)
  std::vector<std::vector<int>> node_dofs;  // per row, its node's free dofs (columns of N) in component order
  std::vector<int> component;               // compact: per column, the component of its dof (else empty)
  /// A pair's slave node relative to its masters (friction on pairs; solvers/contact_frame.hpp):
  /// (M u) at each free dof (j, x) of a pair row's node j is Σ_k w_k u_(k, x) over its masters' free
  /// dofs (k, x), the mortar's interpolation of the master side. n × n over N's columns; empty
  /// (0 × 0) in the compact numbering or without pairs.
  SparseMatrix master_mean;
};

/// The rows of a part's contact nodes `nodes` (ContactSet::nodes, or the cut's part.contact) over
/// its free dofs `dofs`.
ContactMatrix contact_matrix(const DofMap& dofs, std::span<const PartContactNode> nodes, ContactColumns columns);

/// The owned nodes' rows of `local` (contact_matrix over ContactColumns::local), whole: over the
/// local free dofs, a spread pair row's ghost masters' too (PartPieces::pairs_spread; else every
/// entry is in the owned dofs, which come first), with their rows' dofs (the masters' mean is
/// local's: only owned rows have masters), taken from the one matrix rather than built again. ContactSet keeps them for
/// g − N u from u with its ghosts, and cuts the solvers' N from them (owned_columns, remote_pieces).
ContactMatrix owned_rows(const ContactMatrix& local, const MeshPart& part, std::span<const PartContactNode> nodes);

/// A's columns of the owned free dofs (the first ones): ContactConstraints::N (and T) of whole rows.
/// A 0 × 0 matrix (no tangents) as it is; one with no rows (a rank without contact rows) 0 × owned.
SparseMatrix owned_columns(const SparseMatrix& A, const MeshPart& part);

/// Other ranks' pieces of their rows in this rank's owned dofs (ContactConstraints::remote), from each
/// rank's whole rows (owned_rows): `N` this rank's rows (global numbers `rows`) over its local free
/// dofs, `T` their `tangents` tangent rows each (0 × 0 without friction). Each entry in a ghost column
/// goes to that dof's owner (one Comm::exchange). Empty (`spread` unset: ContactSet::constraints sets
/// it) where the part's pairs are not spread. Collective where they are.
RemoteRows remote_pieces(const MeshPart& part, const std::vector<int>& rows, const SparseMatrix& N,
                         const SparseMatrix& T, int tangents);

/// How many times contact_matrix has run in this process: a set-up runs it once (tests count it).
long long contact_matrix_builds();

}  // namespace vpc
