#pragma once
// A symmetric positive definite operator over the owned entries of a Layout,
// assembled from the ranks' local contributions: the serial backend is an
// Eigen::SparseMatrix (SparseOperator, below), the PETSc backend an MPIAIJ
// matrix (la/petsc.hpp). Vectors here are the owned entries.
#include "la/comm.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <functional>
#include <memory>
#include <vector>

namespace vpc::la {

/// x ↦ (A x)_R for a set R of one rank's owned rows (SpdOperator::rows): y gets |R| entries,
/// in R's order. Collective where the operator is (every rank calls it, R empty or not).
using RowProduct = std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& y)>;

class SpdOperator {
 public:
  virtual ~SpdOperator() = default;
  virtual const Comm& comm() const = 0;
  /// Rows owned by this rank.
  virtual int n_owned() const = 0;
  /// y = A x.
  virtual void mult(const Eigen::VectorXd& x, Eigen::VectorXd& y) const = 0;
  /// y = A x over this process's threads where the backend can (the whole matrix of one
  /// process: Aᵀx, the same for a symmetric A stored whole, whose row-major product Eigen
  /// spreads over the OpenMP threads); else mult.
  virtual void mult_threaded(const Eigen::VectorXd& x, Eigen::VectorXd& y) const { mult(x, y); }
  /// The whole matrix where one process holds it (the serial backend); null otherwise.
  virtual const Eigen::SparseMatrix<double>* whole_matrix() const { return nullptr; }
  /// r = b − A x.
  virtual void residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r) const = 0;
  virtual Eigen::VectorXd diagonal() const = 0;
  /// Stored entries over all processes (for reports; collective).
  virtual long long nonzeros() const = 0;
  /// A_FF, F = the owned rows i with fixed[i] == 0, renumbered in order (collective).
  virtual std::unique_ptr<SpdOperator> restrict_to_free(const std::vector<char>& fixed) const = 0;
  /// A with the rows and columns of the owned entries i with fixed[i] != 0 reduced to their
  /// diagonal A_ii (Dirichlet rows: the primal contact solver's active rows; A's scale is
  /// kept, which multigrid's smoothers and coarse spaces need: with rows of the identity
  /// instead, CG + GAMG took 3-4x more iterations a decade on foundation-3d). The
  /// layout, the block size and the stored pattern are kept, so a factor reuses its
  /// analysis and multigrid its rigid-body modes (collective).
  virtual std::unique_ptr<SpdOperator> with_fixed(const std::vector<char>& fixed) const = 0;
  /// This operator made (base + B).with_fixed(fixed) in place (B as in plus; null: none), where
  /// it has base's stored pattern and B's entries lie within it: the primal contact solver's
  /// active set changes without a second copy of K held meanwhile (0.32 GB a rank at
  /// foundation-3d n = 70 on 2 ranks, docs/parallel.md), and with friction its springs change
  /// at every iterate without two copies made (frictional foundation-3d n = 40, 2 ranks: 57 ms
  /// an iterate, 15 % of the contact solves' time). False where the patterns differ or the
  /// backend makes a new one instead (plus, with_fixed). Collective.
  virtual bool assign_with_fixed(const SpdOperator& /*base*/, const std::vector<char>& /*fixed*/,
                                 const Eigen::SparseMatrix<double>* /*owned_block*/) {
    return false;
  }
  /// A + B, B given on the owned rows and columns (n_owned × n_owned, owned
  /// numbering): penalty–duality's H + ωEᵀE (collective).
  virtual std::unique_ptr<SpdOperator> plus(const Eigen::SparseMatrix<double>& owned_block) const = 0;
  /// The product with the owned rows `rows` (ascending) only: a few rows' worth of work where
  /// mult would do the whole matrix's (the primal friction solver's Coulomb coupling needs K's
  /// normal rows at the slip nodes at each GMRES iteration). Collective.
  virtual RowProduct rows(const std::vector<int>& rows) const = 0;
};

/// One process: the whole matrix.
class SparseOperator final : public SpdOperator {
 public:
  explicit SparseOperator(Eigen::SparseMatrix<double> A) : A_(std::move(A)) {}
  const Comm& comm() const override { return comm_; }
  int n_owned() const override { return static_cast<int>(A_.rows()); }
  void mult(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override { y = A_ * x; }
  void mult_threaded(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override { y = A_.transpose() * x; }
  const Eigen::SparseMatrix<double>* whole_matrix() const override { return &A_; }
  void residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r) const override {
    r = b - A_ * x;
  }
  Eigen::VectorXd diagonal() const override { return A_.diagonal(); }
  long long nonzeros() const override { return A_.nonZeros(); }
  std::unique_ptr<SpdOperator> restrict_to_free(const std::vector<char>& fixed) const override;
  std::unique_ptr<SpdOperator> with_fixed(const std::vector<char>& fixed) const override;
  std::unique_ptr<SpdOperator> plus(const Eigen::SparseMatrix<double>& B) const override {
    return std::make_unique<SparseOperator>(A_ + B);
  }
  RowProduct rows(const std::vector<int>& rows) const override;
  const Eigen::SparseMatrix<double>& matrix() const { return A_; }

 private:
  Comm comm_;
  Eigen::SparseMatrix<double> A_;
};

}  // namespace vpc::la
