#include "scheme/scheme_solvers.hpp"

#include "core/stopwatch.hpp"
#include "part/contact_matrix.hpp"
#include "scheme/pair_slider.hpp"
#include "solvers/contact_frame.hpp"
#include "solvers/primal_active_set.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

namespace vpc {

namespace {

using Clock = std::chrono::steady_clock;


/// Damage solvers kept for the step sizes in use.
constexpr std::size_t kDamageSolversKept = 4;

/// The contact solver of s.contact_pick for `constraints` (the primal takes s.K_factor and forms its
/// K_rot from K_local, the part's K).
std::unique_ptr<ContactSolver> contact_solver(const DiscreteSystem& sys, const SolverChoice& choice, SchemeSolvers& s,
                                              ContactConstraints constraints, const SparseMatrix& K_local) {
  const MeshPart& part = sys.part;
  ContactSolverOptions options = choice.contact_options;
  options.friction_tolerance = friction_force_tolerance(choice.residual_tolerance);
  if (s.contact_pick.name == "primal-active-set") {
    // Rows off the axes are turned into one dof each by node-local reflections Q: K_rot = Q K Q,
    // assembled from the cells' matrices like K (Q acts within each node's dofs). A pair's row also
    // writes its slave node in its masters' dofs: K_rot = Pᵀ K P (contact_basis), which every rank
    // forms from its own cells because the cells at a slave node are on the rank that owns it and
    // its masters (own_pairs_together).
    // Over the part's rows, ghosts included: every rank's cells need its nodes' basis (a ghost row's
    // reflection too). A pair row is never a ghost (its slave node's owner holds its masters).
    for (const PartContactNode& node : sys.contact->nodes)
      require(node.owned || node.pair < 0, "internal: contact pair row {} is a ghost on this rank", node.row);
    const ContactMatrix& local = sys.contact->local;
    const ContactBasis basis = contact_basis(local.N, local.node_dofs, sys.contact->friction.local_master_mean);
    std::shared_ptr<const la::SpdOperator> K_rot;
    if (part.comm.any(basis.P.size() > 0)) {  // else every row lies on an axis: K itself
      const SparseMatrix& P = basis.P;
      K_rot = sys.backend->assemble(basis.pairs()     ? SparseMatrix(P.transpose() * K_local * P)
                                    : P.size() > 0 ? SparseMatrix(P * K_local * P)
                                                   : K_local,  // no row of this rank's cells needs it
                                    *part.dof_layout, sys.K_block);
    }
    return make_primal_active_set_solver(sys.K, std::move(K_rot), std::exchange(s.K_factor, nullptr),
                                         std::move(constraints), 0, options.friction_tolerance);
  }
  return make_contact_solver(s.contact_pick.name, sys.K, s.K_factor, std::move(constraints),
                             la::factor_factory(sys.backend), options);
}

/// Where the case gives κ, for the message of an H that k κ makes singular (make_damage_solver).
std::string kappa_location(const Problem& p) {
  const std::string at = p.where("damage.kappa");
  return p.bodies.empty() ? at : at + " (or a [[body]]'s [body.damage] kappa)";
}

}  // namespace

SchemeSolvers set_up_solvers(DiscreteSystem& sys, const SolverChoice& choice, PairSlider& slider,
                             SetupTiming& timing, std::optional<SolverCost>& cost) {
  const MeshPart& part = sys.part;
  SchemeSolvers s;
  choice.stage(fmt::format("factorization of K ({} x {}, {} nonzeros; {})", part.n_global_dofs, part.n_global_dofs,
                           sys.K->nonzeros(), sys.backend->describe()));
  auto t1 = Clock::now();
  ContactConstraints constraints = contact_constraints(sys);
  // What the problem asks of its solver, against the table of what each solves (auto's choice and the refusals).
  const ContactNeeds needs = contact_needs(part.comm, constraints);
  s.contact_pick = pick_contact_solver(choice.contact, part.n_contact, sys.backend->linear_solver(), needs, constraints.block);
  refuse_unsolvable(s.contact_pick.name, needs);
  const bool primal = s.contact_pick.name == "primal-active-set";
  s.K_factor = sys.make_stiffness_factor();
  cost = check_before_factorizing(sys, *s.K_factor, choice, primal);
  // The primal contact solver factors K with its active rows when it first solves.
  if (!primal) s.K_factor->factorize(*sys.K, "elastic stiffness K");
  timing.factor_K = seconds_since(t1);
  timing.factored_K = process_memory();
  choice.stage("factorization of K", timing.factor_K);

  choice.stage(fmt::format("factorization of H ({} x {}, {} nonzeros)", part.n_global_nodes, part.n_global_nodes,
                           sys.H_first->nonzeros()));
  t1 = Clock::now();
  s.damage.for_step(sys, choice, sys.first_step, std::move(sys.H_first));
  timing.factor_H = seconds_since(t1);
  timing.factored_H = process_memory();
  choice.stage("factorization of H", timing.factor_H);

  choice.stage("contact set-up");
  t1 = Clock::now();
  s.contact = contact_solver(sys, choice, s, std::move(constraints), sys.K_local);
  slider.keep_stiffness(sys.K_local);  // a large-sliding pair's K_rot is made again
  timing.contact = seconds_since(t1);
  timing.contact_ready = process_memory();
  choice.stage("contact set-up", timing.contact);
  return s;
}

void remake_contact_solver(const DiscreteSystem& sys, const SolverChoice& choice, SchemeSolvers& s,
                           const SparseMatrix& K_local) {
  const Vector warm = s.contact->warm_state();
  if (s.contact_pick.name == "primal-active-set") s.K_factor = sys.make_stiffness_factor();  // the last went with it
  s.contact = contact_solver(sys, choice, s, contact_constraints(sys), K_local);
  s.contact->set_warm_state(warm);
}

DamageSolver& DamageSolvers::for_step(const DiscreteSystem& sys, const SolverChoice& choice, double k,
                                      std::unique_ptr<la::SpdOperator> H) {
  auto it = std::find_if(kept_.begin(), kept_.end(), [k](const ForStep& d) { return d.k == k; });
  if (it == kept_.end()) {
    const Vector warm = current_ ? current_->warm_state() : Vector();
    if (kept_.size() >= kDamageSolversKept) {  // the least recently used (never the current: it is last)
      dropped_factorizations_ += kept_.front().solver->n_factorizations();
      kept_.erase(kept_.begin());
    }
    if (!H)
      H = sys.backend->assemble(SparseMatrix(sys.M_local + (k * sys.kappa) * sys.A_local),
                                *sys.part.node_layout, 1);
    ++matrices_made_;
    kept_.push_back({k, make_damage_solver(choice.damage, std::move(H), la::factor_factory(sys.backend),
                                           choice.damage_reduced, kappa_location(*sys.problem))});
    kept_.back().solver->hold(sys.constant_damage);
    if (current_) kept_.back().solver->set_warm_state(warm);
    current_ = kept_.back().solver.get();
    return *current_;
  }
  if (it + 1 != kept_.end()) std::rotate(it, it + 1, kept_.end());
  DamageSolver* next = kept_.back().solver.get();
  if (next != current_) next->set_warm_state(current_->warm_state());  // the warm start is the state's
  current_ = next;
  return *next;
}

int DamageSolvers::n_factorizations() const {
  int n = dropped_factorizations_;
  for (const ForStep& d : kept_) n += d.solver->n_factorizations();
  return n;
}

double DamageSolvers::factor_bytes() const {
  double bytes = 0;
  for (const ForStep& d : kept_) bytes += d.solver->factor_bytes();
  return bytes;
}

}  // namespace vpc
