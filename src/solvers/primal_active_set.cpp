#include "solvers/primal_active_set.hpp"

#include "core/error.hpp"
#include "solvers/contact_capabilities.hpp"

#include "solvers/active_set_history.hpp"
#include "solvers/primal_friction_iteration.hpp"
#include "solvers/primal_operator.hpp"
#include "solvers/pull_off.hpp"

#include <memory>

namespace vpc {

namespace {

/// The frictionless active-set Newton method over the operator: the rows have no tangents.
class PrimalNormalIteration final : public PrimalIteration {
 public:
  ContactReport solve(PrimalOperator& op, PrimalWarmStart& answers, int max_iterations, const Vector& F, Vector& u,
                      Vector& lambda) override {
    const ContactConstraints& c = op.constraints();
    const auto rows = op.n_rows();
    const la::Comm& comm = op.comm();
    const Vector b = op.rotate(F);
    Vector w = answers.start_point(op, F, u);
    const Vector lambda_in = lambda.size() == c.m ? local_rows(c, lambda) : Vector(Vector::Zero(rows));
    std::vector<char> active(static_cast<size_t>(rows));
    for (Eigen::Index i = 0; i < rows; ++i) active[i] = op.first_state(i, lambda_in[i], op.gap_left(w, i));
    Vector lambda_local = Vector::Zero(rows);
    ActiveSetHistory history;  // the active sets met in this solve
    ContactReport rep;
    bool monotone = false, converged = false;
    // An iterative solver finds the set with loose solves (the set decides by signs, not
    // digits), then confirms it with one at its own tolerance (an inexact semismooth Newton
    // method); a direct one is exact every time.
    bool tight = !op.iterative();
    for (int it = 0; it < max_iterations && !converged; ++it) {
      PrimalOperator::Iterate x = floating_iterate(op, active, b, w, tight, lambda_local, rep);
      std::vector<char>& next = x.next;
      if (comm.all(next == active)) {
        converged = tight;
        tight = true;
        continue;
      }
      if (monotone) {
        op.release_one(active, next, x.most_negative, x.worst);
        if (comm.all(next == active)) {  // what the rule would still release has λ = 0: KKT holds
          converged = tight;
          tight = true;
          continue;
        }
      }
      if (history.came_back(next, comm) && !monotone) {
        monotone = true;
        ++rep.cycles;
      }
      active = std::move(next);
    }
    answers.keep_answer(op, w, u);
    lambda = replicate(comm, c, lambda_local);
    ContactReport out = contact_report(op.K(), c, F, u, lambda, converged, rep.iterations);
    out.factorizations = rep.factorizations;
    out.cycles = rep.cycles;
    return out;
  }
  int most_iterations() const override { return kPrimalMaxIterations; }

 private:
  /// An iterate; where only the bonds hold a body (ContactConstraints::floating) a set that releases too
  /// many of them leaves K singular although an equilibrium exists (the pull-off test passed): a
  /// guess from an extrapolated warm start, or a Newton step that overshoots past L. That set is then
  /// taken with every released bond back on its spring (the bonds hold the body: check_body_held), and
  /// the iteration goes on from that solve.
  PrimalOperator::Iterate floating_iterate(PrimalOperator& op, std::vector<char>& active, const Vector& b, Vector& w,
                                           bool tight, Vector& lambda_local, ContactReport& rep) {
    if (!op.constraints().floating()) return op.iterate(active, b, w, tight, lambda_local, rep, none_);
    try {
      return op.iterate(active, b, w, tight, lambda_local, rep, none_);
    } catch (const Error&) {
      const ContactConstraints& c = op.constraints();
      bool released = false;
      for (Eigen::Index i = 0; i < op.n_rows(); ++i)
        if (active[static_cast<std::size_t>(i)] == PrimalOperator::kOff && c.bond_of(i) > 0) {
          active[static_cast<std::size_t>(i)] = PrimalOperator::kBonded;
          released = true;
        }
      if (!op.comm().any(released)) throw;  // not a released bond's doing
      return op.iterate(active, b, w, tight, lambda_local, rep, none_);
    }
  }
  NoTangents none_;
};

/// The solver's iteration, chosen once: HSW's with friction (the rows' tangents), else the frictionless one.
std::unique_ptr<PrimalIteration> primal_iteration(const PrimalOperator& op, double friction_tolerance) {
  if (op.constraints().frictional()) return std::make_unique<PrimalFrictionIteration>(op, friction_tolerance);
  return std::make_unique<PrimalNormalIteration>();
}

/// The primal active-set solver: the operator it keeps (PrimalOperator: K_rot with the active rows,
/// its factor, the constrained solve) and the iteration over it (PrimalIteration).
class PrimalActiveSetSolver final : public ContactSolver {
 public:
  PrimalActiveSetSolver(std::shared_ptr<const la::SpdOperator> K, std::shared_ptr<const la::SpdOperator> K_rot,
                        std::shared_ptr<la::LinearSolver> factor, ContactConstraints c, int max_iterations,
                        double friction_tolerance)
      : op_(std::move(K), std::move(K_rot), std::move(factor), std::move(c)),
        iteration_(primal_iteration(op_, friction_tolerance)),
        max_iterations_(max_iterations > 0 ? max_iterations : iteration_->most_iterations()) {}

  ContactReport solve(const Vector& F, Vector& u, Vector& lambda) override {
    if (op_.constraints().floating()) {  // a body its bonds alone hold: is there an equilibrium at all?
      const double excess = unbalanced_share(op_.comm(), op_.constraints(), F);
      if (excess > kPullOffShare) {
        ContactReport r;
        r.pulled_off = true;
        r.pull_off_excess = excess;
        return r;
      }
    }
    return iteration_->solve(op_, answers_, max_iterations_, F, u, lambda);
  }

  void set_gap(const Vector& gap) override { op_.set_gap(gap); }
  void set_friction(const Vector& tresca, const Vector& shift) override { op_.set_friction(tresca, shift); }
  void set_bond(const StepBonds& bonds) override { op_.set_bond(bonds); }
  const ContactConstraints& constraints() const override { return op_.constraints(); }
  const la::LinearSolver* own_factor() const override { return op_.factor(); }
  std::string name() const override { return "primal-active-set"; }
  std::string describe() const override {
    return "primal active set on u (K with the active rows as constraints; refactorized when the set changes)";
  }

 private:
  PrimalOperator op_;
  std::unique_ptr<PrimalIteration> iteration_;
  const int max_iterations_;
  PrimalWarmStart answers_;  // the last answers: the next solve's first iterate
};

}  // namespace

std::unique_ptr<ContactSolver> make_primal_active_set_solver(std::shared_ptr<const la::SpdOperator> K,
                                                             std::shared_ptr<const la::SpdOperator> K_rot,
                                                             std::shared_ptr<la::LinearSolver> factor,
                                                             ContactConstraints constraints, int max_iterations,
                                                             double friction_tolerance) {
  // What the primal cannot solve is refused before its basis is formed (the capability table).
  refuse_unsolvable("primal-active-set", contact_needs(K->comm(), constraints));
  return std::make_unique<PrimalActiveSetSolver>(std::move(K), std::move(K_rot), std::move(factor),
                                                 std::move(constraints), max_iterations, friction_tolerance);
}

}  // namespace vpc
