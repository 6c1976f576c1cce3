#pragma once
// Convergence studies of the fully discrete scheme (Theorem 3.5): a sequence of
// levels, each a run of the scheme on a red-refined mesh and/or with a halved time
// step, and the errors of each level in the norms of (3.39):
//   max_n |u_n − u_n*|_E   (energy norm (ℰε(·), ε(·))^{1/2}),  max_n |u_n − u_n*|_L2,
//   max_n |σ_n − σ_n*|_L2,  max_n |β_n − β_n*|_L2,  (k Σ_n |∇(β_n − β_n*)|²_L2)^{1/2},
// where * is the exact solution when there is one, else the finest run (the
// reference). The maximum and the sum run over the time levels t_n of the run being
// measured (n = 0..N; the reference's time grid contains them). Fields are compared
// on the finer mesh, where P1 and P0 fields of a coarser level are represented
// exactly (verification/refine.hpp).
//
// All runs advance together (in lockstep over the finest time grid), so no run is
// stored in time. Besides the errors against * the study records the differences of
// consecutive levels, |w_l − w_{l+1}| in the same norms: their ratios estimate the
// rate without the bias that a reference only one level finer introduces.
#include "problem/problem.hpp"
#include "scheme/time_stepper.hpp"
#include "verification/norms.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vpc {

/// Which discretization parameters are halved from level to level.
enum class RefinementSequence {
  HK,  // h and k together: mesh level l, N = N0 2^l
  H,   // h alone: mesh level l, N = N0 on every level
  K,   // k alone: the base mesh on every level, N = N0 2^l
};
std::string to_string(RefinementSequence s);
RefinementSequence refinement_sequence_from_name(const std::string& name);

/// Builds the problem on a given mesh with N time steps (the mesh is a red
/// refinement of the base mesh; everything else is the case's).
using ProblemFactory = std::function<std::shared_ptr<const Problem>(const Mesh& mesh, int n_steps)>;

/// A factory that copies `base` and replaces its mesh and number of steps. A base with a
/// non-uniform grid has each of its steps split into N / N_base equal steps (N must be
/// N_base 2^l), so that every level's grid contains the coarser ones; a base with
/// error-controlled steps becomes a uniform grid of N steps.
ProblemFactory same_data_on(std::shared_ptr<const Problem> base);

struct ConvergenceOptions {
  RefinementSequence sequence = RefinementSequence::HK;
  int levels = 4;              // measured levels 0 .. levels − 1
  int reference_offset = 1;    // without an exact solution: the reference is level levels − 1 + offset
  int base_steps = 0;          // N0 (required, >= 1)
  SolverChoice solvers;
  int quadrature_points = 0;   // per direction for errors against an exact solution; 0: 3 (d <= 2), 2 (d = 3)
  /// Progress lines (may be empty).
  std::function<void(const std::string&)> log;
  /// Makes each level's stepper; empty: one process, TimeStepper(problem, solvers). A
  /// distributed one (the PETSc engine: every process runs the study on the same meshes)
  /// has its state gathered to rank 0 at every step, where the norms are computed: the
  /// result is complete on rank 0 only.
  std::function<std::unique_ptr<TimeStepper>(std::shared_ptr<const Problem>, const SolverChoice&)> make_stepper;
  /// Error-controlled levels besides the fixed-grid ones: level l takes the tolerance
  /// tolerance / 2^l (sequences hk and k; h: the tolerance alone). Every run of the study
  /// is then compared at the times of the base grid (N0 steps) only, where the error
  /// control lands exactly, so that both kinds of levels are measured alike.
  std::optional<StepControl> step_control;
};

/// The errors of one level, in the norms of (3.39) (see the file comment).
struct ErrorNorms {
  double u_energy = 0, u_l2 = 0, sigma_l2 = 0, beta_l2 = 0, beta_grad = 0;
  /// max_n |Σλ − Σλ*|: the total contact force (NaN against an exact solution).
  double contact_force = 0;
  static const std::vector<std::string>& names();
  std::vector<double> values() const;
};

struct IterationStats {
  double mean = 0;
  int max = 0;
};

struct LevelResult {
  int level = 0;
  double h = 0, k = 0;  // largest cell diameter, time step
  int n_cells = 0, n_nodes = 0, n_free_dofs = 0, n_contact_nodes = 0, n_steps = 0;
  ErrorNorms error;       // against the exact solution or the reference
  ErrorNorms difference;  // against level + 1 (NaN on the last level with an exact solution)
  IterationStats contact_iterations, damage_iterations;
  int max_active_contact = 0;  // largest number of active contact nodes over the run
  int active_contact = 0;      // active contact nodes at T
  int beta_at_zero = 0, beta_at_one = 0;  // nodes with β = 0, β = 1 at T
  int contact_set_changes = 0; // steps where the number of active contact nodes changed
  int damage_set_changes = 0;  // steps where the number of nodes at β = 0 or at β = 1 changed
  int n_failed_steps = 0;      // steps not accepted (only counted in solver comparisons)
  double seconds = 0;          // time spent stepping this level
  double tolerance = 0;        // error-controlled levels: the step control's tolerance (k: the largest step)
  int n_rejected = 0;          // error-controlled levels: steps rejected and redone
};

struct ConvergenceResult {
  std::string case_name;
  RefinementSequence sequence = RefinementSequence::HK;
  bool exact = false;          // errors against an exact solution (else against the reference)
  LevelResult reference;       // the reference run (when !exact)
  std::vector<LevelResult> levels;
  std::vector<LevelResult> adaptive;  // error-controlled levels (ConvergenceOptions::step_control)
  bool at_base_times = false;  // errors over the base grid's times only (with error-controlled levels)
  double seconds = 0;

  /// Observed rate between level l − 1 and l of `of` (levels or adaptive):
  /// log(e_{l−1}/e_l) / log(p_{l−1}/p_l), p = h (HK, H), k (K) or the tolerance (K,
  /// error-controlled levels); NaN for l = 0. `values` picks the norm.
  double rate(int l, const std::function<double(const LevelResult&)>& value) const { return rate(levels, l, value); }
  double rate(const std::vector<LevelResult>& of, int l, const std::function<double(const LevelResult&)>& value) const;
};

/// Runs the study. `exact` may be null (then a reference run is made).
ConvergenceResult run_convergence(const std::string& case_name, const Mesh& base_mesh, const ProblemFactory& factory,
                                  std::shared_ptr<const ExactSolution> exact, const ConvergenceOptions& options);

/// The table printed by `vpcontact converge`: errors and observed rates.
std::string format_convergence_table(const ConvergenceResult& r);
/// CSV: one row per level with h, k, sizes, errors, rates, differences, iterations (`adaptive`:
/// of the error-controlled levels, whose k is the largest step taken and N the steps taken).
void write_convergence_csv(const ConvergenceResult& r, const std::string& path, bool adaptive = false);

// --- Solver agreement --------------------------------------------------------

struct SolverComparisonLevel {
  int level = 0;
  double h = 0, k = 0;
  int n_free_dofs = 0, n_contact_nodes = 0, n_nodes = 0, n_steps = 0;
  /// max_n |u_AS − u_PD|_E, |β_AS − β_PD|_L2, ‖λ_AS − λ_PD‖∞, each divided by the largest
  /// |u_AS|_E, |β_AS|_L2, ‖λ_AS‖∞ over the run.
  double diff_u = 0, diff_beta = 0, diff_lambda = 0;
  IterationStats contact_as, contact_pd, damage_as, damage_pd;
  int max_active_contact = 0;
  int failed_as = 0, failed_pd = 0;  // steps whose solver did not converge or whose residual exceeded the tolerance
  double seconds_as = 0, seconds_pd = 0;
};

/// Runs the active-set and the penalty–duality solvers (both inequalities) on mesh
/// levels 0 .. levels − 1 with the same N and compares the discrete solutions step
/// by step.
std::vector<SolverComparisonLevel> compare_solvers(const Mesh& base_mesh, const ProblemFactory& factory, int levels,
                                                   int n_steps, const SolverChoice& base,
                                                   const std::function<void(const std::string&)>& log = {});

std::string format_solver_table(const std::vector<SolverComparisonLevel>& r);
void write_solver_csv(const std::vector<SolverComparisonLevel>& r, const std::string& path);

}  // namespace vpc
