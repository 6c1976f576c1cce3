#include "core/error.hpp"
#include "solvers/linear_solver.hpp"
#include "solvers/blas_threads.hpp"

#include <algorithm>
#include <thread>

#include <Eigen/CholmodSupport>

namespace vpc {

namespace {

/// Eigen keeps CHOLMOD's factor protected; the condition estimate, the two halves
/// of a solve and the memory report need it.
class Llt : public Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> {
 public:
  double rcond() { return cholmod_rcond(m_cholmodFactor, &cholmod()); }
  /// The two halves of a solve with A = PᵀLLᵀP. The permutation is applied
  /// here (k-th entry of PB = row Perm[k] of B), so that only one dense block
  /// besides the caller's and CHOLMOD's result is alive at a time.
  Eigen::MatrixXd forward(const Eigen::MatrixXd& B) const {
    const int* perm = static_cast<const int*>(m_cholmodFactor->Perm);
    Eigen::MatrixXd Y(B.rows(), B.cols());
    for (Eigen::Index j = 0; j < B.cols(); ++j)
      for (Eigen::Index k = 0; k < B.rows(); ++k) Y(k, j) = B(perm[k], j);
    triangular_solve(CHOLMOD_L, Y);
    return Y;
  }
  Eigen::MatrixXd backward(const Eigen::MatrixXd& Y) const {
    const int* perm = static_cast<const int*>(m_cholmodFactor->Perm);
    Eigen::MatrixXd X = Y;
    triangular_solve(CHOLMOD_Lt, X);
    Eigen::MatrixXd out(X.rows(), X.cols());
    for (Eigen::Index j = 0; j < X.cols(); ++j)
      for (Eigen::Index k = 0; k < X.rows(); ++k) out(perm[k], j) = X(k, j);
    return out;
  }
  /// Frees CHOLMOD's factorization workspace (for 2D meshes ~1/3 of the factor's
  /// size), which it would otherwise keep until the solver is destroyed.
  void free_workspace() { cholmod_free_work(&cholmod()); }
  bool is_ll() const { return m_cholmodFactor && m_cholmodFactor->is_ll; }
  /// Values plus the integer structure of the factor.
  double bytes() const {
    const cholmod_factor* L = m_cholmodFactor;
    if (!L) return 0;
    const double ints = L->is_super ? static_cast<double>(L->ssize + 4 * L->nsuper + 3 * L->n)
                                    : static_cast<double>(L->nzmax + 6 * L->n);
    return static_cast<double>(L->is_super ? L->xsize : L->nzmax) * sizeof(double) + ints * sizeof(int);
  }

 private:
  /// X ← L⁻¹X (sys = CHOLMOD_L) or L⁻ᵀX (CHOLMOD_Lt), in place.
  void triangular_solve(int sys, Eigen::MatrixXd& X) const {
    cholmod_dense b = Eigen::viewAsCholmod(X);
    cholmod_common& c = const_cast<Llt*>(this)->cholmod();
    cholmod_dense* x = cholmod_solve(sys, m_cholmodFactor, &b, &c);
    require(x != nullptr, "CHOLMOD: a triangular solve failed (status {})", c.status);
    std::copy_n(static_cast<const double*>(x->x), X.size(), X.data());
    cholmod_free_dense(&x, &c);
  }
};

/// CHOLMOD's rcond is (min diag L / max diag L)²: a singular matrix whose last
/// pivot is a round-off residue passes the positivity check but not this one.
constexpr double kMinRcond = 1e-14;

class CholmodSolver final : public LinearSolver {
 public:
  void factorize(const SparseMatrix& A, const char* what) override {
    require(A.rows() == A.cols(), "{}: matrix is not square", what);
    n_ = static_cast<int>(A.rows());
    if (n_ == 0) return;
    // Factorize with every core's BLAS, solve with one (see blas_threads.hpp).
    set_blas_threads(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    llt_.compute(A);
    set_blas_threads(1);
    require(llt_.info() == Eigen::Success && llt_.rcond() > kMinRcond,
            "{}: the matrix is not positive definite (is the body clamped on a non-empty part Γ1?)",
            what);
    // The supernodal factor is always LLᵀ; forward()/backward() rely on it.
    require(llt_.is_ll(), "{}: CHOLMOD returned an LDLᵀ factor where LLᵀ was asked for", what);
    llt_.free_workspace();
    ++n_factorizations_;
  }
  Vector solve(const Vector& b) const override {
    if (n_ == 0) return Vector(0);
    return llt_.solve(b);
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const override {
    if (n_ == 0) return Eigen::MatrixXd(0, B.cols());
    return llt_.solve(B);
  }
  Eigen::MatrixXd forward(const Eigen::MatrixXd& B) const override {
    if (n_ == 0) return Eigen::MatrixXd(0, B.cols());
    return llt_.forward(B);
  }
  Eigen::MatrixXd backward(const Eigen::MatrixXd& Y) const override {
    if (n_ == 0) return Eigen::MatrixXd(0, Y.cols());
    return llt_.backward(Y);
  }
  int size() const override { return n_; }
  int n_factorizations() const override { return n_factorizations_; }
  double factor_bytes() const override { return llt_.bytes(); }

 private:
  Llt llt_;
  int n_ = 0;
  int n_factorizations_ = 0;
};

}  // namespace

std::unique_ptr<LinearSolver> make_cholmod_solver() { return std::make_unique<CholmodSolver>(); }

}  // namespace vpc
