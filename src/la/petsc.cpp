#include "la/petsc.hpp"

#include "la/mumps_schur.hpp"
#include "la/petsc_segregated.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vpc::la {

namespace {

class MpiComm final : public CommBackend {
 public:
  explicit MpiComm(MPI_Comm comm) : comm_(comm) {}
  MPI_Comm mpi() const { return comm_; }
  int rank() const override { return comm_rank(comm_); }
  int size() const override { return comm_size(comm_); }
  void sum(double* v, int n) const override { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_SUM, comm_); }
  void sum(long long* v, int n) const override {
    MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_LONG_LONG, MPI_SUM, comm_);
  }
  double max(double v) const override { return allreduce_max(comm_, v); }
  double min(double v) const override { return allreduce_min(comm_, v); }
  std::vector<long long> all_gather(long long v) const override {
    std::vector<long long> all(size());
    MPI_Allgather(&v, 1, MPI_LONG_LONG, all.data(), 1, MPI_LONG_LONG, comm_);
    return all;
  }
  std::vector<std::vector<double>> exchange(const std::vector<std::vector<double>>& to) const override {
    return exchange_as(to, MPI_DOUBLE);
  }
  std::vector<std::vector<long long>> exchange(const std::vector<std::vector<long long>>& to) const override {
    return exchange_as(to, MPI_LONG_LONG);
  }
  void broadcast(std::string& bytes) const override {
    long long n = static_cast<long long>(bytes.size());
    MPI_Bcast(&n, 1, MPI_LONG_LONG, 0, comm_);
    bytes.resize(static_cast<std::size_t>(n));
    // In pieces of at most 2^30 bytes: MPI's counts are ints.
    for (long long at = 0; at < n; at += 1LL << 30)
      MPI_Bcast(bytes.data() + at, static_cast<int>(std::min(n - at, 1LL << 30)), MPI_CHAR, 0, comm_);
  }
  std::string first_failure(bool failed, const std::string& message) const override {
    int first = failed ? rank() : size();
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm_);
    if (first == size()) return {};
    int n = static_cast<int>(message.size());
    MPI_Bcast(&n, 1, MPI_INT, first, comm_);
    std::string text = rank() == first ? message : std::string(static_cast<size_t>(n), ' ');
    MPI_Bcast(text.data(), n, MPI_CHAR, first, comm_);
    return text;
  }

 private:
  template <typename T>
  std::vector<std::vector<T>> exchange_as(const std::vector<std::vector<T>>& to, MPI_Datatype type) const {
    const int p = size();
    std::vector<int> n_send(p), n_recv(p), at_send(p), at_recv(p);
    for (int r = 0; r < p; ++r) n_send[r] = static_cast<int>(to[r].size());
    MPI_Alltoall(n_send.data(), 1, MPI_INT, n_recv.data(), 1, MPI_INT, comm_);
    std::exclusive_scan(n_send.begin(), n_send.end(), at_send.begin(), 0);
    std::exclusive_scan(n_recv.begin(), n_recv.end(), at_recv.begin(), 0);
    std::vector<T> send, recv(static_cast<size_t>(at_recv[p - 1] + n_recv[p - 1]));
    for (const auto& v : to) send.insert(send.end(), v.begin(), v.end());
    MPI_Alltoallv(send.data(), n_send.data(), at_send.data(), type, recv.data(), n_recv.data(), at_recv.data(), type,
                  comm_);
    std::vector<std::vector<T>> from(p);
    for (int r = 0; r < p; ++r) from[r].assign(recv.begin() + at_recv[r], recv.begin() + at_recv[r] + n_recv[r]);
    return from;
  }
  MPI_Comm comm_;
};

MPI_Comm mpi_of(const Comm& comm) {
  const auto* b = dynamic_cast<const MpiComm*>(comm.backend());
  return b ? b->mpi() : PETSC_COMM_SELF;
}

void add_local_matrix(Mat A, const Eigen::SparseMatrix<double>& local, const std::vector<PetscInt>& l2g) {
  std::vector<PetscInt> rows;
  std::vector<PetscScalar> vals;
  for (int j = 0; j < local.outerSize(); ++j) {
    rows.clear();
    vals.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(local, j); it; ++it) {
      rows.push_back(l2g[it.row()]);
      vals.push_back(it.value());
    }
    const PetscInt col = l2g[j];
    VPC_PETSC(MatSetValues(A, static_cast<PetscInt>(rows.size()), rows.data(), 1, &col, vals.data(), ADD_VALUES));
  }
}

/// The caller's storage as the array of a work vector for the length of a scope.
class Placed {
 public:
  Placed(Vec v, const double* a) : v_(v) { VPC_PETSC(VecPlaceArray(v_, a)); }
  ~Placed() { VecResetArray(v_); }
  Placed(const Placed&) = delete;
  Placed& operator=(const Placed&) = delete;

 private:
  Vec v_;
};

/// Sets PETSc option `name` to `value` unless it is given (PETSC_OPTIONS, the command line).
/// Returns whether it set it.
bool default_option(const std::string& name, const char* value) {
  PetscBool given = PETSC_FALSE;
  VPC_PETSC(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &given));
  if (!given) VPC_PETSC(PetscOptionsSetValue(nullptr, name.c_str(), value));
  return !given;
}

/// default_option for a scope: an option set here is cleared at its end (one given is left).
class ScopedOption {
 public:
  ScopedOption(const char* name, const char* value) : name_(name), set_(name != nullptr && default_option(name, value)) {}
  ~ScopedOption() {
    if (set_) PetscOptionsClearValue(nullptr, name_);
  }
  ScopedOption(const ScopedOption&) = delete;
  ScopedOption& operator=(const ScopedOption&) = delete;

 private:
  const char* name_;
  bool set_;
};

/// Frees what PETSc keeps on each multigrid level's Galerkin product PᵀAP (and on a smoothed
/// prolongator, A·P₀) to form it again in place: a PC here is never set up twice (a rebuild makes a
/// new KSP). On foundation-3d n = 70 (2 ranks) that was 0.98 GB a rank, the hierarchy itself 0.28 GB
/// (docs/parallel.md, "Where the memory goes"). Not a multigrid PC: nothing to do.
void drop_product_data(PC pc) {
  PetscBool multigrid = PETSC_FALSE;
  VPC_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &multigrid));
  if (!multigrid) return;
  PetscInt levels = 0;
  VPC_PETSC(PCMGGetLevels(pc, &levels));
  for (PetscInt l = 0; l < levels; ++l) {
    KSP smoother = nullptr;
    Mat A = nullptr;
    VPC_PETSC(PCMGGetSmoother(pc, l, &smoother));
    VPC_PETSC(KSPGetOperators(smoother, &A, nullptr));
    VPC_PETSC(MatProductClear(A));
    if (l == 0) continue;
    Mat P = nullptr;
    VPC_PETSC(PCMGGetInterpolation(pc, l, &P));
    VPC_PETSC(MatProductClear(P));
  }
}

/// A factorization (MUMPS Cholesky) or a preconditioned Krylov solver (CG + GAMG,
/// CG + hypre) of a PetscOperator, as one KSP under the options prefix vpc_<name>_
/// (so any PETSc solver can be chosen from the command line or PETSC_OPTIONS, e.g.
/// -vpc_K_ksp_monitor). The iterative ones start from the x passed in (the previous
/// step's solution) and stop at a relative residual of `rtol`.
class PetscFactor final : public LinearSolver {
 public:
  PetscFactor(MPI_Comm comm, const std::string& name, const PetscSolverOptions& options)
      : comm_(comm), prefix_("vpc_" + name + "_"), options_(options) {
    check_linear_solver(options_.kind);
  }
  void set_coordinates(const Eigen::VectorXd& coordinates, int dim) override {
    coordinates_ = coordinates;
    dim_ = dim;
  }
  void set_fields(const std::vector<int>& field) override { field_ = field; }
  void factorize(const SpdOperator& A, const char* what) override {
    const auto* op = dynamic_cast<const PetscOperator*>(&A);
    require(op != nullptr, "internal: PETSc factors PETSc operators only ({})", what);
    what_ = what;
    const double start = flops();
    // Where memory asks for it (run/solver_plan.cpp), PᵀAP row by row: no A·P is held while the
    // levels are formed (foundation-3d n = 70, 2 ranks: a rank's peak 2.14 GB against 2.64 GB; the
    // first step's contact solves, a set-up among them, 67.8 s against 17.5 s). PETSc reads it for
    // every product, unprefixed: it is set for this set-up only (GAMG's and galerkin_levels'), so
    // that a later run in this process (Python) plans its own. On one rank the matrices are SeqAIJ, which
    // has no allatonce (PETSc 3.18 stops the set-up: "Unknown option allatonce for -matptap_via"); its
    // default, scalable, already forms PᵀAP without A·P whole.
    const bool row_by_row_option = options_.products_row_by_row && comm_size(comm_) > 1;
    const ScopedOption row_by_row(row_by_row_option ? "-matptap_via" : nullptr, "allatonce");
    // GAMG's transfers from the matrix without the couplings between fields, where there are
    // several (petsc_segregated.hpp); the levels' operators from the matrix itself.
    PMat within;
    // -vpc_<name>_within_fields false: aggregates across fields (as before; for comparisons).
    PetscBool segregate = PETSC_TRUE;
    VPC_PETSC(PetscOptionsGetBool(nullptr, prefix_.c_str(), "-within_fields", &segregate, nullptr));
    // Collective: every rank decides alike (a restricted operator has fewer rows than the fields
    // on some ranks only).
    if (segregate && options_.kind == "cg-gamg" &&
        allreduce_and(comm_, field_.size() == static_cast<std::size_t>(op->n_owned())) && several_fields(comm_, field_))
      within = within_fields(op->mat(), field_);
    set_up_ksp(op->mat(), within ? within.get() : op->mat(), direct() ? nullptr : rigid_body_modes(*op).get());
    if (within) {
      PC pc = nullptr;
      VPC_PETSC(KSPGetPC(ksp_, &pc));
      galerkin_levels(pc, op->mat());
      drop_product_data(pc);
      VPC_PETSC(KSPSetOperators(ksp_, op->mat(), op->mat()));
      VPC_PETSC(KSPSetReusePreconditioner(ksp_, PETSC_TRUE));
    }
    setup_flops_ = flops() - start;
    rebuild_cost_ = extra_iterations_ = reference_rate_[0] = reference_rate_[1] = 0;
    rebuild_ = false;
    loose_ = false;  // the new KSP stops at options_.rtol
    VPC_PETSC(MatCreateVecs(op->mat(), x_.out(), b_.out()));
    n_ = op->n_owned();
    ++n_factorizations_;
  }
  void refactorize(const SpdOperator& A, const char* what) override {
    const auto* op = dynamic_cast<const PetscOperator*>(&A);
    if (direct() || !ksp_ || !op || op->n_owned() != n_ || rebuild_) {
      factorize(A, what);
      return;
    }
    // The multigrid hierarchy of the last set-up serves the changed operator (rows fixed or
    // freed: the primal contact solver's active set), with the finest level's smoother and
    // residual on the new operator (cheap: a Jacobi diagonal and a Chebyshev eigenvalue
    // estimate). Smoothing with the old operator took twice the iterations on foundation-3d
    // n = 40 (20-27 a solve against 10-16); rebuilding the whole hierarchy costs ~15 of them.
    // It is rebuilt once the iterations it costs beyond its first rate pay for that (rebuild_).
    what_ = what;
    VPC_PETSC(KSPSetOperators(ksp_, op->mat(), op->mat()));
    VPC_PETSC(KSPSetReusePreconditioner(ksp_, PETSC_TRUE));
    PC pc = nullptr;
    VPC_PETSC(KSPGetPC(ksp_, &pc));
    PetscBool multigrid = PETSC_FALSE;
    VPC_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &multigrid));
    if (multigrid) {
      PetscInt levels = 0;
      VPC_PETSC(PCMGGetLevels(pc, &levels));
      KSP smoother = nullptr;
      VPC_PETSC(PCMGGetSmoother(pc, levels - 1, &smoother));
      VPC_PETSC(KSPSetOperators(smoother, op->mat(), op->mat()));
      VPC_PETSC(PCMGSetResidual(pc, levels - 1, PCMGResidualDefault, op->mat()));
    }
  }
  bool iterative() const override { return !direct(); }
  long long iterations() const override { return iterations_; }
  void set_relative_tolerance(double rtol) override {
    loose_ = rtol > 0;
    if (!direct() && ksp_)
      VPC_PETSC(KSPSetTolerances(ksp_, rtol > 0 ? rtol : options_.rtol, 1e-300, PETSC_DEFAULT, options_.max_iterations));
  }
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const override {
    if (x.size() != n_) x = Eigen::VectorXd::Zero(n_);
    Placed pb(b_, b.data()), px(x_, x.data());
    const double start = flops();
    VPC_PETSC(KSPSolve(ksp_, b_, x_));
    check_converged(true);
    if (!direct()) note_iterations(flops() - start);
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const override {
    // MUMPS solves the block together, an iterative solver column by column.
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n_, B.cols());
    PetscInt N = 0;
    VPC_PETSC(VecGetSize(b_, &N));
    PMat Bm, Xm;
    VPC_PETSC(MatCreateDense(comm_, n_, PETSC_DECIDE, N, B.cols(), const_cast<double*>(B.data()), Bm.out()));
    VPC_PETSC(MatCreateDense(comm_, n_, PETSC_DECIDE, N, B.cols(), X.data(), Xm.out()));
    VPC_PETSC(KSPMatSolve(ksp_, Bm, Xm));
    check_converged(false);
    return X;
  }
  int n_factorizations() const override { return n_factorizations_; }
  /// MUMPS' Schur complement of [A Bᵀ; B 0] where m solves with A's factor (4 flops an entry of it
  /// for each: forward and backward) would cost more than A's factorization, which the augmented
  /// one about repeats (dome-3d refine = 1 on 2 ranks, m = 1,865: contact set-up 19.7 s by solves),
  /// and they take more than one block of 64 (which costs about one solve, less than an analysis).
  std::optional<Eigen::MatrixXd> schur_complement(const Eigen::SparseMatrix<double>& B_local,
                                                  const std::vector<int>& rows, int m) const override {
    if (!direct() || !ksp_ || m <= 64) return std::nullopt;
    Mat A = nullptr, F = nullptr;
    PC pc = nullptr;
    VPC_PETSC(KSPGetOperators(ksp_, &A, nullptr));
    VPC_PETSC(KSPGetPC(ksp_, &pc));
    VPC_PETSC(PCFactorGetMatrix(pc, &F));
    const MumpsFactorSize factor = mumps_factor_size(F);  // global: every rank decides alike
    if (4.0 * factor.entries * m < factor.flops) return std::nullopt;
    return mumps_schur_complement(comm_, A, B_local, rows, m, what_.c_str());
  }

  /// PETSc's GMRES, right preconditioned (its stopping residual is the true one), over a shell
  /// matrix A + C, preconditioned by this solver's PC of A (MUMPS' factor, or the kept multigrid
  /// hierarchy: its iterations count in the rebuild decision as a CG solve's do).
  void solve_perturbed(const SpdOperator& A, const Perturbation& C, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                       double rtol, const char* what) const override {
    const auto* op = dynamic_cast<const PetscOperator*>(&A);
    require(op != nullptr && ksp_ && op->n_owned() == n_, "internal: GMRES needs the factorized PETSc operator ({})", what);
    Shell shell{op->mat(), &C, n_};
    PMat J;
    VPC_PETSC(MatCreateShell(comm_, n_, n_, PETSC_DETERMINE, PETSC_DETERMINE, &shell, J.out()));
    VPC_PETSC(MatShellSetOperation(J, MATOP_MULT, reinterpret_cast<void (*)(void)>(&Shell::mult)));
    PKsp gmres;
    VPC_PETSC(KSPCreate(comm_, gmres.out()));
    VPC_PETSC(KSPSetOperators(gmres, J, J));
    VPC_PETSC(KSPSetType(gmres, KSPGMRES));
    VPC_PETSC(KSPGMRESSetRestart(gmres, kRestart));
    VPC_PETSC(KSPSetPCSide(gmres, PC_RIGHT));
    VPC_PETSC(KSPSetTolerances(gmres, rtol, 1e-300, PETSC_DEFAULT, options_.max_iterations));
    VPC_PETSC(KSPSetResidualHistory(gmres, nullptr, PETSC_DECIDE, PETSC_TRUE));
    PC pc = nullptr, inner = nullptr;
    VPC_PETSC(KSPGetPC(gmres, &pc));
    VPC_PETSC(KSPGetPC(ksp_, &inner));
    VPC_PETSC(PCSetType(pc, PCSHELL));
    VPC_PETSC(PCShellSetContext(pc, inner));
    VPC_PETSC(PCShellSetApply(pc, &Shell::precondition));
    if (x.size() != n_) x = Eigen::VectorXd::Zero(n_);
    x.setZero();
    Placed pb(b_, b.data()), px(x_, x.data());
    const double start = flops();
    VPC_PETSC(KSPSolve(gmres, b_, x_));
    KSPConvergedReason reason;
    VPC_PETSC(KSPGetConvergedReason(gmres, &reason));
    PetscInt its = 0;
    VPC_PETSC(KSPGetIterationNumber(gmres, &its));
    require(reason > 0, "solving with the {} failed (GMRES: {}, after {} iterations)", what, KSPConvergedReasons[reason], its);
    if (!direct()) note_iterations(gmres, flops() - start);
  }

 private:
  static constexpr int kRestart = 50;
  /// solve_perturbed's operator and preconditioner.
  struct Shell {
    Mat A;
    const Perturbation* C;
    int n;
    static PetscErrorCode mult(Mat J, Vec x, Vec y) {
      Shell* s = nullptr;
      PetscCall(MatShellGetContext(J, &s));
      PetscCall(MatMult(s->A, x, y));
      const double* xa = nullptr;
      double* ya = nullptr;
      PetscCall(VecGetArrayRead(x, &xa));
      Eigen::VectorXd xv = Eigen::Map<const Eigen::VectorXd>(xa, s->n), c;
      PetscCall(VecRestoreArrayRead(x, &xa));
      try {
        (*s->C)(xv, c);
      } catch (...) {
        return PETSC_ERR_LIB;
      }
      PetscCall(VecGetArray(y, &ya));
      Eigen::Map<Eigen::VectorXd>(ya, s->n) += c;
      PetscCall(VecRestoreArray(y, &ya));
      return 0;
    }
    static PetscErrorCode precondition(PC pc, Vec x, Vec y) {
      void* inner = nullptr;
      PetscCall(PCShellGetContext(pc, &inner));
      return PCApply(static_cast<PC>(inner), x, y);
    }
  };
  bool direct() const { return options_.kind == "mumps"; }

  /// Rigid-body modes (the near-null space of elasticity) for algebraic multigrid, from the coordinates.
  PetscHandle<MatNullSpace, MatNullSpaceDestroy> rigid_body_modes(const PetscOperator& op) const {
    PetscHandle<MatNullSpace, MatNullSpaceDestroy> rigid;
    if (options_.kind != "cg-gamg" || coordinates_.size() != op.n_owned() || dim_ <= 0) return rigid;
    PVec xyz;
    VPC_PETSC(MatCreateVecs(op.mat(), xyz.out(), nullptr));
    VPC_PETSC(VecSetBlockSize(xyz, dim_));
    Placed p(xyz, coordinates_.data());
    VPC_PETSC(MatNullSpaceCreateRigidBody(xyz, rigid.out()));
    return rigid;
  }

  /// The KSP takes a PETSc reference to A. Throws naming `what_` if the factorization fails.
  /// MUMPS sizes its workspace from the analysis plus ICNTL(14) percent; on several ranks
  /// its dynamic scheduling can need more (INFOG(1) = −9, seen as MAT_FACTOR_OUTMEMORY,
  /// now and then on block-3d at 2 ranks), so the factorization is redone with twice the
  /// margin, up to 800 % (-vpc_<name>_mat_mumps_icntl_14 overrides every try).
  void set_up_ksp(Mat A, Mat P, MatNullSpace near_null_space) {
    for (int margin = 50;; margin *= 2) {
      const MatFactorError err = try_set_up_ksp(A, P, near_null_space, margin);
      if (err == MAT_FACTOR_NOERROR) return;
      if (err == MAT_FACTOR_OUTMEMORY && margin < 800) continue;
      require(err != MAT_FACTOR_OUTMEMORY, "the {}: MUMPS ran out of workspace (last try with ICNTL(14) = {} %)", what_, margin);
      fail("the {} is not positive definite (MUMPS factorization failed: {})", what_,
           err == MAT_FACTOR_NUMERIC_ZEROPIVOT  ? "zero pivot"
           : err == MAT_FACTOR_STRUCT_ZEROPIVOT ? "structurally zero pivot"
                                                : "error " + std::to_string(static_cast<int>(err)));
    }
  }

  /// One try of set_up_ksp, with `margin` % extra MUMPS workspace; the factorization's error.
  MatFactorError try_set_up_ksp(Mat A, Mat P, MatNullSpace near_null_space, int margin) {
    VPC_PETSC(KSPCreate(comm_, ksp_.out()));
    VPC_PETSC(KSPSetOptionsPrefix(ksp_, prefix_.c_str()));
    VPC_PETSC(KSPSetOperators(ksp_, A, P));
    PC pc = nullptr;
    VPC_PETSC(KSPGetPC(ksp_, &pc));
    if (direct()) {
      VPC_PETSC(KSPSetType(ksp_, KSPPREONLY));
      VPC_PETSC(PCSetType(pc, PCCHOLESKY));
      VPC_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
      VPC_PETSC(PCFactorSetUpMatSolverType(pc));
      Mat F = nullptr;
      VPC_PETSC(PCFactorGetMatrix(pc, &F));
      VPC_PETSC(MatMumpsSetIcntl(F, 14, margin));
    } else {
      VPC_PETSC(KSPSetType(ksp_, KSPCG));
      VPC_PETSC(KSPSetTolerances(ksp_, options_.rtol, 1e-300, PETSC_DEFAULT, options_.max_iterations));
      VPC_PETSC(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
      VPC_PETSC(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED));
      VPC_PETSC(KSPSetResidualHistory(ksp_, nullptr, PETSC_DECIDE, PETSC_TRUE));  // see note_iterations
      if (options_.kind == "cg-gamg") {
        VPC_PETSC(PCSetType(pc, PCGAMG));
        // One Chebyshev sweep a level (PETSc's default: two): more iterations, each cheaper;
        // foundation-3d n = 40 on 2 ranks, primal contact solver: 2.6 → 1.8 s a step, one
        // solve of K unchanged. An option given (PETSC_OPTIONS, -vpc_<name>_...) wins.
        default_option("-" + prefix_ + "mg_levels_ksp_max_it", "1");
        if (near_null_space) VPC_PETSC(MatSetNearNullSpace(P, near_null_space));
        // Transfers from another matrix than A (galerkin_levels): GAMG's smoothed-aggregation
        // eigenvalue estimates are P's, and the Chebyshev smoothers would keep them for A's levels,
        // whose D⁻¹A can reach beyond them (an indefinite preconditioner: two stiff blocks pressed
        // and slid through a contact pair). Without them each smoother estimates on its own operator.
        if (P != A) VPC_PETSC(PCGAMGSetUseSAEstEig(pc, PETSC_FALSE));
      } else {
        VPC_PETSC(PCSetType(pc, PCHYPRE));
        VPC_PETSC(PCHYPRESetType(pc, "boomeramg"));
      }
    }
    VPC_PETSC(KSPSetFromOptions(ksp_));
    VPC_PETSC(KSPSetUp(ksp_));
    drop_product_data(pc);
    MatFactorError err = MAT_FACTOR_NOERROR;
    if (direct()) {
      Mat F = nullptr;
      VPC_PETSC(PCFactorGetMatrix(pc, &F));
      VPC_PETSC(MatFactorGetError(F, &err));
    }
    return err;
  }

  /// A preconditioner kept by refactorize is rebuilt once what it has cost since it was
  /// built, in iterations beyond the rate of its first solve (iterations per decade of
  /// residual reduction, so that solves from different guesses compare; loose and tight
  /// solves each against their own first), exceeds what building it costs (its set-up's
  /// floating-point operations over an iteration's, as PETSc counts them). The decision is the
  /// same on every rank (iteration counts, and the cost taken as the ranks' largest) and from
  /// run to run: with the set-up's time over an iteration's (~30 iterations on foundation-3d
  /// n = 70) the preconditioner was rebuilt at other solves in each run, and ironing-3d's results
  /// differed between runs of the same binary at round-off.
  void note_iterations(double solve_flops) const { note_iterations(ksp_, solve_flops); }
  void note_iterations(KSP ksp, double solve_flops) const {
    PetscInt its = 0;
    VPC_PETSC(KSPGetIterationNumber(ksp, &its));
    iterations_ += its;
    if (rebuild_cost_ == 0 && its > 0) {  // its is the same on every rank; the flops are this rank's (0 on
                                          // a rank that owns no rows): the reduction is on every rank
      rebuild_cost_ = solve_flops > 0 ? kSetupWork * setup_flops_ / (solve_flops / static_cast<double>(its)) : 0.0;
      VPC_PETSC(MPI_Allreduce(MPI_IN_PLACE, &rebuild_cost_, 1, MPI_DOUBLE, MPI_MAX, comm_));
    }
    const PetscReal* history = nullptr;
    PetscInt n = 0;
    VPC_PETSC(KSPGetResidualHistory(ksp, &history, &n));
    if (its < 3 || n < 2 || !(history[n - 1] > 0) || !(history[0] > history[n - 1])) return;  // too few to judge
    const double decades = std::log10(history[0] / history[n - 1]);
    double& reference = reference_rate_[loose_ ? 1 : 0];
    if (reference == 0) {
      reference = static_cast<double>(n - 1) / decades;
      return;
    }
    extra_iterations_ += std::max(0.0, static_cast<double>(its) - reference * decades);
    rebuild_ = extra_iterations_ > rebuild_cost_;
  }

  /// Throws unless the last solve converged (a block solve reports no iterations).
  void check_converged(bool single) const {
    KSPConvergedReason reason;
    VPC_PETSC(KSPGetConvergedReason(ksp_, &reason));
    PetscInt its = 0;
    VPC_PETSC(KSPGetIterationNumber(ksp_, &its));
    require(single ? reason > 0 : reason >= 0, "solving with the {} failed ({}, after {} iterations)", what_,
            KSPConvergedReasons[reason], its);
  }

  MPI_Comm comm_;
  std::string prefix_;
  PetscSolverOptions options_;
  PKsp ksp_;
  std::string what_;
  int n_factorizations_ = 0;
  PVec x_, b_;
  int n_ = 0;
  Eigen::VectorXd coordinates_;
  int dim_ = 0;
  std::vector<int> field_;  // of each owned row (set_fields)
  // See note_iterations: the set-up's cost (operations, then iterations), the reference rate
  // (iterations per decade, tight and loose solves) and the iterations spent beyond it.
  // GAMG's set-up does much work that PETSc counts no operations for (the graph, its coarsening,
  // symbolic products): its time over an iteration's was 4.5–5.3 times its counted operations over
  // an iteration's on foundation-3d n = 20 and 40 (82–113 iterations against 18–21).
  static constexpr double kSetupWork = 5;
  static double flops() {
    PetscLogDouble f = 0;
    VPC_PETSC(PetscGetFlops(&f));
    return f;
  }
  double setup_flops_ = 0;
  mutable double rebuild_cost_ = 0, extra_iterations_ = 0, reference_rate_[2] = {0, 0};  // [tight, loose]
  bool loose_ = false;                 // the next solves stop above the solver's own tolerance
  mutable bool rebuild_ = false;
  mutable long long iterations_ = 0;  // over single solves (iterations())
};

}  // namespace

Comm make_mpi_comm(MPI_Comm comm) { return Comm(std::make_shared<MpiComm>(comm)); }

void check_linear_solver(const std::string& kind) {
  require(kind == "mumps" || kind == "cg-gamg" || kind == "cg-hypre",
          "unknown linear solver '{}'; expected mumps, cg-gamg or cg-hypre", kind);
}

namespace {

/// The sum of the ranks' local matrices as an MPIAIJ matrix, with exact preallocation.
PMat assemble_mpiaij(MPI_Comm mpi, const Eigen::SparseMatrix<double>& local, const std::vector<PetscInt>& l2g,
                     PetscInt n_owned, PetscInt n_global, int block_size) {
  PMat pre, A;
  VPC_PETSC(MatCreate(mpi, pre.out()));
  VPC_PETSC(MatSetType(pre, MATPREALLOCATOR));
  VPC_PETSC(MatSetSizes(pre, n_owned, n_owned, n_global, n_global));
  VPC_PETSC(MatSetBlockSize(pre, block_size));
  VPC_PETSC(MatSetUp(pre));
  add_local_matrix(pre, local, l2g);
  VPC_PETSC(MatAssemblyBegin(pre, MAT_FINAL_ASSEMBLY));
  VPC_PETSC(MatAssemblyEnd(pre, MAT_FINAL_ASSEMBLY));
  VPC_PETSC(MatCreate(mpi, A.out()));
  VPC_PETSC(MatSetType(A, MATAIJ));
  VPC_PETSC(MatSetSizes(A, n_owned, n_owned, n_global, n_global));
  VPC_PETSC(MatSetBlockSize(A, block_size));
  VPC_PETSC(MatPreallocatorPreallocate(pre, PETSC_TRUE, A));
  add_local_matrix(A, local, l2g);
  VPC_PETSC(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  VPC_PETSC(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  VPC_PETSC(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE));
  VPC_PETSC(MatSetOption(A, MAT_SPD, PETSC_TRUE));
  return A;
}

}  // namespace

PetscOperator::PetscOperator(Comm comm, const Eigen::SparseMatrix<double>& local, const std::vector<PetscInt>& l2g,
                             PetscInt n_owned, PetscInt n_global, int block_size)
    : PetscOperator(comm, assemble_mpiaij(mpi_of(comm), local, l2g, n_owned, n_global, block_size)) {}

PetscOperator::PetscOperator(Comm comm, PMat A) : comm_(std::move(comm)), A_(std::move(A)) {
  VPC_PETSC(MatCreateVecs(A_, x_.out(), y_.out()));
  PetscInt n = 0;
  VPC_PETSC(VecGetLocalSize(x_, &n));
  n_owned_ = static_cast<int>(n);
}

void PetscOperator::mult(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  y.resize(n_owned_);
  Placed px(x_, x.data()), py(y_, y.data());
  VPC_PETSC(MatMult(A_, x_, y_));
}

void PetscOperator::residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r) const {
  Eigen::VectorXd Ax;
  mult(x, Ax);
  r = b - Ax;
}

Eigen::VectorXd PetscOperator::diagonal() const {
  Eigen::VectorXd d(n_owned_);
  Placed py(y_, d.data());
  VPC_PETSC(MatGetDiagonal(A_, y_));
  return d;
}

long long PetscOperator::nonzeros() const {
  MatInfo info;
  VPC_PETSC(MatGetInfo(A_, MAT_GLOBAL_SUM, &info));
  return static_cast<long long>(info.nz_used);
}

std::unique_ptr<SpdOperator> PetscOperator::restrict_to_free(const std::vector<char>& fixed) const {
  PetscInt begin = 0;
  VPC_PETSC(MatGetOwnershipRange(A_, &begin, nullptr));
  std::vector<PetscInt> free;
  for (int i = 0; i < n_owned_; ++i)
    if (!fixed[i]) free.push_back(begin + i);
  PIs is;
  VPC_PETSC(ISCreateGeneral(PetscObjectComm(reinterpret_cast<PetscObject>(A_.get())),
                            static_cast<PetscInt>(free.size()), free.data(), PETSC_COPY_VALUES, is.out()));
  PMat AFF;
  VPC_PETSC(MatCreateSubMatrix(A_, is, is, MAT_INITIAL_MATRIX, AFF.out()));
  VPC_PETSC(MatSetOption(AFF, MAT_SPD, PETSC_TRUE));
  return std::make_unique<PetscOperator>(comm_, std::move(AFF));
}

namespace {

/// A += B, B on the owned rows and columns (owned numbering), new entries allowed; assembled.
void add_owned_block(Mat A, const Eigen::SparseMatrix<double>& B, int n_owned) {
  VPC_PETSC(MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscInt begin = 0;
  VPC_PETSC(MatGetOwnershipRange(A, &begin, nullptr));
  std::vector<PetscInt> l2g(static_cast<size_t>(n_owned));
  std::iota(l2g.begin(), l2g.end(), begin);
  add_local_matrix(A, B, l2g);
  VPC_PETSC(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  VPC_PETSC(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
}

/// C (a copy of A's values on A's pattern) with the `fixed` owned rows and columns reduced to A's
/// diagonal (SpdOperator::with_fixed).
void fix_rows(Mat C, Mat A, int n_owned, const std::vector<char>& fixed) {
  PetscInt begin = 0;
  VPC_PETSC(MatGetOwnershipRange(A, &begin, nullptr));
  std::vector<PetscInt> rows;
  for (int i = 0; i < n_owned; ++i)
    if (fixed[i]) rows.push_back(begin + i);
  // Zeroes the values, keeps the nonzero structure (MatZeroRowsColumns does not compress);
  // then A's diagonal back on the fixed rows.
  PVec d;
  VPC_PETSC(MatCreateVecs(A, d.out(), nullptr));
  VPC_PETSC(MatGetDiagonal(A, d));
  VPC_PETSC(MatZeroRowsColumns(C, static_cast<PetscInt>(rows.size()), rows.data(), 1.0, nullptr, nullptr));
  VPC_PETSC(MatDiagonalSet(C, d, INSERT_VALUES));
  VPC_PETSC(MatSetOption(C, MAT_SPD, PETSC_TRUE));
}

}  // namespace

std::unique_ptr<SpdOperator> PetscOperator::with_fixed(const std::vector<char>& fixed) const {
  PMat C;
  VPC_PETSC(MatDuplicate(A_, MAT_COPY_VALUES, C.out()));
  fix_rows(C, A_, n_owned_, fixed);
  return std::make_unique<PetscOperator>(comm_, std::move(C));
}

bool PetscOperator::assign_with_fixed(const SpdOperator& base, const std::vector<char>& fixed,
                                      const Eigen::SparseMatrix<double>* owned_block) {
  const auto* b = dynamic_cast<const PetscOperator*>(&base);
  // This operator was made from base by copies and insertions only, so an equal count of stored
  // entries (over all ranks: every rank decides alike) is an equal pattern.
  if (b == nullptr || b->n_owned_ != n_owned_ || b->nonzeros() != nonzeros()) return false;
  VPC_PETSC(MatCopy(b->A_, A_, SAME_NONZERO_PATTERN));
  // An entry outside the pattern is taken (a correct matrix, a new pattern: the next call then
  // finds the counts differ and returns false before copying).
  if (owned_block) add_owned_block(A_, *owned_block, n_owned_);
  fix_rows(A_, A_, n_owned_, fixed);  // the diagonal of base + B (fix_rows reads it first)
  return true;
}

std::unique_ptr<SpdOperator> PetscOperator::plus(const Eigen::SparseMatrix<double>& B) const {
  PMat C;
  VPC_PETSC(MatDuplicate(A_, MAT_COPY_VALUES, C.out()));
  add_owned_block(C, B, n_owned_);
  VPC_PETSC(MatSetOption(C, MAT_SPD, PETSC_TRUE));
  return std::make_unique<PetscOperator>(comm_, std::move(C));
}

RowProduct PetscOperator::rows(const std::vector<int>& rows) const {
  // MatCreateSubMatrix with all of this rank's columns: S's column layout is A's, so its
  // product scatters only the ghost values those rows read.
  PetscInt begin = 0;
  VPC_PETSC(MatGetOwnershipRange(A_, &begin, nullptr));
  std::vector<PetscInt> global(rows.begin(), rows.end());
  for (PetscInt& g : global) g += begin;
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(A_.get()));
  PIs is_rows, is_cols;
  VPC_PETSC(ISCreateGeneral(comm, static_cast<PetscInt>(global.size()), global.data(), PETSC_COPY_VALUES, is_rows.out()));
  VPC_PETSC(ISCreateStride(comm, n_owned_, begin, 1, is_cols.out()));
  auto S = std::make_shared<PMat>();
  VPC_PETSC(MatCreateSubMatrix(A_, is_rows, is_cols, MAT_INITIAL_MATRIX, S->out()));
  auto vx = std::make_shared<PVec>(), vy = std::make_shared<PVec>();
  VPC_PETSC(MatCreateVecs(*S, vx->out(), vy->out()));
  const auto m = static_cast<Eigen::Index>(rows.size());
  return [S, vx, vy, m](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    y.resize(m);
    Placed px(*vx, x.data()), py(*vy, y.data());
    VPC_PETSC(MatMult(*S, *vx, *vy));
  };
}

namespace {

class PetscBackend final : public Backend {
 public:
  PetscBackend(Comm comm, PetscSolverOptions options) : comm_(std::move(comm)), options_(std::move(options)) {}
  const Comm& comm() const override { return comm_; }
  std::unique_ptr<SpdOperator> assemble(const Eigen::SparseMatrix<double>& local, const Layout& layout,
                                        int block_size) const override {
    std::vector<PetscInt> l2g(static_cast<size_t>(layout.n_local()));
    std::iota(l2g.begin(), l2g.begin() + layout.n_owned(), static_cast<PetscInt>(layout.begin()));
    std::copy(layout.ghosts().begin(), layout.ghosts().end(), l2g.begin() + layout.n_owned());
    return std::make_unique<PetscOperator>(comm_, local, l2g, layout.n_owned(), layout.n_global(), block_size);
  }
  std::unique_ptr<LinearSolver> factor(const std::string& name) const override {
    return std::make_unique<PetscFactor>(mpi_of(comm_), name, options_);
  }
  std::string describe() const override { return "PETSc " + options_.kind; }
  std::string linear_solver() const override { return options_.kind; }
  std::string engine() const override { return "petsc"; }

 private:
  Comm comm_;
  PetscSolverOptions options_;
};

}  // namespace

std::shared_ptr<const Backend> make_petsc_backend(Comm comm, PetscSolverOptions options) {
  return std::make_shared<const PetscBackend>(std::move(comm), std::move(options));
}

}  // namespace vpc::la
