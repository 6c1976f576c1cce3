#include "solvers/penalty_duality_contact.hpp"

#include "core/error.hpp"
#include "solvers/penalty_duality.hpp"

#include <algorithm>
#include <limits>

namespace vpc {

namespace {

/// The iteration contracts at the rate |ωc − 1| / (ωc + 1) along a constraint of
/// compliance c = N_i K⁻¹ N_iᵀ, so ω = 1 / mean(c) (not the stiffness scale).
double default_omega(const la::Comm& comm, const la::LinearSolver& factor, const ContactConstraints& c) {
  double sum = 0;
  for (int j0 = 0; j0 < c.m; j0 += 64) {
    const int nb = std::min(64, c.m - j0);
    const Eigen::MatrixXd B = transposed_rows(c.N, c.rows, j0, nb);
    sum += (B.transpose() * factor.solve(B)).trace();
  }
  return c.m / comm.sum(sum);
}

class PenaltyDualityContactSolver final : public ContactSolver {
 public:
  PenaltyDualityContactSolver(std::shared_ptr<const la::SpdOperator> K, const la::LinearSolver& K_factor,
                              ContactConstraints c, const la::LinearSolverFactory& make_factor,
                              const ContactSolverOptions& opt)
      : K_(std::move(K)), c_(std::move(c)), opt_(opt),
        pd_(*K_, c_.N, opt.omega > 0 ? opt.omega : default_omega(K_->comm(), K_factor, c_), make_factor, "K_pd") {}

  ContactReport solve(const Vector& F, Vector& u, Vector& lambda) override {
    const auto rows = static_cast<Eigen::Index>(c_.rows.size());
    const Vector lo = Vector::Constant(rows, -std::numeric_limits<double>::infinity());
    Vector theta = lambda.size() == c_.m ? local_rows(c_, lambda) : Vector();
    const PenaltyDualityResult r = pd_.solve(F, lo, c_.gap, u, theta, opt_.tolerance, opt_.max_iterations);
    lambda = replicate(K_->comm(), c_, theta);
    // The force scale of PenaltyDuality::solve's KKT test (b = F there).
    const double force_scale =
        std::max(lambda.size() ? lambda.cwiseAbs().maxCoeff() : 0.0, K_->comm().max(F.size() ? F.cwiseAbs().maxCoeff() : 0.0));
    return contact_report(*K_, c_, F, u, lambda, r.converged, r.iterations, opt_.tolerance * force_scale);
  }
  void set_gap(const Vector& gap) override { c_.gap = checked_gap(c_, gap); }
  void set_friction(const Vector& tresca, const Vector& shift) override { set_friction_data(c_, tresca, shift); }
  /// Refused where rows can bond (contact_capabilities.hpp): never called.
  void set_bond(const StepBonds&) override { require(false, "internal: penalty-duality given adhesion's bonds"); }
  const ContactConstraints& constraints() const override { return c_; }
  std::string name() const override { return "penalty-duality"; }
  std::string describe() const override { return "penalty-duality, factor of K + omega N^T N"; }
  Vector warm_state() const override {
    const bool started = pd_.multiplier_state().size() == static_cast<Eigen::Index>(c_.rows.size());
    return K_->comm().all(started) ? replicate(K_->comm(), c_, pd_.multiplier_state()) : Vector();
  }
  void set_warm_state(const Vector& q) override {
    pd_.set_multiplier_state(q.size() == c_.m ? local_rows(c_, q) : Vector());
  }

 private:
  std::shared_ptr<const la::SpdOperator> K_;  // for the reported residuals
  ContactConstraints c_;
  ContactSolverOptions opt_;
  PenaltyDuality pd_;
};

}  // namespace

std::unique_ptr<ContactSolver> make_penalty_duality_contact_solver(std::shared_ptr<const la::SpdOperator> K,
                                                                   const la::LinearSolver& K_factor,
                                                                   ContactConstraints constraints,
                                                                   const la::LinearSolverFactory& make_factor,
                                                                   const ContactSolverOptions& opt) {
  return std::make_unique<PenaltyDualityContactSolver>(std::move(K), K_factor, std::move(constraints), make_factor,
                                                       opt);
}

}  // namespace vpc
