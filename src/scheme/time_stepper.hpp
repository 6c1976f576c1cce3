#pragma once
// The fully discrete scheme of SPEC §2 (the paper's Problem 3.1, (3.4)–(3.9)),
// once for every backend: a facade over its parts, each in its own file —
//   the discrete system, built once (scheme/discrete_system.hpp), and its solvers
//   (scheme/scheme_solvers.hpp);
//   the step's data F_n, u_D, g (scheme/step_data.hpp);
//   the step, steps 1–5 in order (scheme/scheme_step.hpp);
//   step-size control: error estimate, snapshot and rollback, halving (scheme/step_control.hpp);
//   the step's checks and report (scheme/step_checks.hpp, scheme/step_report.hpp).
#include "fem/assembly.hpp"
#include "fem/cell_geometry.hpp"
#include "fem/dof_map.hpp"
#include "la/backend.hpp"
#include "la/vector.hpp"
#include "part/mesh_part.hpp"
#include "problem/problem.hpp"
#include "scheme/discrete_system.hpp"
#include "scheme/pair_slider.hpp"
#include "scheme/scheme_solvers.hpp"
#include "scheme/scheme_step.hpp"
#include "scheme/solver_choice.hpp"
#include "scheme/state.hpp"
#include "scheme/step_checks.hpp"
#include "scheme/step_control.hpp"
#include "scheme/step_report.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/damage_solver.hpp"
#include "solvers/solver_cost.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vpc {

/// Advances the scheme on this process's part of the mesh (part/mesh_part.hpp)
/// over a linear-algebra backend (la/backend.hpp): one class for one process and
/// for many. Elementwise work (G, φ, z, ε, σ) runs on the part's cells; vectors
/// of unknowns are the owned entries; every decision is a reduction over the
/// backend's communicator, so every process gets the same report.
class TimeStepper {
 public:
  /// One process: the whole mesh, Eigen + CHOLMOD. Validates the problem.
  TimeStepper(std::shared_ptr<const Problem> problem, SolverChoice choice = {});
  /// This process's part over a backend (the problem was validated where the part
  /// was made: distribute_mesh). Collective.
  TimeStepper(std::shared_ptr<const Problem> problem, MeshPart part, std::shared_ptr<const la::Backend> backend,
              SolverChoice choice = {});

  const Problem& problem() const { return *sys_.problem; }
  const MeshPart& part() const { return sys_.part; }
  /// The part's mesh (the whole mesh on one process).
  const Mesh& mesh() const { return sys_.part.mesh(); }
  const la::Comm& comm() const { return sys_.part.comm; }
  const la::Backend& backend() const { return *sys_.backend; }
  const SolverChoice& solvers() const { return choice_; }
  /// This process's state: u and β at the part's nodes (owned, then ghosts), σ, ε,
  /// z on its cells, λ for all contact rows.
  const State& state() const { return state_; }
  bool done() const {
    return problem().step_control ? state_.t >= problem().final_time : state_.n >= problem().n_steps;
  }
  /// Advances from step n − 1 to n (steps 1–5 of SPEC §2) on the problem's grid, or by a
  /// step its error control accepts (rejected attempts restore the state before them
  /// exactly); with SolverChoice::max_halvings, a failed step of a fixed grid is redone
  /// as two half steps. Collective.
  StepReport step();
  /// The time levels t_0 … t_n reached so far.
  const std::vector<double>& times() const { return times_; }
  const StepControlState& step_control_state() const { return control_state_; }
  /// After restore() of a checkpoint's state at step n: its time levels t_0 … t_n and
  /// step-size state. Throws vpc::Error unless the times end at the state's.
  void set_step_history(std::vector<double> times, const StepControlState& c);

  /// How far the state is from its own data at t_n (an adaptation's new nodes take u_D and g at their own
  /// positions, which the carried u does not meet until the next step): the largest |u − u_D(t_n)| over
  /// the prescribed dofs, and the largest penetration max(0, N u − g(t_n)) over the contact rows (lengths;
  /// over every process). Collective.
  std::pair<double, double> data_mismatch() const;

  /// Moves the state out (its arrays keep their addresses): for a stepper about to be destroyed whose
  /// state someone still reads (the Python views of a mesh an adaptation replaces). Nothing may step
  /// or read the stepper's state after it.
  State take_state() { return std::move(state_); }

  Snapshot snapshot() const;
  /// The solvers' warm starts of snapshot(), without a copy of the state (checkpoints). Collective.
  Vector contact_warm_state() const;
  Vector damage_warm_state() const;
  /// Restores a snapshot of a run of the same problem and part; throws vpc::Error if the sizes differ.
  void restore(const Snapshot& s);

  const DofMap& dofs() const { return sys_.part.dofs; }
  /// The constant matrices, for inspection (the Python module, docs/python.md): K over the
  /// free dofs (on one process a la::SparseOperator), the part's mass M and Laplacian A
  /// over its nodes, and the contact rows N (ContactConstraints::N: owned rows × owned free dofs).
  const la::SpdOperator& stiffness_operator() const { return *sys_.K; }
  const SparseMatrix& mass_matrix() const { return sys_.M_local; }
  const SparseMatrix& laplacian_matrix() const { return sys_.A_local; }
  SparseMatrix contact_rows() const { return sys_.contact->N; }
  /// The contact set of the configuration the last step started from (part/contact_set.hpp): its
  /// nodes (owned and ghost, by row), rows and friction frame.
  const ContactSet& contact() const { return *sys_.contact; }
  int n_factorizations() const;
  /// Krylov iterations of K's and the contact solver's iterative solves so far (0 on direct solvers).
  long long n_linear_iterations() const;
  /// The damage matrices H = M + kκA made so far: one per step size, while at most
  /// four sizes are in use (the least recently used is dropped beyond that).
  int n_damage_matrices() const { return solvers_.damage.n_matrices(); }
  /// The factor of K (for benchmarks: the cost of one solve; made here when the contact
  /// solver is the primal one, which factors K with its active rows instead).
  const la::LinearSolver& stiffness_factor();
  /// One line on how the contact step solves (ContactSolver::describe) and why that solver.
  std::string contact_method() const { return solvers_.contact->describe() + "; " + solvers_.contact_pick.why; }
  /// The contact solver in use ("auto" resolved).
  std::string contact_solver() const { return solvers_.contact->name(); }
  /// Memory of the factors of K and of the damage matrix (bytes; this process).
  double factor_bytes() const;
  /// Memory of the mesh, the constant matrices and the state (bytes, estimated from sizes; this process).
  double model_bytes() const;
  double setup_seconds() const { return setup_timing_.total; }
  const SetupTiming& setup_timing() const { return setup_timing_; }
  /// The estimated cost of the run by the direct and the iterative path (solvers/solver_cost.hpp),
  /// where the backend's factor has a symbolic analysis (CHOLMOD).
  const std::optional<SolverCost>& solver_cost() const { return solver_cost_; }

 private:
  /// One attempt from the current state to t_end with the step k: the step, its report, its
  /// error estimate and whether it is accepted.
  StepReport advance(double k, double t_end);
  StepAttempts attempts();
  /// Large sliding (scheme/pair_slider.hpp): sys_'s contact set at x + u of the state, and the
  /// contact solver for it, where the slider makes a new one. Collective.
  void slide();

  SolverChoice choice_;
  SetupTiming setup_timing_;
  std::optional<SolverCost> solver_cost_;
  DiscreteSystem sys_;
  /// Large-sliding pairs' rows in the configuration each step starts from (scheme/pair_slider.hpp;
  /// does nothing without them). Made before solvers_, which hand it K_local.
  std::unique_ptr<PairSlider> slider_;
  SchemeSolvers solvers_;
  SchemeStep step_;
  LaggedStepBackstop backstop_;
  StepControlState control_state_;
  std::vector<double> times_{0.0};      // t_0 … t_n
  State state_;
  Vector u_free_;  // owned free dofs: the contact solver's warm start
};

}  // namespace vpc
