#include "solvers/contact_solver.hpp"

#include "core/error.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/penalty_duality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

double ContactResiduals::max() const {
  return std::max({equilibrium, penetration, negative_force, complementarity});
}

ContactResiduals contact_residuals(const SparseMatrix& K, const SparseMatrix& N, const Vector& F,
                                   const Vector& g, const Vector& u, const Vector& lambda) {
  ContactResiduals r;
  if (!F.allFinite() || !u.allFinite() || !lambda.allFinite() || !g.allFinite()) {
    const double inf = std::numeric_limits<double>::infinity();  // NaN would compare as "small"
    return {inf, inf, inf, inf};
  }
  // K is symmetric and stored whole: Kᵀu is the same product, and Eigen spreads
  // a row-major one (which Kᵀ is) over the OpenMP threads.
  const Vector Ku = K.transpose() * u;
  const Vector s = g - N * u;  // the gap left: ≥ 0
  auto inf = [](const Vector& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; };
  const double f_scale = std::max({inf(F), inf(Ku), 1e-300});
  r.equilibrium = inf(Vector(Ku - F + N.transpose() * lambda)) / f_scale;
  const double u_scale = std::max({inf(u), inf(g), 1e-300});
  const double l_scale = std::max({inf(lambda), f_scale});
  for (int i = 0; i < s.size(); ++i) {
    r.penetration = std::max(r.penetration, -s[i] / u_scale);
    r.negative_force = std::max(r.negative_force, -lambda[i] / l_scale);
    r.complementarity = std::max(r.complementarity, std::abs(lambda[i] * s[i]) / (l_scale * u_scale));
  }
  return r;
}

namespace {

/// `active_threshold`: see ContactReport::n_active.
void finish_report(ContactReport& rep, const SparseMatrix& K, const SparseMatrix& N, const Vector& F,
                   const Vector& g, const Vector& u, const Vector& lambda, double active_threshold = 0) {
  rep.active_threshold = active_threshold;
  rep.n_active = static_cast<int>((lambda.array() > active_threshold).count());
  rep.total_force = lambda.sum();
  rep.residuals = contact_residuals(K, N, F, g, u, lambda);
}

class ActiveSetContactSolver final : public ContactSolver {
 public:
  ActiveSetContactSolver(std::shared_ptr<const SparseMatrix> K, std::shared_ptr<const LinearSolver> factor,
                         const SparseMatrix& N, double max_cached_share)
      : K_(std::move(K)), N_(N), factor_(std::move(factor)) {
    // With K = PᵀLLᵀP: Y = L⁻¹PNᵀ (the forward half of K⁻¹Nᵀ) and S = N K⁻¹Nᵀ = YᵀY,
    // formed once (K and N never change). A column of Y is nonzero only on the
    // elimination-tree path of its contact dof, so Y is small and kept sparse.
    const int m = static_cast<int>(N.rows());
    const SparseMatrix Nt = N.transpose();
    const double max_bytes = std::min(kMaxYBytes, max_cached_share * factor_->factor_bytes());
    std::vector<Eigen::Triplet<double>> t;
    bool keep_y = max_cached_share > 0;
    const int block = rhs_block_columns(N.cols());  // dense blocks of right-hand sides
    for (int j0 = 0; j0 < m && keep_y; j0 += block) {
      const int nb = std::min(block, m - j0);
      const Eigen::MatrixXd Yb = factor_->forward(Eigen::MatrixXd(Nt.middleCols(j0, nb)));
      for (int j = 0; j < nb; ++j)
        for (Eigen::Index i = 0; i < Yb.rows(); ++i)
          if (Yb(i, j) != 0) t.emplace_back(static_cast<int>(i), j0 + j, Yb(i, j));
      keep_y = 12.0 * static_cast<double>(t.size()) <= max_bytes;  // value + row index per entry
    }
    Eigen::MatrixXd S(m, m);
    if (keep_y) {
      Y_.resize(N.cols(), m);
      Y_.setFromTriplets(t.begin(), t.end());
      S = Eigen::MatrixXd(SparseMatrix(Y_.transpose() * Y_));
    } else {  // Y too large: S from full solves; a step then costs two solves
      Y_ = SparseMatrix();
      for (int j0 = 0; j0 < m; j0 += block) {
        const int nb = std::min(block, m - j0);
        S.middleCols(j0, nb) = N * factor_->solve(Eigen::MatrixXd(Nt.middleCols(j0, nb)));
      }
    }
    S = 0.5 * (S + S.transpose()).eval();
    S_ = std::make_unique<DenseBoxQpOperator>(std::move(S));
  }

  ContactReport solve(const Vector& F, const Vector& g, Vector& u, Vector& lambda) override {
    const int m = static_cast<int>(N_.rows());
    if (lambda.size() != m) lambda = Vector::Zero(m);
    const Vector lo = Vector::Zero(m), hi = Vector::Constant(m, std::numeric_limits<double>::infinity());
    BoxQpResult r;
    if (Y_.cols() == m) {
      // One solve in two halves: y = L⁻¹PF; the dual QP min ½λᵀSλ − (N K⁻¹F − g)ᵀλ,
      // λ ≥ 0, with N K⁻¹F = Yᵀy; then u = PᵀL⁻ᵀ(y − Yλ) = K⁻¹(F − Nᵀλ).
      const Vector y = factor_->forward(F);
      r = solve_box_qp(*S_, Vector(Y_.transpose() * y - g), lo, hi, lambda);
      u = factor_->backward(Vector(y - Y_ * lambda));
    } else {
      const Vector u_free = factor_->solve(F);  // the solution without contact
      r = solve_box_qp(*S_, Vector(N_ * u_free - g), lo, hi, lambda);
      u = factor_->solve(Vector(F - N_.transpose() * lambda));
    }
    ContactReport rep;
    rep.converged = r.converged;
    rep.iterations = r.iterations;
    finish_report(rep, *K_, N_, F, g, u, lambda);
    return rep;
  }
  std::string name() const override { return "active-set"; }
  /// Whether Y is kept (one solve per step).
  bool caches_y() const { return Y_.cols() > 0; }

 private:
  std::shared_ptr<const SparseMatrix> K_;  // for the reported residuals
  SparseMatrix N_;
  std::shared_ptr<const LinearSolver> factor_;
  std::unique_ptr<DenseBoxQpOperator> S_;
  SparseMatrix Y_;  // L⁻¹PNᵀ, or empty when too large
  static constexpr double kMaxYBytes = 256.0 * 1024 * 1024;
};

/// The iteration contracts at the rate |ωc − 1| / (ωc + 1) along a constraint of
/// compliance c = N_i K⁻¹ N_iᵀ, so ω = 1 / mean(c) (not the stiffness scale).
double default_omega(const LinearSolver& factor, const SparseMatrix& N) {
  const SparseMatrix Nt = N.transpose();
  const int m = static_cast<int>(N.rows());
  double sum = 0;
  for (int j0 = 0; j0 < m; j0 += 64) {
    const int nb = std::min(64, m - j0);
    const Eigen::MatrixXd B(Nt.middleCols(j0, nb));
    sum += (B.transpose() * factor.solve(B)).trace();
  }
  return m / sum;
}

class PenaltyDualityContactSolver final : public ContactSolver {
 public:
  PenaltyDualityContactSolver(std::shared_ptr<const SparseMatrix> K, const LinearSolver& factor,
                              const SparseMatrix& N, const ContactSolverOptions& opt)
      : K_(std::move(K)), N_(N), opt_(opt), pd_(*K_, N, opt.omega > 0 ? opt.omega : default_omega(factor, N)) {}

  ContactReport solve(const Vector& F, const Vector& g, Vector& u, Vector& lambda) override {
    const int m = static_cast<int>(N_.rows());
    const Vector lo = Vector::Constant(m, -std::numeric_limits<double>::infinity());
    const PenaltyDualityResult r = pd_.solve(F, lo, g, u, lambda, opt_.tolerance, opt_.max_iterations);
    ContactReport rep;
    rep.converged = r.converged;
    rep.iterations = r.iterations;
    // The force scale of PenaltyDuality::solve's KKT test (b = F there).
    const auto inf = [](const Vector& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; };
    const double force_scale = std::max(inf(lambda), inf(F));
    finish_report(rep, *K_, N_, F, g, u, lambda, opt_.tolerance * force_scale);
    return rep;
  }
  std::string name() const override { return "penalty-duality"; }
  Vector warm_state() const override { return pd_.multiplier_state(); }
  void set_warm_state(const Vector& q) override { pd_.set_multiplier_state(q); }

 private:
  std::shared_ptr<const SparseMatrix> K_;  // for the reported residuals
  SparseMatrix N_;
  ContactSolverOptions opt_;
  PenaltyDuality pd_;
};

}  // namespace

std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, const SparseMatrix& K,
                                                   std::shared_ptr<const LinearSolver> K_factor,
                                                   const SparseMatrix& N, const ContactSolverOptions& opt) {
  return make_contact_solver(name, std::make_shared<const SparseMatrix>(K), std::move(K_factor), N, opt);
}

std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, std::shared_ptr<const SparseMatrix> K_ptr,
                                                   std::shared_ptr<const LinearSolver> K_factor,
                                                   const SparseMatrix& N, const ContactSolverOptions& opt) {
  require(K_ptr != nullptr, "contact solver: no stiffness matrix");
  const SparseMatrix& K = *K_ptr;
  require(N.rows() > 0, "contact solver: there are no contact unknowns (is the contact part empty?)");
  require(K_factor != nullptr && K_factor->size() == K.rows(), "contact solver: needs the factor of K");
  if (name == "active-set") return std::make_unique<ActiveSetContactSolver>(std::move(K_ptr), std::move(K_factor), N,
                                                                            opt.max_cached_share);
  if (name == "penalty-duality") return std::make_unique<PenaltyDualityContactSolver>(std::move(K_ptr), *K_factor, N, opt);
  fail("unknown contact solver '{}'; expected active-set or penalty-duality", name);
}

}  // namespace vpc
