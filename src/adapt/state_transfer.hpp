#pragma once
// The state of a run carried through the changes of a bisection forest (issue 51): gathered from a
// stepper's mesh into the forest's numbering, carried through each coarsening and refinement, then
// scattered into the stepper of the adapted mesh.
//   on refinement, exactly: u, β and every per-node contact field interpolated (a new node takes its
//     edge's mean: P1 fields are unchanged), σ, ε, z inherited by the children (σ = ℰε(u) + z holds
//     on each child as on its parent, since ε of a P1 field on a child is the parent's);
//   on coarsening: u, β and the contact fields by injection (the remaining nodes keep their values:
//     0 ≤ β ≤ 1 is kept), z by the area-weighted mean of the children, ε(u) recomputed on the parent
//     and σ = ℰε(u) + z.
// The contact forces are carried as the pressure λ_i / |Γ3|_i and multiplied by the new nodes'
// measures: a warm start for the next step only, which computes them again.
#include "mesh/bisection.hpp"
#include "scheme/time_stepper.hpp"

#include <vector>

namespace vpc {

struct ForestState {
  int n = 0;  // the state's step and time
  double t = 0;
  int dim = 2;
  /// Per forest node (BisectionForest numbering; a removed node keeps stale values): d numbers of u, β.
  std::vector<double> u, beta;
  /// Per forest node, the contact fields packed (contact_width numbers; NaN where the node is not a
  /// contact node): λ / |Γ3|_i (contact_block), the slip increment (contact_block − 1), the accumulated
  /// slip and the status (with friction), then each surface field.
  std::vector<double> contact;
  int contact_width = 0;
  int contact_block = 1;
  /// The leaves the cell fields are on (BisectionForest::leaves() order), and 6 numbers a leaf of σ, ε, z.
  std::vector<int> leaves;
  std::vector<double> sigma, eps, z;
};

/// The state `carry` of the stepper `s` (on the forest's leaf mesh) in the forest's numbering.
ForestState gather_state(const BisectionForest& forest, const TimeStepper& s, const State& carry);

/// After forest.coarsen: the fields on the forest's leaves now (see above). `elasticity`: per coarse cell.
void carry_through_coarsening(const BisectionForest& forest, const std::vector<const Elasticity*>& elasticity,
                              ForestState& fs);

/// After forest.refine: the fields on the forest's leaves and nodes now.
void carry_through_refinement(const BisectionForest& forest, ForestState& fs);

/// The state of `fs` on the stepper `s` of the forest's leaf mesh (its contact rows and measures).
State scatter_state(const BisectionForest& forest, const ForestState& fs, const TimeStepper& s);

/// ε of the P1 displacement `u` (d numbers a forest node) on forest cell c (any cell, not only a leaf).
SymTensor forest_cell_strain(const BisectionForest& forest, const std::vector<double>& u, int dim, int c);

}  // namespace vpc
