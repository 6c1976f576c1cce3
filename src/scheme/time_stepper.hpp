#pragma once
// The fully discrete scheme of SPEC §2 (the paper's Problem 3.1, (3.4)–(3.9)),
// once for every backend. Setup assembles and factorizes everything that is
// constant over the run (K, M + kκA, the contact constraint rows); step()
// performs steps 1–5 in order.
#include "fem/assembly.hpp"
#include "fem/cell_geometry.hpp"
#include "fem/dof_map.hpp"
#include "la/backend.hpp"
#include "la/vector.hpp"
#include "scheme/mesh_part.hpp"
#include "scheme/problem.hpp"
#include "scheme/state.hpp"
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

struct ContactConstraints;  // solvers/contact_solver.hpp

struct SolverChoice {
  std::string contact = "auto";  // "active-set" (dual), "primal-active-set", "penalty-duality" (pick_contact_solver)
  std::string damage = "active-set";   // or "penalty-duality"
  ContactSolverOptions contact_options;
  /// Damage active set: how systems with some β_i at a bound are solved.
  ReducedSolve damage_reduced = ReducedSolve::automatic;
  /// A step whose residuals exceed this (relative) is reported as failed.
  double residual_tolerance = 1e-8;
  /// A failed step is retried as two steps of half the size, at most this many
  /// times nested (0: a failed step is reported as it is).
  int max_halvings = 0;
  /// Optional: told as each setup stage starts (seconds < 0) and when it ends
  /// (its wall time), so that a long setup shows what it is doing (vpcontact run/check).
  std::function<void(const std::string& stage, double seconds)> on_setup_stage;
  /// The memory a run may use (la/memory_estimate.hpp): a size such as "8G",
  /// or empty for $VPCONTACT_MEMORY_LIMIT, else the machine's available memory.
  std::string memory_limit;
  /// The caller can run the case on CG + GAMG instead (--engine auto on one process): with
  /// contact "auto", a set-up whose direct path is estimated to be much slower
  /// (solvers/solver_cost.hpp) throws IterativeIsFaster before factorizing.
  bool iterative_fallback = false;
};

/// The smallest value and where it is. The one rule for min β in the step
/// reports and summary.json of both engines and any rank count: among equal
/// minima (β = 0 or β = 1 at many nodes), the smallest node index in the
/// numbering of the mesh as read.
struct MinimumAt {
  double value = 0;
  int index = -1;
};
/// The minimum of `values` by that rule; `index[i]` is the node number of
/// values[i] (empty: i itself). `values` empty: index −1. NaN entries are
/// passed over unless they come first.
MinimumAt minimum_at(std::span<const double> values, std::span<const int> index = {});
/// The minimum of two candidates by that rule (the reduction over ranks).
MinimumAt minimum_at(const MinimumAt& a, const MinimumAt& b);

struct StepReport {
  int n = 0;
  double t = 0;
  double k = 0;  // the step's size t_n − t_{n−1}
  /// The estimate of the relative error this step adds (StepControl, scheme/time_grid.hpp),
  /// made for every grid; error-controlled steps are chosen by it.
  double error_estimate = 0;
  /// Attempts of this step that were rejected and redone from the state before it
  /// (error-controlled steps: error, event or solver).
  int rejected = 0;
  ContactReport contact;
  DamageReport damage;
  double beta_min = 1, beta_max = 1;
  int beta_min_node = 0;  // by the rule of minimum_at
  double max_von_mises = 0;
  double sigma_norm = 0;  // |σ_n|_{L2}
  /// The contact area: the summed tributary measures of the active contact nodes
  /// (a length in 2D, 1 per node in 1D).
  double contact_area = 0;
  /// With obstacles: the total contact force on each (Problem::contact.obstacles order),
  /// each node's force counted for the obstacle nearest to it at this step.
  std::vector<double> obstacle_force;
  /// The reaction force on each Dirichlet part (dirichlet_parts order): the force its
  /// supports exert on the body, Σ over the part's nodes of (σ_n, ε(φ)) − F_n, in each
  /// component the part prescribes (DirichletDofs::components), in increasing order. A
  /// dof on several parts counts for the first of them that prescribes it.
  std::vector<double> reaction;
  double seconds_sources = 0, seconds_damage = 0, seconds_contact = 0, seconds_stress = 0;
  /// True when both solvers converged and all residuals are within tolerance.
  bool ok = true;
  /// Sub-steps taken (1, or more after step halving).
  int substeps = 1;
};

/// Everything a step changes, on this process: the state and the solvers' warm
/// starts. Restoring a snapshot makes the following steps bit-identical to a run
/// that never left it.
struct Snapshot {
  State state;
  Vector u_free;                     // owned free dofs
  Vector contact_warm, damage_warm;  // ContactSolver / DamageSolver::warm_state
};

/// What the step sizes carry from step to step (kept in checkpoints, so that a resumed
/// run takes the same steps as one that was never stopped).
struct StepControlState {
  double k_next = 0;       // error-controlled: the next step's size before landings (0: dt_initial)
  double sigma_scale = 0;  // max over the steps so far of |σ_n|_L2 (the estimate's scale)
  double n_active = 0, n_beta_zero = 0, n_beta_one = 0;  // the last step's sets (events)
  double rejected = 0;     // steps rejected over the run
  /// As values (checkpoints), and back; throws vpc::Error for a wrong count.
  Vector values() const;
  static StepControlState from_values(const Vector& v);
};

/// Where the setup time goes (seconds).
struct SetupTiming {
  double total = 0;
  double assembly = 0;  // K, M, A
  double factor_K = 0;  // factorization of K
  double factor_H = 0;  // the damage solver's setup (factor of M + kκA)
  double contact = 0;   // contact rows N and the contact solver's setup (S = N K⁻¹ Nᵀ)
};

/// Advances the scheme on this process's part of the mesh (scheme/mesh_part.hpp)
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

  const Problem& problem() const { return *problem_; }
  const MeshPart& part() const { return part_; }
  /// The part's mesh (the whole mesh on one process).
  const Mesh& mesh() const { return part_.mesh(); }
  const la::Comm& comm() const { return part_.comm; }
  const la::Backend& backend() const { return *backend_; }
  const SolverChoice& solvers() const { return choice_; }
  /// This process's state: u and β at the part's nodes (owned, then ghosts), σ, ε,
  /// z on its cells, λ for all contact rows.
  const State& state() const { return state_; }
  bool done() const {
    return problem_->step_control ? state_.t >= problem_->final_time : state_.n >= problem_->n_steps;
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

  Snapshot snapshot() const;
  /// The solvers' warm starts of snapshot(), without a copy of the state (checkpoints). Collective.
  Vector contact_warm_state() const;
  Vector damage_warm_state() const;
  /// Restores a snapshot of a run of the same problem and part; throws vpc::Error if the sizes differ.
  void restore(const Snapshot& s);

  const DofMap& dofs() const { return part_.dofs; }
  /// The constant matrices, for inspection (the Python module, docs/python.md): K over the
  /// free dofs (on one process a la::SparseOperator), the part's mass M and Laplacian A
  /// over its nodes, and the contact rows N (ContactConstraints::N: owned rows × owned free dofs).
  const la::SpdOperator& stiffness_operator() const { return *K_; }
  const SparseMatrix& mass_matrix() const { return M_local_; }
  const SparseMatrix& laplacian_matrix() const { return A_local_; }
  SparseMatrix contact_rows() const { return contact_matrix(true); }
  int n_factorizations() const;
  /// The damage matrices H = M + kκA made so far: one per step size, while at most
  /// four sizes are in use (the least recently used is dropped beyond that).
  int n_damage_matrices() const { return damage_matrices_made_; }
  /// The factor of K (for benchmarks: the cost of one solve; made here when the contact
  /// solver is the primal one, which factors K with its active rows instead).
  const la::Factor& stiffness_factor();
  /// One line on how the contact step solves (ContactSolver::describe) and why that solver.
  std::string contact_method() const { return contact_->describe() + "; " + contact_pick_.why; }
  /// The contact solver in use ("auto" resolved).
  std::string contact_solver() const { return contact_->name(); }
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
  void assemble_and_factorize();
  ContactConstraints contact_constraints() const;
  /// g(t) at this process's contact rows (the owned ones, in row order): the gap of the step ending at t.
  Vector contact_gap(double t) const;
  /// Steps 1–5 from the current state to time t_end with the step k, and the step's error estimate.
  StepReport advance(double k, double t_end);
  /// The same, halving on failure down to max_halvings levels.
  StepReport advance_or_halve(int level, double k, double t_end);
  /// An error-controlled step (Problem::step_control).
  StepReport controlled_step();
  /// Whether the step's sets changed in a way StepControl redoes with a smaller step.
  bool is_event(const StepReport& rep) const;
  /// The damage solver of H = M + kκA: kept for the step sizes in use (kDamageSolversKept,
  /// least recently used dropped); switching hands on the warm start. `H`: that matrix
  /// already assembled (set-up's), else it is assembled here when needed.
  DamageSolver& damage_solver(double k, std::unique_ptr<la::SpdOperator> H = nullptr);
  /// G and φ of step 1 at the current state, per cell: the next step's rates and the last one's estimate.
  void compute_rates();
  /// Per cell, ⟨ΔG, J ΔG⟩ with ΔG = G_n − G_{n−1} and J = ∂G/∂σ at the current state (a difference
  /// quotient of the law): how fast the law damps an error of z in the direction of the step's
  /// local error (the error estimate's μ). After compute_rates().
  std::vector<double> error_damping(const std::vector<SymTensor>& G_before) const;
  /// F_n of (3.3) without the Bᵀz term: the loads f0, f2 at time t (the part's full dofs).
  Vector load(double t) const;
  /// The contact area and the force on each obstacle, from λ of the step ending at t. Collective.
  void contact_totals(StepReport& rep) const;
  /// u_D(t) of SPEC §6 on the part's full dofs: the prescribed values, zero elsewhere;
  /// empty when no displacement is prescribed other than zero.
  Vector prescribed_displacement(double t) const;
  /// The reactions on the Dirichlet parts from σ_n and the load F_n (the part's full dofs). Collective.
  void reactions(StepReport& rep, const Vector& F) const;
  /// min β over all processes by minimum_at's rule, and max β.
  void beta_range(StepReport& rep) const;
  /// The backstop for an unstable explicit G (scheme/stability.hpp): after an accepted step,
  /// throws vpc::Error when ΔG_n = G_n − G_{n−1} flipped sign and grew in a row. Collective.
  void check_lagged_step(const StepReport& rep);

  std::shared_ptr<const Problem> problem_;
  MeshPart part_;
  std::shared_ptr<const la::Backend> backend_;
  SolverChoice choice_;
  std::vector<CellGeometry> geo_;
  std::vector<Material> materials_;  // Problem::material_list(), indexed by part_.cell_material
  const Material& material(int cell) const { return materials_[part_.cell_material[cell]]; }
  std::shared_ptr<la::SpdOperator> K_;  // shared with the contact solver
  std::unique_ptr<la::SpdOperator> M_;
  SparseMatrix M_local_, A_local_;      // the part's mass and Laplacian (H for halved steps)
  double K_local_nonzeros_ = 0;         // for model_bytes
  Vector basis_integral_cells_, basis_integral_traction_;  // ∫ψ_a over Ω and Γ2 (for uniform f0, f2)
  std::shared_ptr<la::Factor> K_factor_;  // of K; made on demand under the primal contact solver
  ContactSolverPick contact_pick_;
  /// A factor of K's kind (name "K"), its coordinates set for multigrid's rigid-body modes.
  std::shared_ptr<la::Factor> make_stiffness_factor(int block) const;
  int K_block_ = 1;
  /// N, one row per contact node of this process in part_.contact order: its owned nodes over
  /// the owned free dofs (ContactConstraints::N), or every node it knows, ghosts included, over
  /// its local free dofs (owned, then ghosts: the reflections of K_rot's local matrix).
  SparseMatrix contact_matrix(bool owned_only) const;
  std::unique_ptr<ContactSolver> contact_;
  struct DamageForStep {
    double k = 0;
    std::unique_ptr<DamageSolver> solver;
  };
  std::vector<DamageForStep> damage_;  // most recently used last
  DamageSolver* damage_current_ = nullptr;  // the last one used: holds the warm start
  int dropped_factorizations_ = 0;           // of damage solvers no longer kept
  int damage_matrices_made_ = 0;
  std::vector<SymTensor> rates_G_;           // G at the current state (valid: rates_valid_)
  std::vector<double> rates_phi_;            // φ at the current state
  bool rates_valid_ = false;
  /// The backstop's data: ΔG of the last accepted step and of the last attempt, |ΔG|² of the
  /// last accepted step, the last attempt's |ΔG|² and (ΔG, ΔG of the last accepted step) (L2),
  /// the accepted steps in a row in which ΔG flipped sign and grew, and its growth over them.
  std::vector<SymTensor> dG_last_, dG_attempt_;
  double dG2_last_ = 0, dG2_attempt_ = 0, dG_dot_attempt_ = 0;
  int growing_steps_ = 0;
  double growth_product_ = 1;
  std::optional<StepControl> control_;       // completed (defaults filled)
  StepControlState control_state_;
  std::vector<double> times_{0.0};           // t_0 … t_n
  double volume_ = 0;                        // |Ω|
  Vector lumped_mass_;                       // the row sums of M (owned nodes): the estimate's M_L
  la::Vector f_, phi_, u_, beta_;  // ghosted work vectors: the load, F_φ, u_free, β
  State state_;
  Vector u_free_;  // owned free dofs: the contact solver's warm start
  SetupTiming setup_timing_;
  std::optional<SolverCost> solver_cost_;
  double miss_gap_ = 0;  // the gap where no obstacle lies ahead (contact_miss_gap)
  std::vector<int> dirichlet_cells_;  // the part's cells with a prescribed dof: u_D's lifting, the reactions
};

}  // namespace vpc
