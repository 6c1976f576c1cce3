#pragma once
// The contact set of a part: its contact nodes (the cut's, MeshPart::contact, taken at set-up), their
// rows over the part's free dofs (N of (3.9)) and friction's frame on them (SPEC §7). A set is a
// value, fixed once made: the discrete system holds the set of the configuration a step starts from
// (DiscreteSystem::contact), made at set-up and, where large-sliding pairs move the nodes, made anew
// from the moved nodes (scheme/pair_slider.hpp), never changed in place. The solvers' constraints
// (ContactConstraints) are made from it; the step's data (gap, friction bounds, slip shift), its
// checks and the outputs read it.
#include "part/contact_matrix.hpp"
#include "problem/problem.hpp"
#include "solvers/contact_solver.hpp"

#include <vector>

namespace vpc {

struct ContactSet {
  /// The part's contact nodes, owned and ghost, by row (the rows of `local`): the one place a
  /// contact node lives once the part is set up.
  std::vector<PartContactNode> nodes;
  /// The part's contact rows, ghost rows included, over its local free dofs (ContactColumns::local):
  /// the primal solver's reflections (scheme/scheme_solvers.cpp).
  ContactMatrix local;
  /// N: one row per owned contact node, in `nodes` order, over the owned free dofs
  /// (ContactConstraints::N), and each row's free dofs (columns of N) in component order
  /// (ContactConstraints::node_dofs): local's owned rows.
  SparseMatrix N;
  std::vector<std::vector<int>> dofs;
  /// The same rows whole, over the local free dofs: where the pairs are spread
  /// (PartPieces::pairs_spread) a row's entries at its ghost masters too, which N leaves to their
  /// owners (remote_pieces). g − N_local u with u's ghosts current is each row's gap left, exact
  /// and without communication (contact_gap.hpp); else N_local has N's entries alone.
  SparseMatrix N_local;
  /// Friction's frame on the owned rows (SPEC §7), built where some entry has friction or wear
  /// (ContactSpec::tangential: wear needs the slip); every field empty without.
  struct FrictionFrame {
    /// T, tangent_dof, Coulomb's μ_i and shear limit τ_max |Γ3|_i (+∞: none) (ContactConstraints; set_tangents)
    SparseMatrix T;
    std::vector<int> tangent_dof;
    /// T's rows whole over the local free dofs, as N_local (the slip shift from u with its ghosts).
    SparseMatrix T_local;
    Vector mu, limit;
    std::vector<const FrictionLaw*> row_friction;  // per owned row (nullptr: a frictionless entry's)
    std::vector<std::shared_ptr<const FrictionLaw>> laws;  // ContactSpec::frictions()
    /// The pairs' masters' mean over the owned dofs and the local ones (ContactMatrix::master_mean,
    /// taken from the owned rows and from `local`: friction alone reads it): friction's slip on a
    /// pair is the slave's relative to it. The owned one leaves out ghost masters: the primal reads
    /// it, which refuses spread pairs.
    SparseMatrix master_mean, local_master_mean;
  } friction;
  /// The gap where no obstacle (nor a sliding pair's master) lies ahead: the diagonal of the
  /// bodies' bounding box over every process (contact_miss_gap).
  double miss_gap = 0;

  ContactSet() = default;
  /// The set of `part`'s contact nodes `nodes` (the cut's: part.contact) under p's laws. Collective.
  ContactSet(const Problem& p, const MeshPart& part, std::vector<PartContactNode> nodes);
  /// The set of the same part with its nodes moved (large sliding: scheme/pair_slider.hpp): the
  /// rows and frame made from `moved`, the miss gap this set's.
  ContactSet moved(const Problem& p, const MeshPart& part, std::vector<PartContactNode> moved) const;

  /// The rows of N this process owns, in the nodes' order (ContactConstraints::rows).
  std::vector<int> owned_row_numbers() const;
  /// Their laws' index (ContactNode::law: in ContactSpec::laws() and frictions()), in that order.
  std::vector<int> owned_row_laws() const;
  /// The solvers' constraints: N, the gap g(0) `gap`, each row's law and datum and, with friction,
  /// its frame (the bounds and shift zero until the first step's); where the pairs are spread, the
  /// other ranks' pieces of their rows here (remote_pieces) and RemoteRows::spread, set here alone.
  /// Collective.
  ContactConstraints constraints(const Problem& p, const MeshPart& part, Vector gap) const;

 private:
  /// The rows and frame from `nodes`.
  void set_rows(const Problem& p, const MeshPart& part);
  /// The set of `nodes` with the miss gap `miss_gap` (both constructors' work).
  ContactSet(const Problem& p, const MeshPart& part, std::vector<PartContactNode> nodes, double miss_gap);
  /// Each owned node's surface laws' data there (SurfaceHistory::check_at): a located error for a bad one.
  /// Once, by the set-up's constructor (a moved set keeps the nodes and their laws).
  void check_surface_laws(const Problem& p, const MeshPart& part) const;
  /// The frame from N_local, the rows' dofs and local's masters' mean (taken).
  void set_friction_frame(const Problem& p, const MeshPart& part);
};

}  // namespace vpc
