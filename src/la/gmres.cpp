// LinearSolver::solve_perturbed on one process: Eigen's GMRES (unsupported/IterativeSolvers) over
// the matrix-free A + C, preconditioned by the solver's own solve with A (Eigen's matrix-free
// pattern: "Matrix-free solvers" in its documentation).
#include "core/error.hpp"
#include "la/linear_solver.hpp"

#include <unsupported/Eigen/IterativeSolvers>

namespace vpc::la {
namespace {

/// A + C as an Eigen expression: y = A x + C x.
class PerturbedOperator;

}  // namespace
}  // namespace vpc::la

namespace Eigen::internal {
template <>
struct traits<vpc::la::PerturbedOperator> : public traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace vpc::la {
namespace {

class PerturbedOperator : public Eigen::EigenBase<PerturbedOperator> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = false };
  PerturbedOperator(const SpdOperator& A, const Perturbation& C) : A_(&A), C_(&C) {}
  Eigen::Index rows() const { return A_->n_owned(); }
  Eigen::Index cols() const { return A_->n_owned(); }
  template <typename Rhs>
  Eigen::Product<PerturbedOperator, Rhs, Eigen::AliasFreeProduct> operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<PerturbedOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    Eigen::VectorXd c;
    A_->mult(x, y);
    (*C_)(x, c);
    y += c;
  }

 private:
  const SpdOperator* A_;
  const Perturbation* C_;
};

/// The LinearSolver's solve with A as GMRES's preconditioner.
class FactorPreconditioner {
 public:
  FactorPreconditioner() = default;
  template <typename M>
  FactorPreconditioner& analyzePattern(const M&) { return *this; }
  template <typename M>
  FactorPreconditioner& factorize(const M&) { return *this; }
  template <typename M>
  FactorPreconditioner& compute(const M&) { return *this; }
  template <typename Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
    factor->solve(Eigen::VectorXd(b), x);
    return x;
  }
  Eigen::ComputationInfo info() { return Eigen::Success; }
  const LinearSolver* factor = nullptr;
};

}  // namespace
}  // namespace vpc::la

namespace Eigen::internal {
template <typename Rhs>
struct generic_product_impl<vpc::la::PerturbedOperator, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<vpc::la::PerturbedOperator, Rhs,
                                generic_product_impl<vpc::la::PerturbedOperator, Rhs>> {
  template <typename Dest>
  static void scaleAndAddTo(Dest& dst, const vpc::la::PerturbedOperator& lhs, const Rhs& rhs, const double& alpha) {
    Eigen::VectorXd y;
    lhs.apply(Eigen::VectorXd(rhs), y);
    dst += alpha * y;
  }
};
}  // namespace Eigen::internal

namespace vpc::la {

void LinearSolver::solve_perturbed(const SpdOperator& A, const Perturbation& C, const Eigen::VectorXd& b,
                                   Eigen::VectorXd& x, double rtol, const char* what) const {
  require(A.comm().size() == 1, "internal: Eigen's GMRES runs on one process ({})", what);
  // Restarts every kRestart iterations; the Coulomb coupling is a small change of A (μ times some
  // rows of K), so GMRES preconditioned by A's factor needs only a few.
  constexpr int kRestart = 50, kMaxIterations = 1000;
  const PerturbedOperator J(A, C);
  Eigen::GMRES<PerturbedOperator, FactorPreconditioner> gmres;
  gmres.set_restart(kRestart);
  gmres.setMaxIterations(kMaxIterations);
  gmres.setTolerance(rtol);
  gmres.preconditioner().factor = this;
  gmres.compute(J);
  x = gmres.solve(b);
  // Eigen's GMRES can report success at a breakdown (A + C singular, x = 0): the answer must at
  // least reduce the true residual (the caller measures it against its own tolerance).
  Eigen::VectorXd r;
  J.apply(x, r);
  const double error = (b - r).norm(), start = b.norm();
  require(gmres.info() == Eigen::Success && (error < start || start == 0),
          "solving with the {} failed (GMRES: residual {:.3e} of the right-hand side's after {} iterations)", what,
          start > 0 ? error / start : error, gmres.iterations());
}

}  // namespace vpc::la
