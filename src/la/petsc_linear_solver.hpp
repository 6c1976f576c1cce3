#pragma once
// The PETSc engine's linear solver: factorize (or precondition) a constant
// symmetric positive definite PETSc matrix once, solve many times. It is not a
// LinearSolver (la/linear_solver.hpp): no symbolic estimate (analyze), no
// triangular halves (forward/backward), vectors and matrices are PETSc's.
//   "mumps"     Cholesky by MUMPS (distributed direct; the default)
//   "cg-gamg"   conjugate gradients with PETSc's algebraic multigrid (rigid-body
//               near-null space for elasticity when coordinates are given)
//   "cg-hypre"  conjugate gradients with hypre BoomerAMG
// The iterative ones start from the x passed in (the previous step's solution)
// and stop at a relative residual of `rtol` (default 1e-12). Every KSP also reads
// the PETSc options under its prefix (e.g. -vpc_K_ksp_monitor), so any PETSc
// solver can be chosen from the command line or PETSC_OPTIONS.
#include "la/petsc_util.hpp"

#include <string>

namespace vpc {

struct PetscSolverOptions {
  std::string kind = "mumps";
  double rtol = 1e-12;
  int max_iterations = 10000;
};

class PetscLinearSolver {
 public:
  /// `prefix`: the PETSc options prefix of this solver (e.g. "vpc_K_").
  PetscLinearSolver(MPI_Comm comm, const std::string& prefix, PetscSolverOptions options = {});
  /// Sets up the solver for A (its KSP takes a PETSc reference to A, so the caller
  /// may destroy its handle).
  /// `near_null_space`: rigid-body modes for AMG on elasticity (may be null).
  /// Throws vpc::Error naming `what` if the factorization fails.
  void factorize(Mat A, const char* what, MatNullSpace near_null_space = nullptr);
  /// x = A⁻¹ b; x is the initial guess of an iterative solver. Throws if it fails.
  void solve(Vec b, Vec x) const;
  /// X = A⁻¹ B for a block of right-hand sides (dense matrices; MUMPS solves them
  /// together, an iterative solver one by one). Throws if it fails.
  void solve(Mat B, Mat X) const;
  bool iterative() const { return options_.kind != "mumps"; }
  int n_factorizations() const { return n_factorizations_; }
  /// Krylov iterations of the last solve (1 for the direct solver).
  int last_iterations() const { return last_iterations_; }
  const std::string& kind() const { return options_.kind; }

 private:
  MPI_Comm comm_;
  std::string prefix_;
  PetscSolverOptions options_;
  PKsp ksp_;
  std::string what_;
  int n_factorizations_ = 0;
  mutable int last_iterations_ = 0;
};

}  // namespace vpc
