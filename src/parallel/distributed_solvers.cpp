#include "parallel/distributed_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

namespace {

/// Read access to the owned entries of a vector.
class ReadArray {
 public:
  explicit ReadArray(Vec v) : v_(v) {
    VPC_PETSC(VecGetArrayRead(v_, &a_));
    VPC_PETSC(VecGetLocalSize(v_, &n_));
  }
  ~ReadArray() { VecRestoreArrayRead(v_, &a_); }
  ReadArray(const ReadArray&) = delete;
  ReadArray& operator=(const ReadArray&) = delete;
  double operator[](PetscInt i) const { return a_[i]; }
  PetscInt size() const { return n_; }

 private:
  Vec v_;
  const PetscScalar* a_ = nullptr;
  PetscInt n_ = 0;
};

/// Write access to the owned entries of a vector.
class WriteArray {
 public:
  explicit WriteArray(Vec v) : v_(v) {
    VPC_PETSC(VecGetArray(v_, &a_));
    VPC_PETSC(VecGetLocalSize(v_, &n_));
  }
  ~WriteArray() { VecRestoreArray(v_, &a_); }
  WriteArray(const WriteArray&) = delete;
  WriteArray& operator=(const WriteArray&) = delete;
  double& operator[](PetscInt i) { return a_[i]; }
  PetscInt size() const { return n_; }

 private:
  Vec v_;
  PetscScalar* a_ = nullptr;
  PetscInt n_ = 0;
};

double norm_inf(Vec v) {
  PetscReal r = 0;
  VPC_PETSC(VecNorm(v, NORM_INFINITY, &r));
  return r;
}

double inf(const Vector& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

// ---------------------------------------------------------------------------
// Contact

DistributedContactSolver::DistributedContactSolver(const DistributedMesh& part, Mat K,
                                                   const PetscLinearSolver& K_solver)
    : comm_(part.comm), d_(part.mesh.dim()), m_(part.n_contact), K_(K), K_solver_(K_solver) {
  require(m_ > 0, "contact solver: there are no contact unknowns (is the contact part empty?)");
  g_ = Vector::Zero(m_);
  for (const auto& c : part.contact) {
    if (!c.owned) continue;
    OwnedRow r{c.row, {-1, -1, -1}, {0, 0, 0}};
    for (int i = 0; i < d_; ++i) {
      r.dof[i] = part.dofs.free_index(part.dofs.full_index(c.local_node, i));
      require(r.dof[i] >= 0 && r.dof[i] < part.n_owned_dofs, "internal: contact row {} has no owned dof", c.row);
      r.nu[i] = c.direction[i];
    }
    rows_.push_back(r);
    g_[c.row] = c.gap;
  }
  allreduce_sum(comm_, g_.data(), m_);  // one owner per row: the sum is exact

  VPC_PETSC(MatCreateVecs(K_, u_free_.out(), work_.out()));
  VPC_PETSC(VecDuplicate(work_, rhs_.out()));
  PetscInt n_owned = 0;
  VPC_PETSC(VecGetLocalSize(work_, &n_owned));
  // W = K⁻¹Nᵀ is kept when it costs at most kMaxWBytesPerRank on every rank:
  // then u = u_free − Wλ and a step costs one solve instead of two.
  const bool keep_w = allreduce_max(comm_, static_cast<double>(n_owned) * m_ * sizeof(double)) <= kMaxWBytesPerRank;
  if (keep_w) W_.resize(n_owned, m_);
  // S = N K⁻¹Nᵀ and W = K⁻¹Nᵀ in blocks of right-hand sides (MUMPS solves a block at once).
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(m_, m_);
  PetscInt N = 0;
  VPC_PETSC(VecGetSize(work_, &N));
  for (int j0 = 0; j0 < m_; j0 += kBlock) {
    const int nb = std::min(kBlock, m_ - j0);
    PMat B, X;
    VPC_PETSC(MatCreateDense(comm_, n_owned, PETSC_DECIDE, N, nb, nullptr, B.out()));
    VPC_PETSC(MatCreateDense(comm_, n_owned, PETSC_DECIDE, N, nb, nullptr, X.out()));
    PetscScalar* b = nullptr;
    VPC_PETSC(MatDenseGetArrayWrite(B, &b));
    std::fill(b, b + static_cast<size_t>(n_owned) * nb, 0.0);
    for (const auto& r : rows_)
      if (r.row >= j0 && r.row < j0 + nb)
        for (int i = 0; i < d_; ++i) b[r.dof[i] + static_cast<size_t>(r.row - j0) * n_owned] = r.nu[i];
    VPC_PETSC(MatDenseRestoreArrayWrite(B, &b));
    K_solver_.solve(B, X);
    const PetscScalar* x = nullptr;
    VPC_PETSC(MatDenseGetArrayRead(X, &x));
    const Eigen::Map<const Eigen::MatrixXd> Xb(x, n_owned, nb);
    if (keep_w) W_.middleCols(j0, nb) = Xb;
    for (const auto& r : rows_)
      for (int j = 0; j < nb; ++j) {
        double s = 0;
        for (int i = 0; i < d_; ++i) s += r.nu[i] * Xb(r.dof[i], j);
        S(r.row, j0 + j) = s;
      }
    VPC_PETSC(MatDenseRestoreArrayRead(X, &x));
  }
  allreduce_sum(comm_, S.data(), m_ * m_);  // one owner per row: exact, the same on every rank
  S = 0.5 * (S + S.transpose()).eval();
  S_ = std::make_unique<DenseBoxQpOperator>(std::move(S));
}

Vector DistributedContactSolver::apply_N(Vec u) const {
  Vector Nu = Vector::Zero(m_);
  {
    ReadArray a(u);
    for (const auto& r : rows_) {
      double s = 0;
      for (int i = 0; i < d_; ++i) s += r.nu[i] * a[r.dof[i]];
      Nu[r.row] = s;
    }
  }
  allreduce_sum(comm_, Nu.data(), m_);
  return Nu;
}

void DistributedContactSolver::add_Nt(const Vector& lambda, double scale, Vec out) const {
  WriteArray a(out);
  for (const auto& r : rows_)
    for (int i = 0; i < d_; ++i) a[r.dof[i]] += scale * r.nu[i] * lambda[r.row];
}

ContactReport DistributedContactSolver::solve(Vec F, Vec u, Vector& lambda) {
  K_solver_.solve(F, u_free_);  // the solution without contact (warm-started by the last one)
  // Dual QP: min ½λᵀSλ − (N u_free − g)ᵀλ, λ ≥ 0: the same data on every rank.
  const Vector b = apply_N(u_free_) - g_;
  const Vector lo = Vector::Zero(m_), hi = Vector::Constant(m_, std::numeric_limits<double>::infinity());
  if (lambda.size() != m_) lambda = Vector::Zero(m_);
  const BoxQpResult r = solve_box_qp(*S_, b, lo, hi, lambda);
  if (keeps_w()) {
    const Vector Wl = W_ * lambda;
    ReadArray uf(u_free_);
    WriteArray a(u);
    for (PetscInt i = 0; i < a.size(); ++i) a[i] = uf[i] - Wl[i];
  } else {
    VPC_PETSC(VecCopy(F, rhs_));
    add_Nt(lambda, -1.0, rhs_);
    VPC_PETSC(VecCopy(u_free_, u));
    K_solver_.solve(rhs_, u);
  }
  ContactReport rep;
  rep.converged = r.converged;
  rep.iterations = r.iterations;
  rep.n_active = static_cast<int>((lambda.array() > 0).count());
  rep.total_force = lambda.sum();
  rep.residuals = residuals(F, u, lambda);
  return rep;
}

ContactResiduals DistributedContactSolver::residuals(Vec F, Vec u, const Vector& lambda) {
  ContactResiduals res;
  const double nf = norm_inf(F), nu = norm_inf(u);
  if (!std::isfinite(nf) || !std::isfinite(nu) || !lambda.allFinite() || !g_.allFinite()) {
    const double inf_ = std::numeric_limits<double>::infinity();  // NaN would compare as "small"
    return {inf_, inf_, inf_, inf_};
  }
  VPC_PETSC(MatMult(K_, u, work_));
  const double f_scale = std::max({nf, norm_inf(work_), 1e-300});
  VPC_PETSC(VecAXPY(work_, -1.0, F));
  add_Nt(lambda, 1.0, work_);
  res.equilibrium = norm_inf(work_) / f_scale;
  const Vector s = g_ - apply_N(u);  // the gap left: ≥ 0
  const double u_scale = std::max({nu, inf(g_), 1e-300});
  const double l_scale = std::max({inf(lambda), f_scale});
  for (int i = 0; i < m_; ++i) {
    res.penetration = std::max(res.penetration, -s[i] / u_scale);
    res.negative_force = std::max(res.negative_force, -lambda[i] / l_scale);
    res.complementarity = std::max(res.complementarity, std::abs(lambda[i] * s[i]) / (l_scale * u_scale));
  }
  return res;
}

// ---------------------------------------------------------------------------
// Damage

namespace {
constexpr double kRoundoff = 1e-14;  // as solvers/box_qp.cpp
constexpr int kMaxIterations = 200;
}  // namespace

DistributedDamageSolver::DistributedDamageSolver(MPI_Comm comm, Mat H, const PetscSolverOptions& linear)
    : comm_(comm), H_(H), linear_(linear), full_(comm, "vpc_H_", linear) {
  full_.factorize(H_, "damage matrix M + k kappa A");
  VPC_PETSC(MatCreateVecs(H_, diag_.out(), Hx_.out()));
  VPC_PETSC(VecDuplicate(Hx_, r_.out()));
  VPC_PETSC(MatGetDiagonal(H_, diag_));
}

double DistributedDamageSolver::kkt_residual(Vec Hx, Vec b, Vec x) const {
  PetscInt N = 0;
  VPC_PETSC(VecGetSize(x, &N));
  if (N == 0) return 0;
  ReadArray hx(Hx), bb(b), xx(x), dd(diag_);
  double res = 0, scale = 0;
  bool finite = true;
  for (PetscInt i = 0; i < xx.size(); ++i) {
    const double r = bb[i] - hx[i];
    finite = finite && std::isfinite(r) && std::isfinite(xx[i]);
    if (!finite) break;
    const double p = std::clamp(xx[i] + r / dd[i], 0.0, 1.0);
    res = std::max(res, std::abs(xx[i] - p));
    scale = std::max({scale, std::abs(xx[i]), std::abs(bb[i] / dd[i])});
  }
  // NaN compares false: a NaN iterate must not pass as exact.
  if (!allreduce_and(comm_, finite)) return std::numeric_limits<double>::infinity();
  res = allreduce_max(comm_, res);
  scale = allreduce_max(comm_, scale);
  return scale > 0 ? res / scale : res;
}

void DistributedDamageSolver::solve_free(const std::vector<char>& fixed, Vec b, Vec x) {
  const int n = static_cast<int>(fixed.size());
  const bool none_fixed =
      allreduce_and(comm_, std::none_of(fixed.begin(), fixed.end(), [](char c) { return c; }));
  if (none_fixed) {
    full_.solve(b, x);
    return;
  }
  // r = b − H_{·A} x_A
  {
    ReadArray xx(x);
    WriteArray xa(r_);
    for (int i = 0; i < n; ++i) xa[i] = fixed[i] ? xx[i] : 0.0;
  }
  VPC_PETSC(MatMult(H_, r_, Hx_));
  VPC_PETSC(VecWAXPY(r_, -1.0, Hx_, b));
  const bool changed = allreduce_or(comm_, !have_mask_ || fixed != mask_);
  if (changed) {
    // The active set changed: factor H_FF (only then; it is reused while A repeats).
    PetscInt begin = 0;
    VPC_PETSC(VecGetOwnershipRange(x, &begin, nullptr));
    free_local_.clear();
    for (int i = 0; i < n; ++i)
      if (!fixed[i]) free_local_.push_back(i);
    std::vector<PetscInt> global(free_local_.size());
    for (size_t a = 0; a < free_local_.size(); ++a) global[a] = begin + free_local_[a];
    n_free_global_ = allreduce_sum(comm_, static_cast<long long>(free_local_.size()));
    reduced_.reset();
    HFF_.reset();
    if (n_free_global_ > 0) {
      PIs is;
      VPC_PETSC(ISCreateGeneral(comm_, static_cast<PetscInt>(global.size()), global.data(), PETSC_COPY_VALUES,
                                is.out()));
      VPC_PETSC(MatCreateSubMatrix(H_, is, is, MAT_INITIAL_MATRIX, HFF_.out()));
      VPC_PETSC(MatSetOption(HFF_, MAT_SPD, PETSC_TRUE));
      reduced_ = std::make_unique<PetscLinearSolver>(comm_, "vpc_H_reduced_", linear_);
      reduced_->factorize(HFF_, "reduced damage matrix");
      ++n_reduced_factorizations_;
      VPC_PETSC(MatCreateVecs(HFF_, xf_.out(), rf_.out()));
    }
    mask_ = fixed;
    have_mask_ = true;
  }
  if (n_free_global_ == 0) return;
  {
    ReadArray rr(r_), xx(x);
    WriteArray rf(rf_), xf(xf_);
    for (size_t a = 0; a < free_local_.size(); ++a) {
      rf[a] = rr[free_local_[a]];
      xf[a] = xx[free_local_[a]];  // initial guess of an iterative solver
    }
  }
  reduced_->solve(rf_, xf_);
  ReadArray xf(xf_);
  WriteArray xx(x);
  for (size_t a = 0; a < free_local_.size(); ++a) xx[free_local_[a]] = xf[a];
}

DamageReport DistributedDamageSolver::solve(Vec b, Vec x) {
  DamageReport rep;
  PetscInt n = 0;
  VPC_PETSC(VecGetLocalSize(x, &n));
  const double nb = norm_inf(b);
  if (!std::isfinite(nb)) {  // NaN or Inf data (e.g. a formula): report, never "solve"
    rep.kkt_residual = std::numeric_limits<double>::infinity();
    return rep;
  }
  {
    WriteArray xx(x);
    for (PetscInt i = 0; i < n; ++i) xx[i] = std::clamp(xx[i], 0.0, 1.0);
  }
  // state: 0 free, 1 at lower bound, 2 at upper bound; -1 = not yet determined.
  std::vector<signed char> state(n, -1), next(n);
  std::vector<char> fixed(n);
  for (rep.iterations = 0; rep.iterations < kMaxIterations; ++rep.iterations) {
    VPC_PETSC(MatMult(H_, x, Hx_));
    {
      ReadArray hx(Hx_), bb(b), xx(x), dd(diag_);
      for (PetscInt i = 0; i < n; ++i) {
        const double trial = xx[i] + (bb[i] - hx[i]) / dd[i];
        next[i] = trial < 0.0 ? 1 : (trial > 1.0 ? 2 : 0);
      }
    }
    // Converged when the active sets repeat (on every rank), or when x already
    // satisfies KKT to round-off (degenerate bounds).
    if (allreduce_and(comm_, next == state) || kkt_residual(Hx_, b, x) <= kRoundoff) {
      rep.converged = true;
      break;
    }
    state = next;
    {
      WriteArray xx(x);
      for (PetscInt i = 0; i < n; ++i) {
        fixed[i] = state[i] != 0;
        if (state[i] == 1) xx[i] = 0.0;
        if (state[i] == 2) xx[i] = 1.0;
      }
    }
    solve_free(fixed, b, x);
  }
  long long counts[2] = {0, 0};
  {
    WriteArray xx(x);
    for (PetscInt i = 0; i < n; ++i) {
      xx[i] = std::clamp(xx[i], 0.0, 1.0);
      counts[0] += xx[i] == 0.0;
      counts[1] += xx[i] == 1.0;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_LONG_LONG, MPI_SUM, comm_);
  rep.n_lower = static_cast<int>(counts[0]);
  rep.n_upper = static_cast<int>(counts[1]);
  VPC_PETSC(MatMult(H_, x, Hx_));
  rep.kkt_residual = kkt_residual(Hx_, b, x);
  return rep;
}

}  // namespace vpc
