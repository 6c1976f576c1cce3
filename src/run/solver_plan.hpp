#pragma once
// The engine and linear solver of a run, chosen once before anything is assembled or
// factorized (issue 27), for the command line, the Python module and mpirun alike:
// from the mesh (its node graph's symbolic Cholesky analysis: K's and H's factors),
// the options and the memory limit. A requested solver that does not fit is refused,
// naming the estimate, the limit and the option to use; the default moves to CG + GAMG
// (memory linear in the unknowns), saying so. One process: CHOLMOD or, when CG + GAMG
// is estimated clearly faster (solvers/solver_cost.hpp), CG + GAMG on the PETSc engine.
//   SolverPlan plan = plan_solver(problem, solvers, {.engine = "auto"});
//   if (!quiet) fmt::print("  {}\n", plan.why);
#include "la/linear_solver.hpp"
#include "la/memory_estimate.hpp"
#include "scheme/time_stepper.hpp"

#include <string>

namespace vpc {

/// What the options ask for.
struct SolverRequest {
  /// --engine: "serial" (one process, CHOLMOD), "petsc" (the PETSc engine, on `ranks`
  /// processes) or "auto" (one process: CHOLMOD or CG + GAMG by the estimates).
  std::string engine = "auto";
  /// --linear-solver: mumps, cg-gamg or cg-hypre on the PETSc engine; empty: the default
  /// (MUMPS if it fits, else CG + GAMG).
  std::string linear_solver{};
  int ranks = 1;              // the processes the run is spread over
  int ranks_on_machine = 1;   // of them, those sharing this machine's memory
  bool petsc_built = false;   // the PETSc engine exists in this build (one process, auto)
  /// The PETSc engine under --engine auto without --linear-solver (issue 48 item 18): the route one
  /// process would take where several ranks cannot gain: rank 0 alone on CHOLMOD (SolverPlan::petsc
  /// false) where one process is estimated below kDistributeAbove seconds, and CG + GAMG instead of
  /// MUMPS where the cost model estimates it clearly faster (hertz-3d on 2 ranks: MUMPS and the dual
  /// 1.35x one process's CG + GAMG).
  bool auto_route = false;
};

/// The sizes the choice is made from, before any matrix is built.
struct ProblemSize {
  double unknowns = 0;       // free displacement dofs (rows of K)
  double nodes = 0, cells = 0;
  double contact_nodes = 0;  // m: rows of N
  double contact_unknowns = 0;  // the dual's: m × the contact block (d with friction: λ_ν and λ_τ; 2m with adhesion)
  double K_nonzeros = 0;     // both triangles
  double node_nonzeros = 0;  // of M, A, H (the node graph, both triangles)
  FactorEstimate K, H;       // CHOLMOD's factors (symbolic analysis of the node graph)
  bool dual_only = false;    // a row only the dual solver takes (dual_only: e.g. a power-law compliance)
};

/// The sizes of `p`'s run on one process: Dirichlet data, contact rows and the symbolic
/// analysis of the node graph, K's factor scaled from it by d (blocks of d dofs a node).
/// `rows`: p's contact rows as its validation built them (Case::contact_rows); null: built here.
ProblemSize problem_size(const Problem& p, const ContactRows& rows = nullptr);

/// CHOLMOD's factors of a node graph that no process holds whole (Problem::block: a generated
/// mesh of `s.nodes` nodes): analysed on `coarse`, the same generator's grid with fewer cells,
/// and scaled to s.nodes by the growth of nested dissection on a d-dimensional grid (factor
/// entries as N log N in 2D and N^(4/3) in 3D, flops as N^(3/2) and N²). Sets s.H and s.K.
void scale_factors(ProblemSize& s, const Mesh& coarse, int d);

/// The chosen engine and linear solver.
struct SolverPlan {
  bool petsc = false;         // the PETSc engine (else one process: Eigen + CHOLMOD)
  std::string linear_solver;  // cholmod, mumps, cg-gamg, cg-hypre
  std::string why;            // one line for the run's header: the choice and its estimates
  double memory = 0;          // the chosen path's estimate on this machine (bytes)
  bool products_row_by_row = false;  // CG + GAMG's Galerkin products formed row by row (less memory)
};

/// The memory of each path on this machine (bytes), by part.
MemoryEstimate cholmod_memory(const Problem& p, const ProblemSize& s, const SolverChoice& solvers);
MemoryEstimate mumps_memory(const Problem& p, const ProblemSize& s, int ranks, int ranks_on_machine);
/// A Krylov solver's (`linear_solver`: cg-gamg or cg-hypre); CG + GAMG's with its Galerkin products
/// formed row by row where `products_row_by_row`.
MemoryEstimate iterative_memory(const Problem& p, const ProblemSize& s, const std::string& linear_solver = "cg-gamg",
                                bool products_row_by_row = false);

/// Chooses for `p` (its whole mesh: on one process, or rank 0's before distribute_mesh).
/// Throws vpc::Error (MemoryLimitError) for a run that fits no allowed path.
SolverPlan plan_solver(const Problem& p, const SolverChoice& solvers, const SolverRequest& request);
SolverPlan plan_solver(const Problem& p, const ProblemSize& size, const SolverChoice& solvers,
                       const SolverRequest& request, const MemoryLimit& limit);

/// SolverRequest::auto_route: below this estimate of one process's time (estimate_solver_cost's
/// direct path) rank 0 runs the case alone. There the PETSc engine's own costs on P ranks (MUMPS'
/// analysis and a message per solve, with every step's exchanges) outweigh what P ranks could save:
/// of 14 shipped cases estimated below it, 13 ran 1.1-40x slower distributed on 2 ranks than on one
/// process, punch-3d 0.82x (docs/parallel.md, "Two ranks against one process").
constexpr double kDistributeAbove = 1.0;

}  // namespace vpc
