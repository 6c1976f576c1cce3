// The serial backend (la/backend.hpp): Eigen operators, and la::LinearSolver by
// CHOLMOD's supernodal Cholesky.
#include "core/error.hpp"
#include "la/backend.hpp"
#include "la/blas.hpp"
#include "la/linear_solver.hpp"
#include "la/memory_estimate.hpp"

#include <cholmod.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <thread>

namespace vpc::la {

Eigen::MatrixXd LinearSolver::forward(const Eigen::MatrixXd&) const {
  fail("internal: forward half of a factor that has no triangular halves");
}
Eigen::MatrixXd LinearSolver::backward(const Eigen::MatrixXd&) const {
  fail("internal: backward half of a factor that has no triangular halves");
}

namespace {

/// CHOLMOD reports an error through a callback without a user pointer: the last
/// message of this thread is kept here and put into the vpc::Error thrown, and
/// CHOLMOD's own printing is off (print = 0), so a failure reads as one message.
thread_local std::string last_cholmod_error;

std::string status_name(int status) {
  switch (status) {
    case CHOLMOD_OUT_OF_MEMORY: return "out of memory";
    case CHOLMOD_TOO_LARGE: return "problem too large";
    case CHOLMOD_INVALID: return "invalid input";
    case CHOLMOD_NOT_POSDEF: return "not positive definite";
    default: return fmt::format("CHOLMOD status {}", status);
  }
}

void record_cholmod_error(int status, const char* file, int line, const char* message) {
  const char* base = std::strrchr(file, '/');
  const std::string name = status_name(status);
  last_cholmod_error = fmt::format("{} ({}CHOLMOD status {} at {}:{})", message, name == message ? "" : name + "; ",
                                   status, base ? base + 1 : file, line);
}

/// What a failed CHOLMOD call says: its recorded message, else its status.
std::string cholmod_failure(const cholmod_common& c) {
  return last_cholmod_error.empty() ? status_name(c.status) : last_cholmod_error;
}

/// CHOLMOD's rcond is (min diag L / max diag L)²: a singular matrix whose last
/// pivot is a round-off residue passes the positivity check but not this one.
constexpr double kMinRcond = 1e-14;

using Long = SuiteSparse_long;

const SparseMatrix& matrix_of(const SpdOperator& A, const char* what) {
  const auto* s = dynamic_cast<const SparseOperator*>(&A);
  require(s != nullptr, "internal: CHOLMOD factorizes one process's operators only ({})", what);
  return s->matrix();
}

/// Supernodal LLᵀ through CHOLMOD's 64-bit integer interface (cholmod_l_*): a
/// factor may exceed 2³¹ entries (issue 11: the 32-bit one stopped at "problem
/// too large" and the unchecked status then crashed). Every call's status is checked.
class CholmodFactor final : public LinearSolver {
 public:
  CholmodFactor() {
    cholmod_l_start(&c_);
    c_.print = 0;  // errors are reported by vpc::Error, not printed by CHOLMOD
    c_.error_handler = record_cholmod_error;
    // As Eigen's CholmodSupernodalLLT (used before): the same ordering and factor.
    c_.final_asis = 1;
    c_.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~CholmodFactor() override {
    free_factor();
    cholmod_l_finish(&c_);
  }
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  std::optional<FactorEstimate> analyze(const SpdOperator& A, const char* what) override {
    return analyze(matrix_of(A, what), what);
  }
  void factorize(const SpdOperator& A, const char* what) override { factorize(matrix_of(A, what), what); }

  FactorEstimate analyze(const SparseMatrix& A, const char* what) {
    require(A.rows() == A.cols(), "{}: matrix is not square", what);
    free_factor();
    factored_ = false;
    n_ = static_cast<int>(A.rows());
    what_ = what;
    estimate_ = {};
    if (n_ == 0) return estimate_;
    copy_lower(A);
    cholmod_sparse view = view_lower();
    last_cholmod_error.clear();
    L_ = cholmod_l_analyze(&view, &c_);
    if (!L_ || c_.status < CHOLMOD_OK)
      fail("{}: the symbolic analysis for the Cholesky factorization failed: {}", describe(), cholmod_failure(c_));
    estimate_.rows = n_;
    estimate_.entries = static_cast<double>(L_->xsize);
    estimate_.flops = c_.fl;
    estimate_.factor_bytes = static_cast<double>(L_->xsize) * sizeof(double) + integer_bytes();
    // Peak extra during the numeric factorization: CHOLMOD's permuted transpose
    // of A and its dense update buffer (maxcsize entries), besides our copy of A.
    estimate_.workspace_bytes = 2 * lower_bytes() + static_cast<double>(L_->maxcsize) * sizeof(double) +
                                static_cast<double>(n_) * 6 * sizeof(Long);
    analyzed_nnz_ = A.nonZeros();
    pattern_hash_ = pattern_hash(A);
    return estimate_;
  }

  void factorize(const SparseMatrix& A, const char* what) {
    // Reuse the analysis just done by analyze() for this matrix (its values are
    // copied afresh); any other matrix is analyzed here.
    // A factor whose analysis is for the same pattern (the primal contact solver's K with
    // another active set, issue 14) is refactorized numerically: the ordering and the
    // supernodes are kept.
    const bool same_pattern = L_ && A.rows() == n_ && A.nonZeros() == analyzed_nnz_ && pattern_hash(A) == pattern_hash_;
    if (same_pattern && (factored_ || L_->xtype == CHOLMOD_PATTERN))
      copy_lower(A);
    else
      analyze(A, what);
    factored_ = false;
    if (n_ == 0) return;
    cholmod_sparse view = view_lower();
    // Factorize with every core's BLAS, solve with one (see la/blas.hpp).
    set_blas_threads(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    last_cholmod_error.clear();
    const int ok = cholmod_l_factorize(&view, L_, &c_);
    set_blas_threads(1);
    lower_ = {};  // the copy of A is not needed by the solves
    if (!ok || c_.status < CHOLMOD_OK)
      fail("{}: the Cholesky factorization failed: {}; the factor would hold {:.4g} entries ({})", describe(),
           cholmod_failure(c_), estimate_.entries, format_bytes(estimate_.factor_bytes));
    // The hint about Γ1 is K's alone (issue 26: it was given for the damage matrix H as well,
    // whose maker, solvers/damage_solver.cpp, adds its own cause).
    const std::string hint =
        std::string_view(what_).starts_with("elastic stiffness K") ? " (is the body clamped on a non-empty part Γ1?)" : "";
    require(c_.status != CHOLMOD_NOT_POSDEF && L_->minor == L_->n, "{}: the matrix is not positive definite (pivot {} of {}){}",
            describe(), L_->minor + 1, n_, hint);
    const double rc = rcond();
    require(rc > kMinRcond,
            "{}: the matrix is not positive definite: numerically singular (reciprocal condition estimate {:.1e} < {:.0e}){}",
            describe(), rc, kMinRcond, hint);
    // The supernodal factor is always LLᵀ; forward()/backward() rely on it.
    require(L_->is_ll, "{}: CHOLMOD returned an LDLᵀ factor where LLᵀ was asked for", what);
    // Frees CHOLMOD's factorization workspace (for 2D meshes ~1/3 of the factor's
    // size), which it would otherwise keep until the solver is destroyed.
    cholmod_l_free_work(&c_);
    factored_ = true;
    ++n_factorizations_;
  }

  void solve(const Vector& b, Vector& x) const override {
    x.resize(b.size());
    if (n_ > 0) run_solve(CHOLMOD_A, b.data(), b.rows(), 1, x.data());
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const override {
    if (n_ == 0) return Eigen::MatrixXd(0, B.cols());
    Eigen::MatrixXd X(B.rows(), B.cols());
    run_solve(CHOLMOD_A, B.data(), B.rows(), B.cols(), X.data());
    return X;
  }
  bool has_halves() const override { return true; }
  /// The permutation is applied here (k-th entry of PB = row Perm[k] of B), so
  /// that only one dense block besides the caller's and CHOLMOD's result is alive.
  Eigen::MatrixXd forward(const Eigen::MatrixXd& B) const override {
    if (n_ == 0) return Eigen::MatrixXd(0, B.cols());
    const Long* perm = static_cast<const Long*>(L_->Perm);
    Eigen::MatrixXd Y(B.rows(), B.cols());
    for (Eigen::Index j = 0; j < B.cols(); ++j)
      for (Eigen::Index k = 0; k < B.rows(); ++k) Y(k, j) = B(perm[k], j);
    run_solve(CHOLMOD_L, Y.data(), Y.rows(), Y.cols(), Y.data());
    return Y;
  }
  Eigen::MatrixXd backward(const Eigen::MatrixXd& Y) const override {
    if (n_ == 0) return Eigen::MatrixXd(0, Y.cols());
    const Long* perm = static_cast<const Long*>(L_->Perm);
    Eigen::MatrixXd X(Y.rows(), Y.cols());
    run_solve(CHOLMOD_Lt, Y.data(), Y.rows(), Y.cols(), X.data());
    Eigen::MatrixXd out(X.rows(), X.cols());
    for (Eigen::Index j = 0; j < X.cols(); ++j)
      for (Eigen::Index k = 0; k < X.rows(); ++k) out(perm[k], j) = X(k, j);
    return out;
  }
  int n_factorizations() const override { return n_factorizations_; }
  /// Values plus the integer structure of the factor.
  double factor_bytes() const override {
    if (!L_ || L_->xtype == CHOLMOD_PATTERN) return 0;
    return static_cast<double>(L_->is_super ? L_->xsize : L_->nzmax) * sizeof(double) + integer_bytes();
  }

 private:
  double integer_bytes() const {
    const double ints = L_->is_super ? static_cast<double>(L_->ssize + 4 * L_->nsuper + 3 * L_->n)
                                     : static_cast<double>(L_->nzmax + 6 * L_->n);
    return ints * sizeof(Long);
  }
  double lower_bytes() const {
    return static_cast<double>(lower_.i.size()) * (sizeof(double) + sizeof(Long)) +
           static_cast<double>(lower_.p.size()) * sizeof(Long);
  }
  std::string describe() const {
    return fmt::format("{} (n = {}, {} nonzeros in the lower triangle)", what_, n_, nnz_lower_);
  }

  /// FNV-1a over the column pointers and row indices (explicit zeros count as entries).
  static std::uint64_t pattern_hash(const SparseMatrix& A) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](std::uint64_t x) { h = (h ^ x) * 1099511628211ull; };
    for (int j = 0; j < A.outerSize(); ++j) {
      for (SparseMatrix::InnerIterator it(A, j); it; ++it) mix(static_cast<std::uint64_t>(it.row()));
      mix(~static_cast<std::uint64_t>(j));
    }
    return h;
  }

  /// The lower triangle of A with 64-bit indices (CHOLMOD reads only it: stype −1).
  void copy_lower(const SparseMatrix& A) {
    lower_.p.assign(1, 0);
    lower_.p.reserve(static_cast<size_t>(n_) + 1);
    lower_.i.clear();
    lower_.x.clear();
    lower_.i.reserve(static_cast<size_t>(A.nonZeros() / 2 + n_));
    lower_.x.reserve(static_cast<size_t>(A.nonZeros() / 2 + n_));
    for (int j = 0; j < n_; ++j) {
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        if (it.row() >= j) {
          lower_.i.push_back(it.row());
          lower_.x.push_back(it.value());
        }
      lower_.p.push_back(static_cast<Long>(lower_.i.size()));
    }
    nnz_lower_ = lower_.i.size();
  }
  cholmod_sparse view_lower() {
    cholmod_sparse s{};
    s.nrow = s.ncol = static_cast<size_t>(n_);
    s.nzmax = lower_.i.size();
    s.p = lower_.p.data();
    s.i = lower_.i.data();
    s.x = lower_.x.data();
    s.stype = -1;
    s.itype = CHOLMOD_LONG;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }

  /// X = A⁻¹B, L⁻¹B or L⁻ᵀB (sys) for the n × cols blocks B and X (X may be B).
  void run_solve(int sys, const double* B, Eigen::Index rows, Eigen::Index cols, double* X) const {
    require(factored_, "{}: solve without a successful factorization", what_);
    require(rows == n_, "{}: a right-hand side of {} rows for a matrix of size {}", what_, rows, n_);
    cholmod_dense b{};
    b.nrow = b.d = static_cast<size_t>(n_);
    b.ncol = static_cast<size_t>(cols);
    b.nzmax = b.nrow * b.ncol;
    b.x = const_cast<double*>(B);  // read only
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    cholmod_common& c = const_cast<cholmod_common&>(c_);
    last_cholmod_error.clear();
    cholmod_dense* x = cholmod_l_solve(sys, L_, &b, &c);
    if (!x || c.status < CHOLMOD_OK) {
      if (x) cholmod_l_free_dense(&x, &c);
      fail("{}: a solve with the Cholesky factor failed: {}", describe(), cholmod_failure(c));
    }
    std::copy_n(static_cast<const double*>(x->x), b.nzmax, X);
    cholmod_l_free_dense(&x, &c);
  }
  double rcond() { return cholmod_l_rcond(L_, &c_); }
  void free_factor() {
    if (L_) cholmod_l_free_factor(&L_, &c_);
    L_ = nullptr;
  }

  struct Lower {
    std::vector<Long> p, i;
    std::vector<double> x;
  };
  cholmod_common c_{};
  cholmod_factor* L_ = nullptr;
  Lower lower_;
  std::string what_;
  FactorEstimate estimate_;
  Eigen::Index analyzed_nnz_ = -1;
  std::uint64_t pattern_hash_ = 0;
  size_t nnz_lower_ = 0;
  bool factored_ = false;
  int n_ = 0;
  int n_factorizations_ = 0;
};

class SerialBackend final : public Backend {
 public:
  const Comm& comm() const override { return comm_; }
  std::unique_ptr<SpdOperator> assemble(const Eigen::SparseMatrix<double>& local, const Layout& layout,
                                        int) const override {
    require(layout.comm().serial() && layout.n_ghosts() == 0 && local.rows() == layout.n_owned(),
            "internal: the serial backend assembles one process's matrices");
    return std::make_unique<SparseOperator>(local);
  }
  std::unique_ptr<LinearSolver> factor(const std::string& name) const override { return make_cholmod_factor(name); }
  std::string describe() const override { return "CHOLMOD"; }
  std::string linear_solver() const override { return "cholmod"; }
  std::string engine() const override { return "serial"; }

 private:
  Comm comm_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_cholmod_factor(const std::string&) { return std::make_unique<CholmodFactor>(); }

std::shared_ptr<const Backend> serial_backend() {
  static const auto backend = std::make_shared<const SerialBackend>();
  return backend;
}

}  // namespace vpc::la

namespace vpc {

FactorEstimate estimate_cholmod_factor(const SparseMatrix& A, const char* what) {
  la::CholmodFactor f;
  return f.analyze(A, what);
}

}  // namespace vpc
