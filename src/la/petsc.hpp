#pragma once
// The PETSc backend of the linear-algebra layer (PETSc build only): an MPI
// communicator, MPIAIJ operators assembled from the ranks' local matrices, and
// factors (MUMPS Cholesky, CG + GAMG, CG + hypre), each a KSP with its own
// options prefix.
#include "la/backend.hpp"
#include "la/linear_solver.hpp"
#include "la/operator.hpp"
#include "la/petsc_util.hpp"

#include <Eigen/Sparse>
#include <string>
#include <vector>

namespace vpc {

/// The PETSc backend's linear solver:
///   "mumps"     Cholesky by MUMPS (distributed direct; the default)
///   "cg-gamg"   conjugate gradients with PETSc's algebraic multigrid (rigid-body
///               near-null space for elasticity from the coordinates)
///   "cg-hypre"  conjugate gradients with hypre BoomerAMG
/// The iterative ones stop at a relative residual of `rtol`.
struct PetscSolverOptions {
  std::string kind = "mumps";
  double rtol = 1e-12;
  int max_iterations = 10000;
  /// CG + GAMG: the Galerkin products PᵀAP formed row by row (PETSc's allatonce), keeping no A·P:
  /// less memory, slower set-ups (run/solver_plan.hpp chooses it where the default does not fit).
  bool products_row_by_row = false;
};

}  // namespace vpc

namespace vpc::la {

/// Throws vpc::Error unless `kind` is one of PetscSolverOptions' linear solvers.
void check_linear_solver(const std::string& kind);

/// A Comm whose collectives are MPI's over `comm`.
Comm make_mpi_comm(MPI_Comm comm);

/// An MPIAIJ matrix, symmetric positive definite; its vectors are the owned rows.
class PetscOperator final : public SpdOperator {
 public:
  /// The sum over the ranks of their local matrices (rows and columns numbered
  /// locally, global numbers l2g), with exact preallocation. Collective.
  PetscOperator(Comm comm, const Eigen::SparseMatrix<double>& local, const std::vector<PetscInt>& l2g,
                PetscInt n_owned, PetscInt n_global, int block_size);
  /// Adopts an assembled matrix.
  PetscOperator(Comm comm, PMat A);
  const Comm& comm() const override { return comm_; }
  int n_owned() const override { return n_owned_; }
  void mult(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
  void residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r) const override;
  Eigen::VectorXd diagonal() const override;
  long long nonzeros() const override;
  std::unique_ptr<SpdOperator> restrict_to_free(const std::vector<char>& fixed) const override;
  std::unique_ptr<SpdOperator> with_fixed(const std::vector<char>& fixed) const override;
  bool assign_with_fixed(const SpdOperator& base, const std::vector<char>& fixed,
                         const Eigen::SparseMatrix<double>* owned_block) override;
  std::unique_ptr<SpdOperator> plus(const Eigen::SparseMatrix<double>& owned_block) const override;
  RowProduct rows(const std::vector<int>& rows) const override;
  Mat mat() const { return A_; }

 private:
  Comm comm_;
  PMat A_;
  int n_owned_ = 0;
  PVec x_, y_;  // work vectors whose arrays are placed on the caller's storage
};

/// The PETSc backend over `comm` (make_mpi_comm), factors of the given kind.
std::shared_ptr<const Backend> make_petsc_backend(Comm comm, PetscSolverOptions options);

}  // namespace vpc::la
