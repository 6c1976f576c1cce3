#pragma once
// Large sliding between bodies (SPEC §8) as the run's own object, chosen once: a `sliding = "large"`
// pair's rows rebuilt at the start of every step by dual mortar between its surfaces moved by the
// displacement the step starts from, x + u_{n−1}: masters, weights, normals, measures and gaps of
// that configuration. The step's constraint is the gap's linearization about it,
// N_n (u_n − u_{n−1}) ≤ g(x + u_{n−1}), written on u_n as N_n u_n ≤ g(x + u_{n−1}) + N_n u_{n−1}
// (a master's prescribed components move the bound by their motion over the step, step_data.cpp);
// friction's slip is T_n (u_n − u_{n−1}).
//
// Each part holds its piece of the sliding surfaces (MeshPart::sliding, cut with the part: the
// slave facets at its owned slave nodes and the whole master side, with the cells behind them, over
// its own nodes), so a rank rebuilds its owned slave nodes' rows from its own nodes, at x + u. The
// slider keeps the part's K for the primal solver's K_rot and the displacement its rows were built
// at. Without a large-sliding pair the slider does nothing and keeps nothing.
#include "scheme/discrete_system.hpp"

#include <memory>

namespace vpc {

class PairSlider {
 public:
  virtual ~PairSlider() = default;
  /// Takes the part's K once the contact solver's set-up has used it (leaving K_local empty): kept
  /// where the contact solver is made again at each slide, else released.
  virtual void keep_stiffness(SparseMatrix& K_local) = 0;
  /// The contact set of sys in the configuration x + u (u: a state's displacement over the part's
  /// dofs, prescribed components included): sys.contact's nodes with the large-sliding pairs' rows
  /// moved, and their N and friction frame (ContactSet::moved). Null where the rows were built at u
  /// already (the set-up's at u = 0, a rejected attempt restored then retried): the set stays. The
  /// rows, and λ with them, are the slave nodes that had one at t = 0 (the pair's `search` must
  /// reach every slave node that may touch): one that no master facet covers within reach now gets
  /// no masters and the gap ContactSet::miss_gap (it cannot touch this step); a node without a row
  /// at t = 0 gets none. Each rank moves the rows of its owned slave nodes. The caller
  /// (TimeStepper) points sys.contact at the new set and makes the contact solver again for it
  /// (remake_contact_solver, with stiffness()). Collective.
  virtual std::shared_ptr<const ContactSet> slide(const DiscreteSystem& sys, const Vector& u) = 0;
  /// The part's K kept by keep_stiffness (empty where nothing slides).
  virtual const SparseMatrix& stiffness() const = 0;
};

/// The slider of sys's problem: one that slides where some pair has `sliding = "large"`, else one
/// that does nothing.
std::unique_ptr<PairSlider> make_pair_slider(const DiscreteSystem& sys);

}  // namespace vpc
