#pragma once
// The narrow linear-algebra interface of the serial scheme: factorize a symmetric
// positive definite matrix once, then solve many times. Its one implementation is
// CHOLMOD (supernodal, cholmod_l_*). The PETSc engine does not implement it: it has
// its own PetscLinearSolver (la/petsc_linear_solver.hpp), without analyze()
// or the triangular halves.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <memory>

namespace vpc {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Vector = Eigen::VectorXd;

/// The size of a Cholesky factor from the symbolic analysis alone (no numbers).
struct FactorEstimate {
  double rows = 0;             // n
  double entries = 0;          // values in the factor
  double factor_bytes = 0;     // values and integer structure, held until the solver goes
  double workspace_bytes = 0;  // extra at the peak of the numeric factorization
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// Symbolic analysis of A (fill-reducing ordering and the factor's structure):
  /// cheap next to factorize(), and says how large the factor will be. A following
  /// factorize() of the same matrix (same `what`, same pattern) reuses it.
  virtual FactorEstimate analyze(const SparseMatrix& A, const char* what) = 0;
  /// Factorizes A (symmetric positive definite; only the lower triangle is read).
  /// Throws vpc::Error naming `what` (and A's size) if A is not positive definite
  /// or the factorization fails (out of memory, too large).
  virtual void factorize(const SparseMatrix& A, const char* what) = 0;
  /// x = A⁻¹ b.
  virtual Vector solve(const Vector& b) const = 0;
  /// X = A⁻¹ B for a block of right-hand sides.
  virtual Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const = 0;
  /// The two halves of a solve with the Cholesky factor A = Pᵀ L Lᵀ P:
  /// forward(B) = L⁻¹ P B and backward(Y) = Pᵀ L⁻ᵀ Y, so A⁻¹ = backward ∘ forward
  /// and B₁ᵀ A⁻¹ B₂ = forward(B₁)ᵀ forward(B₂). Each costs half a solve.
  virtual Eigen::MatrixXd forward(const Eigen::MatrixXd& B) const = 0;
  virtual Eigen::MatrixXd backward(const Eigen::MatrixXd& Y) const = 0;
  virtual int size() const = 0;
  /// Number of factorizations done so far (for reports and tests).
  virtual int n_factorizations() const = 0;
  /// Memory held by the factor (bytes).
  virtual double factor_bytes() const = 0;
};

/// Columns per block of dense right-hand sides of n rows: up to `most`, but each
/// block below 24 MiB. Larger blocks are beyond glibc's largest mmap threshold
/// (32 MiB; the programs keep freed memory, app/process_policy.hpp): mapped afresh at every allocation, they cost
/// a page fault per 4 KiB (measured: 2D n = 640, contact set-up 14.8 s with
/// blocks of 8 × 6.6 MB).
inline int rhs_block_columns(Eigen::Index n, int most = 8) {
  const double fit = 24.0 * 1024 * 1024 / (8.0 * static_cast<double>(std::max<Eigen::Index>(n, 1)));
  return std::max(1, std::min(most, static_cast<int>(fit)));
}

/// CHOLMOD supernodal Cholesky (64-bit integer interface).
std::unique_ptr<LinearSolver> make_cholmod_solver();

/// The size of CHOLMOD's factor of A, from its symbolic analysis only.
FactorEstimate estimate_cholmod_factor(const SparseMatrix& A, const char* what);

}  // namespace vpc
