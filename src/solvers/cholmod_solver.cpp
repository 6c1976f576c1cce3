#include "core/error.hpp"
#include "solvers/linear_solver.hpp"
#include "solvers/blas_threads.hpp"

#include <thread>

#include <Eigen/CholmodSupport>

namespace vpc {

namespace {

/// Eigen keeps CHOLMOD's factor protected; the reciprocal condition estimate needs it.
class Llt : public Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> {
 public:
  double rcond() { return cholmod_rcond(m_cholmodFactor, &cholmod()); }
  /// Values plus the integer structure of the factor.
  double bytes() const {
    const cholmod_factor* L = m_cholmodFactor;
    if (!L) return 0;
    const double ints = L->is_super ? static_cast<double>(L->ssize + 4 * L->nsuper + 3 * L->n)
                                    : static_cast<double>(L->nzmax + 6 * L->n);
    return static_cast<double>(L->is_super ? L->xsize : L->nzmax) * sizeof(double) + ints * sizeof(int);
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
