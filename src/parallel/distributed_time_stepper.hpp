#pragma once
// The fully discrete scheme of SPEC §2 on a mesh partitioned over MPI ranks: the
// five steps of TimeStepper::advance, with the elementwise work (G, φ, z, ε, σ)
// on each rank's own cells, the global vectors and matrices in PETSc (ghosted
// vectors carry the values of the ghost layer) and the two inequalities solved
// by DistributedContactSolver and the damage solver of the serial engine over the
// PETSc backend of la/ (solvers/damage_solver.hpp).
#include "fem/cell_geometry.hpp"
#include "parallel/distributed_mesh.hpp"
#include "la/petsc.hpp"
#include "la/vector.hpp"
#include "parallel/distributed_solvers.hpp"
#include "scheme/problem.hpp"
#include "scheme/time_stepper.hpp"

#include <memory>
#include <vector>

namespace vpc {

/// The distributed state: u on the free dofs as a ghosted PETSc vector and β on
/// the nodes as an la::Vector (global numbering of DistributedMesh), σ, ε, z on
/// the owned cells, λ (all contact nodes) on every rank.
struct DistributedState {
  int n = 0;
  double t = 0;
  PVec u;
  la::Vector beta;
  std::vector<SymTensor> sigma, eps, z;
  Vector lambda;
};

/// Refuses (vpc::Error, naming the option) what the PETSc engine does not do yet:
/// the penalty–duality solvers, step halving (max_halvings > 0), ContactSolverOptions
/// other than the defaults, a damage ReducedSolve other than automatic. They are
/// serial-only until the engines are one code path (issue 12); nothing is ignored
/// silently. A function of `choice` only, so every rank decides alike; the
/// constructor below calls it first, a run loop may call it earlier to report once.
void require_petsc_engine_supports(const SolverChoice& choice);

class DistributedTimeStepper {
 public:
  /// `problem` supplies the data (its mesh is not used: `part` is this rank's piece).
  DistributedTimeStepper(std::shared_ptr<const Problem> problem, DistributedMesh part, SolverChoice choice,
                         PetscSolverOptions linear = {});

  const Problem& problem() const { return *problem_; }
  const DistributedMesh& part() const { return part_; }
  const DistributedState& state() const { return state_; }
  bool done() const { return state_.n >= problem_->n_steps; }
  /// Steps 1–5 of SPEC §2 from n − 1 to n. Collective; every rank gets the same report.
  StepReport step();

  /// The displacement at the part's nodes (owned and ghosts), full space: node * d + c (0 on Γ1).
  Vector local_u() const;
  /// β at the part's nodes (owned and ghosts).
  Vector local_beta() const;
  /// min β and its node in the numbering of the mesh as read, by the rule of
  /// minimum_at (the serial engine's). Collective; the same on every rank.
  MinimumAt beta_minimum() const;
  const SetupTiming& setup_timing() const { return setup_timing_; }
  int n_factorizations() const;
  bool keeps_w() const { return contact_->keeps_w(); }
  const PetscLinearSolver& stiffness_solver() const { return *K_solver_; }
  /// Sets the state from values at the part's nodes (u full space, node * d + c;
  /// β) and owned cells (σ, ε, z), and λ, at step n, time t (a resumed run).
  void restore(int n, double t, const Vector& u_nodes, const Vector& beta_nodes, std::vector<SymTensor> sigma,
               std::vector<SymTensor> eps, std::vector<SymTensor> z, const Vector& lambda);

 private:
  std::shared_ptr<const Problem> problem_;
  DistributedMesh part_;
  SolverChoice choice_;
  std::vector<CellGeometry> geo_;
  std::vector<int> traction_facets_;
  la::Comm comm_;
  std::unique_ptr<la::PetscOperator> K_, M_;
  PVec F_;
  la::Vector fphi_;
  std::unique_ptr<PetscLinearSolver> K_solver_;
  std::unique_ptr<DistributedContactSolver> contact_;
  std::unique_ptr<DamageSolver> damage_;
  DistributedState state_;
  SetupTiming setup_timing_;
};

/// A local Eigen copy of a ghosted vector's local form (owned entries, then ghosts).
Vector ghosted_local(Vec v);

}  // namespace vpc
