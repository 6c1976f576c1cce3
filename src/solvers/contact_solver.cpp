#include "solvers/contact_solver.hpp"

#include "core/error.hpp"
#include "la/backend.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/compliance_dual.hpp"
#include "solvers/friction_dual.hpp"
#include "solvers/penalty_duality.hpp"
#include "solvers/primal_active_set.hpp"
#include "solvers/solver_failure.hpp"
#include "solvers/stick_slip.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace vpc {

/// λ's entries (m numbers) at this rank's constraint rows.
Vector local_rows(const ContactConstraints& c, const Vector& lambda) {
  Vector l(static_cast<Eigen::Index>(c.rows.size()));
  for (size_t k = 0; k < c.rows.size(); ++k) l[static_cast<Eigen::Index>(k)] = lambda[c.rows[k]];
  return l;
}

bool nonlinear_in_dual(const la::Comm& comm, const ContactConstraints& c) {
  return comm.any(std::ranges::any_of(c.law, [&](int k) { return !c.laws[static_cast<std::size_t>(k)]->linear(); }));
}

double ContactResiduals::max() const {
  return std::max({equilibrium, penetration, negative_force, complementarity, friction_bound, stick_slip, slip_direction});
}

Vector local_normal(const ContactConstraints& c, const Vector& lambda) {
  Vector l(static_cast<Eigen::Index>(c.rows.size()));
  for (size_t k = 0; k < c.rows.size(); ++k) l[static_cast<Eigen::Index>(k)] = lambda[c.rows[k] * c.block];
  return l;
}

Vector local_tangential(const ContactConstraints& c, const Vector& lambda) {
  const int t = c.block - 1;
  Vector l(static_cast<Eigen::Index>(c.rows.size()) * t);
  for (size_t k = 0; k < c.rows.size(); ++k)
    for (int j = 0; j < t; ++j) l[static_cast<Eigen::Index>(k) * t + j] = lambda[c.rows[k] * c.block + 1 + j];
  return l;
}

Vector replicate_blocks(const la::Comm& comm, const ContactConstraints& c, const Vector& normal, const Vector& tangential) {
  const int b = c.block, t = b - 1;
  Vector all = Vector::Zero(static_cast<Eigen::Index>(c.m) * b);
  for (size_t k = 0; k < c.rows.size(); ++k) {
    const auto e = static_cast<Eigen::Index>(k);
    all[c.rows[k] * b] = normal[e];
    for (int j = 0; j < t; ++j) all[c.rows[k] * b + 1 + j] = tangential[e * t + j];
  }
  comm.sum(all.data(), all.size());
  return all;
}

void set_friction_data(ContactConstraints& c, const Vector& tresca, const Vector& shift) {
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  require(c.frictional(), "internal: friction data for frictionless contact constraints");
  require(tresca.size() == rows && shift.size() == rows * (c.block - 1),
          "internal: {} friction bounds and {} slip shifts for {} contact rows of {} tangents", tresca.size(),
          shift.size(), rows, c.block - 1);
  require(tresca.allFinite() && shift.allFinite() && (tresca.size() == 0 || tresca.minCoeff() >= 0),
          "internal: friction bounds must be finite and >= 0 and slip shifts finite");
  c.tresca = tresca;
  c.shift = shift;
}

Vector slip_increment(const ContactConstraints& c, const Vector& u) {
  if (!c.frictional()) return {};
  return c.T * u - c.shift;
}

ContactStatus contact_status(double lambda_nu, double tangential_norm, double bound) {
  if (!(lambda_nu > 0)) return ContactStatus::Free;
  return tangential_norm >= (1 - kSlipShare) * bound ? ContactStatus::Slip : ContactStatus::Stick;
}

ContactResiduals contact_residuals(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F,
                                   const Vector& u, const Vector& lambda) {
  const la::Comm& comm = K.comm();
  ContactResiduals r;
  if (!comm.all(F.allFinite() && u.allFinite() && c.gap.allFinite()) || !lambda.allFinite()) {
    const double inf = std::numeric_limits<double>::infinity();  // NaN would compare as "small"
    return {inf, inf, inf, inf, inf, inf, inf};
  }
  Vector Ku;
  K.mult_threaded(u, Ku);
  const Vector lambda_local = local_normal(c, lambda);
  Vector s = c.gap - c.N * u;  // the gap left: ≥ 0, plus the penetration a compliant law gives at λ
  for (Eigen::Index i = 0; i < s.size() && !c.laws.empty(); ++i)
    if (const ContactLaw& law = c.law_of(i); !law.rigid()) s[i] = law.gap_left(s[i], lambda_local[i], c.compliance[i]);
  auto inf = [&](const Vector& v) { return comm.max(v.size() ? v.cwiseAbs().maxCoeff() : 0.0); };
  const double f_scale = std::max({inf(F), inf(Ku), 1e-300});
  Vector stationarity = Ku - F + c.N.transpose() * lambda_local;
  Vector tangential;
  if (c.frictional()) {
    tangential = local_tangential(c, lambda);
    stationarity += c.T.transpose() * tangential;
  }
  r.equilibrium = inf(stationarity) / f_scale;
  const double l_scale = std::max({lambda.size() ? lambda.cwiseAbs().maxCoeff() : 0.0, f_scale});
  // Not max(‖u‖, ‖g‖) alone: where every free dof is held by contact at a zero gap the exact
  // u is 0, and the dual solver's u = K⁻¹(F − Nᵀλ) is 0 only to round-off (~1e-17), which
  // that scale measured against itself: penetration and complementarity ~1 (issue 26). The
  // displacement l_scale / max K_ii is below any u the forces make otherwise, so elsewhere
  // the scale, and so every residual, is what it was.
  const Vector K_diag = K.diagonal();
  const double k_max = comm.max(K_diag.size() ? K_diag.maxCoeff() : 0.0);
  const double u_scale = std::max({inf(u), inf(c.gap), k_max > 0 ? l_scale / k_max : 0.0, 1e-300});
  for (int i = 0; i < s.size(); ++i) {
    r.penetration = std::max(r.penetration, -s[i] / u_scale);
    r.negative_force = std::max(r.negative_force, -lambda_local[i] / l_scale);
    r.complementarity = std::max(r.complementarity, std::abs(lambda_local[i] * s[i]) / (l_scale * u_scale));
  }
  if (c.frictional()) {  // SPEC §7: |λ_τ| ≤ s; below it Δ = 0; at it Δ along λ_τ
    const int t = c.block - 1;
    const Vector slip = slip_increment(c, u);
    for (Eigen::Index i = 0; i < s.size(); ++i) {
      const auto l = tangential.segment(i * t, t);
      const auto d = slip.segment(i * t, t);
      const double bound = c.bound(i, lambda_local[i]), ln = l.norm(), dn = d.norm();
      r.friction_bound = std::max(r.friction_bound, (ln - bound) / l_scale);
      r.stick_slip = std::max(r.stick_slip, std::max(bound - ln, 0.0) * dn / (l_scale * u_scale));
      r.slip_direction = std::max(r.slip_direction, (ln * dn - l.dot(d)) / (l_scale * u_scale));
    }
  }
  for (double* x : {&r.penetration, &r.negative_force, &r.complementarity}) *x = comm.max(*x);
  if (c.frictional())
    for (double* x : {&r.friction_bound, &r.stick_slip, &r.slip_direction}) *x = comm.max(*x);
  return r;
}

std::string contact_failure(const ContactReport& r, double tolerance) {
  const ContactResiduals& x = r.residuals;
  if (std::isinf(x.max()) || std::isnan(x.max())) return kSolverMetNonFinite;
  std::vector<std::string> above;
  const std::tuple<const char*, const char*, double> named[] = {
      {"equilibrium", "KKT stationarity: Ku = F - N^T lambda", x.equilibrium},
      {"penetration", "feasibility: Nu <= g", x.penetration},
      {"negative-force", "feasibility: lambda >= 0", x.negative_force},
      {"complementarity", "lambda_i (g - Nu)_i = 0", x.complementarity},
      {"friction-bound", "|lambda_t| <= its bound", x.friction_bound},
      {"stick-slip", "no slip below the bound", x.stick_slip},
      {"slip-direction", "slip along the tangential force", x.slip_direction}};
  for (const auto& [name, meaning, value] : named)
    if (!(value <= tolerance)) above.push_back(fmt::format("{} residual {:.2e} ({})", name, value, meaning));
  return solver_failure(r.converged, r.iterations,
                        above.empty() ? "" : fmt::format("{} above the tolerance {:.1e}", fmt::join(above, ", "), tolerance));
}

ContactReport contact_report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                             const Vector& lambda, bool converged, int iterations, double active_threshold) {
  ContactReport rep;
  rep.converged = converged;
  rep.iterations = iterations;
  rep.active_threshold = active_threshold;
  rep.residuals = contact_residuals(K, c, F, u, lambda);
  if (!c.frictional()) {
    rep.n_active = static_cast<int>((lambda.array() > active_threshold).count());
    rep.total_force = lambda.sum();
    return rep;
  }
  const int b = c.block, t = b - 1;
  for (int i = 0; i < c.m; ++i) {
    rep.n_active += lambda[i * b] > active_threshold;
    rep.total_force += lambda[i * b];
  }
  // Stick and slip counts and the dissipation from this rank's rows.
  const std::vector<ContactStatus> status = stick_slip(c, lambda, active_threshold);
  const Vector tangential = local_tangential(c, lambda), slip = slip_increment(c, u);
  double sums[3] = {0, 0, 0};
  for (std::size_t i = 0; i < status.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    sums[0] += status[i] == ContactStatus::Stick;
    sums[1] += status[i] == ContactStatus::Slip;
    sums[2] += tangential.segment(k * t, t).dot(slip.segment(k * t, t));
  }
  K.comm().sum(sums, 3);
  rep.n_stick = static_cast<int>(sums[0]);
  rep.n_slip = static_cast<int>(sums[1]);
  rep.dissipation = sums[2];
  return rep;
}

/// m numbers, the same on every rank, from this rank's rows' values (one owner per row: the sum is exact).
Vector replicate(const la::Comm& comm, const ContactConstraints& c, const Vector& local) {
  Vector all = Vector::Zero(c.m);
  for (size_t k = 0; k < c.rows.size(); ++k) all[c.rows[k]] = local[static_cast<Eigen::Index>(k)];
  comm.sum(all.data(), c.m);
  return all;
}

const Vector& checked_gap(const ContactConstraints& c, const Vector& gap) {
  require(gap.size() == static_cast<Eigen::Index>(c.rows.size()), "internal: {} gaps for {} contact rows", gap.size(),
          c.rows.size());
  return gap;
}

namespace {

ContactReport make_report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                          const Vector& lambda, const BoxQpResult& qp, double active_threshold = 0) {
  ContactReport rep = contact_report(K, c, F, u, lambda, qp.converged, qp.iterations, active_threshold);
  rep.cycles = qp.cycles;
  return rep;
}

/// The columns j0 .. j0+nb−1 of Nᵀ (or of [N; T]ᵀ with friction: `rows` places each local row
/// in λ), owned rows: each rank fills the columns of its own constraint rows (zero elsewhere),
/// so a block solve with it is collective.
Eigen::MatrixXd transposed_rows(const SparseMatrix& N, const std::vector<int>& rows, int j0, int nb) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(N.cols(), nb);
  const SparseMatrix Nt = N.transpose();
  for (int k = 0; k < Nt.outerSize(); ++k) {
    const int j = rows[k] - j0;
    if (j < 0 || j >= nb) continue;
    for (SparseMatrix::InnerIterator it(Nt, k); it; ++it) B(it.row(), j) = it.value();
  }
  return B;
}

/// The same block size on every rank (block solves are collective).
int common_block_columns(const la::Comm& comm, Eigen::Index n_owned, int most) {
  return static_cast<int>(comm.min(rhs_block_columns(n_owned, most)));
}

class ActiveSetContactSolver final : public ContactSolver {
 public:
  ActiveSetContactSolver(std::shared_ptr<const la::SpdOperator> K, std::shared_ptr<const la::LinearSolver> factor,
                         ContactConstraints c, double max_cached_share)
      : K_(std::move(K)), c_(std::move(c)), factor_(std::move(factor)) {
    if (c_.frictional()) B_ = friction_rows(c_, B_rows_);
    Eigen::MatrixXd S = factor_->has_halves() ? dual_matrix_from_halves(max_cached_share)
                                              : dual_matrix_from_solves(max_cached_share);
    S = 0.5 * (S + S.transpose()).eval();
    if (!c_.laws.empty()) {  // every row's law and compliance, the same on every rank
      const auto n = static_cast<Eigen::Index>(c_.law.size());
      const Vector all = replicate(comm(), c_, Eigen::Map<const Eigen::VectorXi>(c_.law.data(), n).cast<double>());
      for (Eigen::Index j = 0; j < all.size(); ++j) row_laws_.push_back(c_.laws[static_cast<std::size_t>(all[j])].get());
      compliance_ = replicate(comm(), c_, c_.compliance);
      nonlinear_ = std::ranges::any_of(row_laws_, [](const ContactLaw* l) { return !l->linear(); });
    }
    require(!nonlinear_ || !c_.frictional(),
            "contact solver 'active-set': friction with a normal law that is not linear is not solved; use Signorini "
            "or a linear normal compliance with friction");
    if (nonlinear_) S_plain_ = S;  // the nonlinear law's dual (solve_compliance_dual) on S itself
    // A linear law's λ_i = k_i d₊ adds its spring's compliance 1/k_i to S_ii (the box QP of S + diag(1/k)),
    // on the normal rows (j × block).
    const Eigen::Index b = c_.block;
    for (Eigen::Index j = 0; j < compliance_.size(); ++j)
      if (const ContactLaw* law = row_laws_[static_cast<std::size_t>(j)]; !law->rigid())
        S(j * b, j * b) += law->spring_compliance(compliance_[j]);
    if (c_.frictional()) sets_ = friction_sets(comm(), c_, row_laws_, S);
    S_ = std::make_unique<DenseBoxQpOperator>(std::move(S));
  }

  // With friction N below is B = [N; T] and g is [g; h] (friction_rows), m is m × block.
  ContactReport solve(const Vector& F, Vector& u, Vector& lambda) override {
    const int m = unknowns();
    if (lambda.size() != m) lambda = Vector::Zero(m);
    BoxQpResult r;
    if (Y_.cols() == m) {
      // One solve in two halves: y = L⁻¹PF; the dual QP min ½λᵀSλ − (N K⁻¹F − g)ᵀλ,
      // λ ≥ 0, with N K⁻¹F = Yᵀy; then u = PᵀL⁻ᵀ(y − Yλ) = K⁻¹(F − Nᵀλ).
      const Vector y = factor_->forward(F);
      r = dual(Vector(Y_.transpose() * y - replicated(offsets())), lambda);
      u = factor_->backward(Vector(y - Y_ * lambda));
    } else {
      Vector u_free = u;  // the solution without contact (u: an iterative solver's initial guess)
      factor_->solve(F, u_free);
      r = dual(replicated(Vector(B() * u_free - offsets())), lambda);
      if (W_.cols() == m) {
        // u = u_free − Wλ over the active rows only (λ_j = 0 elsewhere): the
        // active set is usually a part of Γ3, and each column is n_owned long.
        u = u_free;
        for (int j = 0; j < m; ++j)
          if (lambda[j] != 0) u.noalias() -= lambda[j] * W_.col(j);
      } else {
        u = u_free;
        factor_->solve(Vector(F - B().transpose() * local_of(lambda)), u);
      }
    }
    return make_report(*K_, c_, F, u, lambda, r);
  }
  void set_gap(const Vector& gap) override { c_.gap = checked_gap(c_, gap); }
  void set_friction(const Vector& tresca, const Vector& shift) override { set_friction_data(c_, tresca, shift); }
  std::string name() const override { return "active-set"; }
  std::string describe() const override {
    if (nonlinear_) return describe_solves() + "; semismooth Newton for the nonlinear compliance law";
    if (c_.frictional()) {
      if (sets_.coulomb()) return describe_solves() + "; Coulomb friction by semismooth Newton (Alart-Curnier) on the dual";
      if (c_.block == 2) return describe_solves() + "; Tresca friction as a box QP";
      return describe_solves() + "; Tresca friction by semismooth Newton (Alart-Curnier) on the dual";
    }
    return describe_solves();
  }

 private:
  /// The dual problem for b = N K⁻¹F − g (replicated): the box QP with S (+ diag(1/k)) over
  /// each row's dual set (λ ≥ 0), or, for a law that is not linear on some row, solve_compliance_dual.
  BoxQpResult dual(const Vector& b, Vector& lambda) {
    if (c_.frictional()) {  // friction_dual.hpp; the bounds of this step
      sets_.tresca = replicate(comm(), c_, c_.tresca);
      return solve_friction_dual(*S_, b, sets_, lambda);
    }
    if (nonlinear_) return solve_compliance_dual(S_plain_, b, row_laws_, compliance_, lambda);
    const int m = c_.m;
    Vector lo = Vector::Zero(m), hi = Vector::Constant(m, std::numeric_limits<double>::infinity());
    for (std::size_t j = 0; j < row_laws_.size(); ++j) {
      lo[static_cast<Eigen::Index>(j)] = row_laws_[j]->dual_lower();
      hi[static_cast<Eigen::Index>(j)] = row_laws_[j]->dual_upper();
    }
    return solve_box_qp(*S_, b, lo, hi, lambda);
  }
  std::string describe_solves() const {
    if (Y_.cols() > 0) return "one solve per step (K's halves)";
    if (W_.cols() > 0) return "one solve per step (K⁻¹Nᵀ kept)";
    return "two solves per step";
  }

  const la::Comm& comm() const { return K_->comm(); }

  // The constraint rows: N, or B = [N; T] with friction, node by node in λ's order (λ_ν, λ_τ).
  int unknowns() const { return c_.m * c_.block; }
  const SparseMatrix& B() const { return c_.frictional() ? B_ : c_.N; }
  const std::vector<int>& rows() const { return c_.frictional() ? B_rows_ : c_.rows; }
  /// g (or [g; h]) of this rank's rows of B.
  Vector offsets() const { return c_.frictional() ? friction_offsets(c_) : c_.gap; }
  /// The unknowns of λ (all of them, the same on every rank) from this rank's rows' values, and back.
  Vector replicated(const Vector& local) const {
    if (!c_.frictional()) return replicate(comm(), c_, local);
    Vector all = Vector::Zero(unknowns());  // one owner per row: the sum is exact
    for (std::size_t k = 0; k < B_rows_.size(); ++k) all[B_rows_[k]] = local[static_cast<Eigen::Index>(k)];
    comm().sum(all.data(), all.size());
    return all;
  }
  Vector local_of(const Vector& lambda) const {
    if (!c_.frictional()) return local_rows(c_, lambda);
    Vector l(static_cast<Eigen::Index>(B_rows_.size()));
    for (std::size_t k = 0; k < B_rows_.size(); ++k) l[static_cast<Eigen::Index>(k)] = lambda[B_rows_[k]];
    return l;
  }

  /// With K = PᵀLLᵀP: Y = L⁻¹PNᵀ (the forward half of K⁻¹Nᵀ) and S = N K⁻¹Nᵀ = YᵀY,
  /// formed once (K and N never change). A column of Y is nonzero only on the
  /// elimination-tree path of its contact dof, so Y is small and kept sparse.
  /// A factor with halves is one process's (CHOLMOD): N is whole here.
  Eigen::MatrixXd dual_matrix_from_halves(double max_cached_share) {
    const int m = unknowns();
    const double max_bytes = std::min(kMaxCachedBytes, max_cached_share * factor_->factor_bytes());
    std::vector<Eigen::Triplet<double>> t;
    bool keep_y = max_cached_share > 0;
    const int block = rhs_block_columns(c_.N.cols());  // dense blocks of right-hand sides
    for (int j0 = 0; j0 < m && keep_y; j0 += block) {
      const int nb = std::min(block, m - j0);
      const Eigen::MatrixXd Yb = factor_->forward(transposed_rows(B(), rows(), j0, nb));
      for (int j = 0; j < nb; ++j)
        for (Eigen::Index i = 0; i < Yb.rows(); ++i)
          if (Yb(i, j) != 0) t.emplace_back(static_cast<int>(i), j0 + j, Yb(i, j));
      keep_y = 12.0 * static_cast<double>(t.size()) <= max_bytes;  // value + row index per entry
    }
    if (!keep_y) return dual_matrix_from_solves(0);  // Y too large: a step then costs two solves
    Y_.resize(c_.N.cols(), m);
    Y_.setFromTriplets(t.begin(), t.end());
    return Eigen::MatrixXd(SparseMatrix(Y_.transpose() * Y_));
  }

  /// S = N K⁻¹Nᵀ by block solves X = K⁻¹Nᵀ (collective: every rank solves the same
  /// blocks); S's rows are computed where N's rows live, then summed over the ranks
  /// (one owner per row: exact, the same S everywhere). X is kept as W when it fits
  /// on every rank (a step is then one solve: u = u_free − Wλ).
  Eigen::MatrixXd dual_matrix_from_solves(double max_cached_share) {
    const int m = unknowns();
    const auto n_owned = c_.N.cols();
    double max_bytes = max_cached_share > 0 ? kMaxCachedBytes : 0;
    if (factor_->factor_bytes() > 0) max_bytes = std::min(max_bytes, max_cached_share * factor_->factor_bytes());
    const bool keep_w = !factor_->has_halves() &&
                        comm().max(static_cast<double>(n_owned) * m * sizeof(double)) <= max_bytes;
    if (keep_w) W_.resize(n_owned, m);
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(m, m);
    const int block = factor_->has_halves() ? rhs_block_columns(n_owned) : common_block_columns(comm(), n_owned, 64);
    for (int j0 = 0; j0 < m; j0 += block) {
      const int nb = std::min(block, m - j0);
      const Eigen::MatrixXd X = factor_->solve(transposed_rows(B(), rows(), j0, nb));
      if (keep_w) W_.middleCols(j0, nb) = X;
      const Eigen::MatrixXd NX = B() * X;
      for (size_t k = 0; k < rows().size(); ++k) S.block(rows()[k], j0, 1, nb) = NX.row(static_cast<Eigen::Index>(k));
    }
    comm().sum(S.data(), m * m);
    return S;
  }

  std::shared_ptr<const la::SpdOperator> K_;  // for the reported residuals
  ContactConstraints c_;
  std::shared_ptr<const la::LinearSolver> factor_;
  std::unique_ptr<DenseBoxQpOperator> S_;
  Eigen::MatrixXd S_plain_;                  // S without diag(1/k), for a nonlinear law only
  std::vector<const ContactLaw*> row_laws_;  // every row's law (replicated); empty: Signorini
  Vector compliance_;                        // every row's 1/k_i (replicated), with row_laws_
  bool nonlinear_ = false;                   // some row's law is not linear
  SparseMatrix B_;              // with friction: [N; T] in λ's order (friction_rows)
  std::vector<int> B_rows_;     // its rows' places in λ
  FrictionDualSets sets_;       // with friction: each node's sets, replicated
  SparseMatrix Y_;     // L⁻¹PNᵀ (factors with halves), or empty
  Eigen::MatrixXd W_;  // K⁻¹Nᵀ on the owned rows (factors without halves), or empty
  static constexpr double kMaxCachedBytes = 256.0 * 1024 * 1024;
};

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
    return make_report(*K_, c_, F, u, lambda, {r.converged, r.iterations}, opt_.tolerance * force_scale);
  }
  void set_gap(const Vector& gap) override { c_.gap = checked_gap(c_, gap); }
  void set_friction(const Vector& tresca, const Vector& shift) override { set_friction_data(c_, tresca, shift); }
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

ContactSolverPick pick_contact_solver(const std::string& requested, int m, const std::string& linear_solver,
                                      bool nonlinear_law, int block) {
  if (requested != "auto") return {requested, "as asked"};
  if (nonlinear_law) return {"active-set", "auto: a nonlinear compliance law is solved on the dual"};
  // With friction the dual's unknowns are m × block (λ_ν and the tangential forces of each node).
  const int n = m * block;
  const std::string unknowns =
      block == 1 ? fmt::format("{} contact nodes", m) : fmt::format("{} contact unknowns ({} nodes x {})", n, m, block);
  if (!la::Backend::is_direct(linear_solver))
    return {"primal-active-set", fmt::format("auto: {} is iterative (the dual's S would take {} solves)", linear_solver, n)};
  if (n > kDualContactRows)
    return {"primal-active-set", fmt::format("auto: {} > {} (the dual's S would be dense {} x {})", unknowns,
                                             kDualContactRows, n, n)};
  return {"active-set", fmt::format("auto: {} <= {} and a direct solver", unknowns, kDualContactRows)};
}

std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, std::shared_ptr<const la::SpdOperator> K,
                                                   std::shared_ptr<const la::LinearSolver> K_factor,
                                                   ContactConstraints constraints, const la::LinearSolverFactory& make_factor,
                                                   const ContactSolverOptions& opt) {
  require(K != nullptr, "contact solver: no stiffness matrix");
  require(constraints.m > 0, "contact solver: there are no contact unknowns (is the contact part empty?)");
  require(K_factor != nullptr, "contact solver: needs the factor of K");
  require(name != "penalty-duality" || !constraints.frictional(),
          "contact solver 'penalty-duality' solves frictionless contact only; friction needs 'active-set' (the dual) "
          "or 'primal-active-set'");
  const auto rows = static_cast<Eigen::Index>(constraints.rows.size());
  require(constraints.N.rows() == rows && constraints.gap.size() == rows && constraints.N.cols() == K->n_owned(),
          "internal: contact constraints of {} rows x {} columns for {} rows, {} gaps and {} owned dofs",
          constraints.N.rows(), constraints.N.cols(), rows, constraints.gap.size(), K->n_owned());
  require(constraints.laws.empty() ||
              (constraints.compliance.size() == rows && constraints.law.size() == constraints.rows.size()),
          "internal: {} compliances and {} laws for {} contact rows", constraints.compliance.size(),
          constraints.law.size(), rows);
  const bool compliant = std::ranges::any_of(constraints.law, [&](int k) {
    return !constraints.laws[static_cast<std::size_t>(k)]->rigid();
  });
  if (name == "active-set")
    return std::make_unique<ActiveSetContactSolver>(std::move(K), std::move(K_factor), std::move(constraints),
                                                    opt.max_cached_share);
  require(name != "penalty-duality" || !K->comm().any(compliant),
          "contact solver 'penalty-duality' solves the Signorini conditions only; normal compliance needs 'active-set'");
  if (name == "penalty-duality")
    return std::make_unique<PenaltyDualityContactSolver>(std::move(K), *K_factor, std::move(constraints), make_factor,
                                                         opt);
  if (name == "primal-active-set") {
    require(contact_reflections(constraints.N).size() == 0,
            "internal: the primal contact solver with rows off the axes needs Q K Q (make_primal_active_set_solver)");
    return make_primal_active_set_solver(K, nullptr, std::shared_ptr<la::LinearSolver>(make_factor("K_active")),
                                         std::move(constraints));
  }
  fail("unknown contact solver '{}'; expected active-set, primal-active-set or penalty-duality", name);
}

std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, const SparseMatrix& K,
                                                   const SparseMatrix& N, const Vector& gap,
                                                   const ContactSolverOptions& opt) {
  auto op = std::make_shared<const la::SparseOperator>(K);
  std::shared_ptr<la::LinearSolver> factor = la::serial_backend()->factor("K");
  ContactConstraints c;
  c.m = static_cast<int>(N.rows());
  c.N = N;
  c.gap = gap;
  for (int i = 0; i < c.m; ++i) c.rows.push_back(i);
  if (name == "primal-active-set") {
    const SparseMatrix Q = contact_reflections(N);
    auto K_rot = Q.size() ? std::make_shared<const la::SparseOperator>(SparseMatrix(Q * K * Q)) : nullptr;
    return make_primal_active_set_solver(std::move(op), std::move(K_rot), std::move(factor), std::move(c));
  }
  factor->factorize(*op, "elastic stiffness K");
  return make_contact_solver(name, std::move(op), std::move(factor), std::move(c), la::factor_factory(la::serial_backend()), opt);
}

}  // namespace vpc
