#pragma once
// A backend of the linear-algebra layer: what the scheme needs to turn the local
// matrices of this process's cells into global operators and to factorize them.
// The scheme (scheme/time_stepper.hpp) is written once over it, as deal.II's
// step-40 over LinearAlgebraPETSc or DOLFINx over its la::MatSet callable:
//   serial_backend()        one process: Eigen matrices, CHOLMOD (with triangular halves)
//   make_petsc_backend(...) MPI: MPIAIJ matrices, MUMPS / CG + GAMG / CG + hypre (la/petsc.hpp)
#include "la/linear_solver.hpp"
#include "la/layout.hpp"

#include <memory>
#include <string>

namespace vpc::la {

class Backend {
 public:
  virtual ~Backend() = default;
  virtual const Comm& comm() const = 0;
  /// The sum over the processes of their local matrices, whose rows and columns
  /// are the local entries of `layout` (owned, then ghosts). Collective.
  virtual std::unique_ptr<SpdOperator> assemble(const Eigen::SparseMatrix<double>& local, const Layout& layout,
                                                int block_size) const = 0;
  /// A linear solver (factor or CG) for a matrix called `name` (K, H, ...: PETSc reads its options under vpc_<name>_).
  virtual std::unique_ptr<LinearSolver> factor(const std::string& name) const = 0;
  /// For reports: "CHOLMOD", "PETSc mumps", ...
  virtual std::string describe() const = 0;
  /// The linear solver's name as the options say it: "cholmod", "mumps", "cg-gamg", "cg-hypre".
  virtual std::string linear_solver() const = 0;
  /// Whether factor() factorizes (CHOLMOD, MUMPS) rather than iterates (CG).
  bool direct() const { return is_direct(linear_solver()); }
  /// The engine it makes (--engine, summary.json's "engine"): "serial" (one process, Eigen +
  /// CHOLMOD) or "petsc" (PETSc over MPI, on one rank too).
  virtual std::string engine() const = 0;

  /// Whether the linear solver called so factorizes.
  static bool is_direct(const std::string& linear_solver) { return linear_solver == "cholmod" || linear_solver == "mumps"; }
};

/// The backend's factor() as a LinearSolverFactory; it keeps the backend alive, so it
/// may outlive the caller's pointer (a solver stores it for its reduced factors).
inline LinearSolverFactory factor_factory(std::shared_ptr<const Backend> backend) {
  return [backend = std::move(backend)](const std::string& name) { return backend->factor(name); };
}

/// One process: Eigen::SparseMatrix operators, CHOLMOD factors. The one way to a
/// one-process factor outside la/: serial_backend()->factor(name), or
/// factor_factory(serial_backend()) for a solver that makes its own.
std::shared_ptr<const Backend> serial_backend();

}  // namespace vpc::la
