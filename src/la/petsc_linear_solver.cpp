#include "la/petsc_linear_solver.hpp"

namespace vpc {

PetscLinearSolver::PetscLinearSolver(MPI_Comm comm, const std::string& prefix, PetscSolverOptions options)
    : comm_(comm), prefix_(prefix), options_(std::move(options)) {
  require(options_.kind == "mumps" || options_.kind == "cg-gamg" || options_.kind == "cg-hypre",
          "unknown linear solver '{}'; expected mumps, cg-gamg or cg-hypre", options_.kind);
}

void PetscLinearSolver::factorize(Mat A, const char* what, MatNullSpace near_null_space) {
  what_ = what;
  VPC_PETSC(KSPCreate(comm_, ksp_.out()));
  VPC_PETSC(KSPSetOptionsPrefix(ksp_, prefix_.c_str()));
  VPC_PETSC(KSPSetOperators(ksp_, A, A));
  PC pc = nullptr;
  VPC_PETSC(KSPGetPC(ksp_, &pc));
  if (options_.kind == "mumps") {
    VPC_PETSC(KSPSetType(ksp_, KSPPREONLY));
    VPC_PETSC(PCSetType(pc, PCCHOLESKY));
    VPC_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  } else {
    VPC_PETSC(KSPSetType(ksp_, KSPCG));
    VPC_PETSC(KSPSetTolerances(ksp_, options_.rtol, 1e-300, PETSC_DEFAULT, options_.max_iterations));
    VPC_PETSC(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
    VPC_PETSC(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED));
    if (options_.kind == "cg-gamg") {
      VPC_PETSC(PCSetType(pc, PCGAMG));
      if (near_null_space) VPC_PETSC(MatSetNearNullSpace(A, near_null_space));
    } else {
      VPC_PETSC(PCSetType(pc, PCHYPRE));
      VPC_PETSC(PCHYPRESetType(pc, "boomeramg"));
    }
  }
  VPC_PETSC(KSPSetFromOptions(ksp_));
  VPC_PETSC(KSPSetUp(ksp_));
  if (options_.kind == "mumps") {
    Mat F = nullptr;
    VPC_PETSC(PCFactorGetMatrix(pc, &F));
    MatFactorError err = MAT_FACTOR_NOERROR;
    VPC_PETSC(MatFactorGetError(F, &err));
    require(err == MAT_FACTOR_NOERROR, "the {} is not positive definite (MUMPS factorization failed: error {})",
            what_, static_cast<int>(err));
  }
  ++n_factorizations_;
}

void PetscLinearSolver::solve(Vec b, Vec x) const {
  VPC_PETSC(KSPSolve(ksp_, b, x));
  KSPConvergedReason reason;
  VPC_PETSC(KSPGetConvergedReason(ksp_, &reason));
  PetscInt its = 0;
  VPC_PETSC(KSPGetIterationNumber(ksp_, &its));
  last_iterations_ = static_cast<int>(its);
  require(reason > 0, "solving with the {} failed ({}, after {} iterations)", what_, KSPConvergedReasons[reason], its);
}

void PetscLinearSolver::solve(Mat B, Mat X) const {
  VPC_PETSC(KSPMatSolve(ksp_, B, X));
  KSPConvergedReason reason;
  VPC_PETSC(KSPGetConvergedReason(ksp_, &reason));
  require(reason >= 0, "solving with the {} failed ({})", what_, KSPConvergedReasons[reason]);
}

}  // namespace vpc
