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

}  // namespace vpc
