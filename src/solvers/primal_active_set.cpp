#include "solvers/primal_active_set.hpp"

#include "core/error.hpp"
#include "solvers/contact_capabilities.hpp"

#include "solvers/active_set_history.hpp"
#include "solvers/primal_friction_iteration.hpp"
#include "solvers/primal_operator.hpp"

#include <optional>

namespace vpc {

namespace {

/// The primal active-set solver: the frictionless active-set Newton method here, over the operator
/// it keeps (PrimalOperator: K_rot with the active rows, its factor, the constrained solve); with
/// friction, HSW's iteration (PrimalFrictionIteration) over the same operator.
class PrimalActiveSetSolver final : public ContactSolver {
 public:
  PrimalActiveSetSolver(std::shared_ptr<const la::SpdOperator> K, std::shared_ptr<const la::SpdOperator> K_rot,
                        std::shared_ptr<la::LinearSolver> factor, ContactConstraints c, int max_iterations,
                        double friction_tolerance)
      : max_iterations_(max_iterations > 0 ? max_iterations
                        : c.frictional()  ? kPrimalFrictionMaxIterations
                                          : kPrimalMaxIterations),
        op_(std::move(K), std::move(K_rot), std::move(factor), std::move(c)) {
    if (op_.constraints().frictional()) friction_.emplace(op_, friction_tolerance);
  }

  ContactReport solve(const Vector& F, Vector& u, Vector& lambda) override {
    if (friction_) return friction_->solve(op_, answers_, max_iterations_, F, u, lambda);
    const ContactConstraints& c = op_.constraints();
    const auto rows = op_.n_rows();
    const la::Comm& comm = op_.comm();
    const Vector b = op_.rotate(F);
    Vector w = answers_.start_point(op_, F, u);
    const Vector lambda_in = lambda.size() == c.m ? local_rows(c, lambda) : Vector(Vector::Zero(rows));
    std::vector<char> active(static_cast<size_t>(rows));
    for (Eigen::Index i = 0; i < rows; ++i) active[i] = lambda_in[i] > op_.lower(i) || op_.gap_left(w, i) < 0;
    Vector lambda_local = Vector::Zero(rows);
    ActiveSetHistory history;  // the active sets met in this solve
    ContactReport rep;
    bool monotone = false, converged = false;
    // An iterative solver finds the set with loose solves (the set decides by signs, not
    // digits), then confirms it with one at its own tolerance (an inexact semismooth Newton
    // method); a direct one is exact every time.
    bool tight = !op_.iterative();
    for (int it = 0; it < max_iterations_ && !converged; ++it) {
      PrimalOperator::Iterate x = op_.iterate(active, b, w, tight, lambda_local, rep, nullptr);
      std::vector<char>& next = x.next;
      if (comm.all(next == active)) {
        converged = tight;
        tight = true;
        continue;
      }
      if (monotone) {
        op_.release_one(active, next, x.most_negative, x.worst);
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
    answers_.keep_answer(op_, w, u);
    lambda = replicate(comm, c, lambda_local);
    ContactReport out = contact_report(op_.K(), c, F, u, lambda, converged, rep.iterations);
    out.factorizations = rep.factorizations;
    out.cycles = rep.cycles;
    return out;
  }

  void set_gap(const Vector& gap) override { op_.set_gap(gap); }
  void set_friction(const Vector& tresca, const Vector& shift) override { op_.set_friction(tresca, shift); }
  const ContactConstraints& constraints() const override { return op_.constraints(); }
  const la::LinearSolver* own_factor() const override { return op_.factor(); }
  std::string name() const override { return "primal-active-set"; }
  std::string describe() const override {
    return "primal active set on u (K with the active rows as constraints; refactorized when the set changes)";
  }

 private:
  const int max_iterations_;
  PrimalOperator op_;
  PrimalWarmStart answers_;                          // the last answers: the next solve's first iterate
  std::optional<PrimalFrictionIteration> friction_;  // with friction (block > 1)
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
