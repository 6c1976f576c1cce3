#pragma once
// The linear solver of an SpdOperator, direct (a factorization) or iterative (a
// preconditioned Krylov solver): solve for one right-hand side or a block. The triangular halves of a Cholesky
// factor A = PᵀLLᵀP (forward(B) = L⁻¹PB, backward(Y) = PᵀL⁻ᵀY) are an optional
// capability: CHOLMOD has them, MUMPS and CG do not (has_halves()).
// Backends: make_cholmod_factor (one process, la/cholmod_factor.cpp) and the
// PETSc backend's factors (la/petsc.hpp: MUMPS, CG + GAMG, CG + hypre). Any of them also
// solves A + C for a small nonsymmetric C by GMRES with itself as preconditioner
// (solve_perturbed: la/gmres.cpp on one process, PETSc's GMRES in la/petsc.cpp).
#include "la/operator.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vpc {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Vector = Eigen::VectorXd;

/// The size of a Cholesky factor from the symbolic analysis alone (no numbers).
struct FactorEstimate {
  double rows = 0;             // n
  double entries = 0;          // values in the factor
  double factor_bytes = 0;     // values and integer structure, held until the solver goes
  double workspace_bytes = 0;  // extra at the peak of the numeric factorization
  double flops = 0;            // of the numeric factorization (CHOLMOD's count for its ordering)
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

/// The size of CHOLMOD's factor of A (lower triangle read), from its symbolic analysis only.
FactorEstimate estimate_cholmod_factor(const SparseMatrix& A, const char* what);

}  // namespace vpc

namespace vpc::la {

/// y = C x on the owned entries: a change C of the factored matrix A, possibly nonsymmetric,
/// that solve_perturbed takes on top of A (the primal friction solver's Coulomb coupling).
using Perturbation = std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& y)>;

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// Factorizes A (kept by reference by iterative backends: A must outlive the
  /// next factorize). Throws vpc::Error naming `what` when it fails.
  virtual void factorize(const SpdOperator& A, const char* what) = 0;
  /// A matrix close to the one factorized last, over the same layout (the primal contact
  /// solver's next active set: some Dirichlet rows changed; kept by reference as in
  /// factorize). Direct solvers factorize it (CHOLMOD on the same analysis); iterative ones
  /// take it as their operator and keep their preconditioner while it serves.
  virtual void refactorize(const SpdOperator& A, const char* what) { factorize(A, what); }
  /// An iterative solver (its solves stop at a relative residual, set_relative_tolerance).
  virtual bool iterative() const { return false; }
  /// The relative residual the next solves stop at; 0: the solver's own. Direct solvers ignore it.
  virtual void set_relative_tolerance(double /*rtol*/) {}
  /// The factor's size from a symbolic analysis alone (a following factorize of
  /// the same A reuses it); nullopt where the backend cannot say (PETSc).
  virtual std::optional<FactorEstimate> analyze(const SpdOperator&, const char*) { return std::nullopt; }
  /// The coordinate (x, y or z) each owned row stands for, rows in blocks of `dim`
  /// per node: algebraic multigrid builds the rigid-body modes of elasticity from
  /// them. Before factorize; ignored by direct solvers.
  virtual void set_coordinates(const Eigen::VectorXd& /*coordinates*/, int /*dim*/) {}
  /// The field (a body) each owned row belongs to: algebraic multigrid keeps its aggregates
  /// within one field. Before factorize; ignored by direct solvers.
  virtual void set_fields(const std::vector<int>& /*field*/) {}
  /// x = A⁻¹ b on the owned entries; x on entry is an iterative solver's initial guess.
  virtual void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const = 0;
  /// X = A⁻¹ B for a block of right-hand sides (owned rows).
  virtual Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const = 0;
  /// x = (A + C)⁻¹ b by restarted GMRES from x = 0, preconditioned by this solver's factor (or
  /// preconditioner) of A, the operator of its last factorize/refactorize. Stops when its residual
  /// is within `rtol` of b's (preconditioned on one process, Eigen's; true on PETSc's, right
  /// preconditioned): the caller measures the true residual. Throws vpc::Error naming `what` when
  /// GMRES does not get there. The default is Eigen's GMRES, one process only.
  virtual void solve_perturbed(const SpdOperator& A, const Perturbation& C, const Eigen::VectorXd& b,
                               Eigen::VectorXd& x, double rtol, const char* what) const;
  /// S = B A⁻¹ Bᵀ (m × m, the same on every rank) for a few rows B by the backend's own means,
  /// where they cost less than m solves (MUMPS: one factorization of [A Bᵀ; B 0], la/mumps_schur.hpp);
  /// nullopt where it has none or the solves are cheaper. `B_local`: this rank's rows of B
  /// (columns: A's owned rows), `rows`: their places among B's m rows. Collective.
  virtual std::optional<Eigen::MatrixXd> schur_complement(const Eigen::SparseMatrix<double>& /*B_local*/,
                                                          const std::vector<int>& /*rows*/, int /*m*/) const {
    return std::nullopt;
  }
  virtual bool has_halves() const { return false; }
  /// Only when has_halves().
  virtual Eigen::MatrixXd forward(const Eigen::MatrixXd& B) const;
  virtual Eigen::MatrixXd backward(const Eigen::MatrixXd& Y) const;
  virtual int n_factorizations() const = 0;
  /// An iterative solver's Krylov iterations over all its solves so far (0 for a direct one): the
  /// run's linear work, the same from run to run where wall times are not.
  virtual long long iterations() const { return 0; }
  /// Memory held by the factor (bytes; 0 where the backend does not say).
  virtual double factor_bytes() const { return 0; }
};

/// Makes a backend's factor; `name` says which matrix ("H", "H_reduced": the PETSc
/// backend reads its options under the prefix vpc_<name>_).
using LinearSolverFactory = std::function<std::unique_ptr<LinearSolver>(const std::string& name)>;

/// CHOLMOD's supernodal Cholesky (64-bit integer interface) of a SparseOperator
/// (one process), with halves and a symbolic analysis.
std::unique_ptr<LinearSolver> make_cholmod_factor(const std::string& name = "");

}  // namespace vpc::la
