#pragma once
// Mesh adaptivity during a run (issue 51): the run's coarse mesh as a bisection forest
// (mesh/bisection.hpp), and each adaptation: the indicator of the state (adapt/indicator.hpp), bulk
// marking within the limits of [adapt] (adapt/adapt_spec.hpp), coarsening where it changes z, σ and β
// by less than its tolerance, the forest changed, the state carried over (adapt/state_transfer.hpp) and a
// TimeStepper of the same problem on the adapted mesh. The engine (run/stepper_engine.cpp) swaps the
// stepper; nothing below the scheme knows the mesh changed.
#include "adapt/adapt_spec.hpp"
#include "adapt/state_transfer.hpp"
#include "mesh/bisection.hpp"
#include "scheme/time_stepper.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace vpc {

/// One adaptation, as summary.json's "adaptations" and the run's progress report it.
struct AdaptationRecord {
  int step = 0;  // after this accepted step
  double t = 0;
  int pass = 0;  // 0; k ≥ 1: the k-th redo of the step (AdaptSpec::resolve)
  long long cells_before = 0, cells_after = 0, unknowns_before = 0, unknowns_after = 0;
  int marked = 0, bisected = 0, removed_nodes = 0;
  int max_level = 0;
  double min_angle_degrees = 0, h_min = 0;
  double stress_relative = 0;  // CellIndicators::stress_relative before it
  /// The relative L2 changes coarsening made (z and σ against ‖σ‖, β against |Ω|^½) and the change
  /// of ∫(1 − β) (absolute).
  double change_z = 0, change_sigma = 0, change_beta = 0, change_damage_integral = 0;
  bool truncated = false;  // marking cut to max_unknowns or max_level
  double seconds_adapt = 0, seconds_rebuild = 0;  // indicator, marking, forest, transfer; the new stepper
  double resident_bytes = 0;  // the process's resident memory once the new stepper is made
  /// What the new nodes' own data make of the carried state (TimeStepper::data_mismatch): the largest
  /// |u − u_D| on prescribed dofs and the largest penetration of an obstacle (lengths; the next step
  /// resolves them).
  double dirichlet_mismatch = 0, penetration = 0;
  /// The markings of the zone the forecast sees about to touch, each on the forest refined by the one
  /// before, until it reaches its final level (MeshAdaptivity::adapt); `marked` and `bisected` include them.
  int forecast_passes = 0;
  /// The new stepper's linear solver (cholmod, or the PETSc engine's: mumps, cg-gamg, cg-hypre): under
  /// --engine auto, planned for each adapted mesh (run/solver_plan.hpp).
  std::string linear_solver;
};

/// Makes the stepper of a problem on an adapted mesh (the engine's: one process's, or the PETSc engine's
/// on one rank).
/// When the forecast of surfaces about to touch looks (adapt/indicator.hpp): from the state at t, over
/// `steps` steps of the last step's size k (up to T); steps = 0: none (a redo pass solves the same step
/// again, the run has no next step, or nothing moves towards Γ3). Defined in mesh_adaptivity.cpp.
struct ApproachForecast;

using StepperMaker = std::function<std::unique_ptr<TimeStepper>(std::shared_ptr<const Problem>, const SolverChoice&)>;

class MeshAdaptivity {
 public:
  /// The adaptivity of runs of `coarse` (validated; its mesh the coarse mesh) with `spec`; new steppers
  /// take `choice` and are made by `make` (empty: one process's TimeStepper). Throws vpc::Error (located
  /// at spec.where) where the problem cannot be adapted.
  MeshAdaptivity(std::shared_ptr<const Problem> coarse, SolverChoice choice, AdaptSpec spec, StepperMaker make = {});

  const AdaptSpec& spec() const { return spec_; }
  /// Whether an adaptation is due after accepted step n.
  bool due(int n) const { return n > 0 && n % spec_.every == 0; }

  /// Adapts the mesh of `s` from its state (pass: AdaptationRecord::pass) and returns the stepper on
  /// the adapted mesh carrying `carry` (s's state, or for a redo the state before the step, on s's mesh)
  /// with the time levels `times` and step-size state `control`; null where nothing changes (nothing
  /// marked, or the stress estimate below AdaptSpec::tolerance). Once the state is carried, before the
  /// new stepper is made, `release` is called (where given): the caller frees `s` there (and `carry`,
  /// `control` with it), so that two steppers' factors are never held at once.
  std::unique_ptr<TimeStepper> adapt(const TimeStepper& s, int pass, const State& carry, std::vector<double> times,
                                     StepControlState control, const std::function<void()>& release = {});

  const std::vector<AdaptationRecord>& log() const { return log_; }
  const BisectionForest& forest() const { return forest_; }
  /// The refinement level of each cell of the stepper `s`'s mesh (its part's order).
  std::vector<int> levels(const TimeStepper& s) const;
  /// The combined indicator of the stepper `s`'s state per cell of its mesh (its part's order), computed on
  /// the leaf mesh as the marking does (VTU `indicator`).
  std::vector<double> indicator(const TimeStepper& s) const;
  /// Warnings for the run to print once (a limit that cut marking); taken.
  std::vector<std::string> take_warnings() { return std::move(warnings_); }

  // Checkpoints (a resume across adaptations): the forest's changes are kept in order, so that the
  // coarse mesh replays them into the same leaves, numbered alike.
  /// The history as text (JSON: each adaptation's coarsened patches and refined cells, the log).
  std::string history() const;
  /// Replays `history` (history()'s text) on this adaptivity, which has not adapted yet. Throws
  /// vpc::Error for a malformed history (naming what is wrong).
  void replay(const std::string& history);
  /// The stepper of the current leaf mesh (the engine's maker): where a replay leaves the run.
  std::unique_ptr<TimeStepper> make_stepper() const;

 private:
  /// Truncates `refine` (in its order) to the most cells whose refinement keeps d × nodes within
  /// max_unknowns (warned once, rec.truncated); false where it cut.
  bool within_max_unknowns(std::vector<int>& refine, AdaptationRecord& rec);
  /// The zone the forecast sees about to touch (adapt/indicator.hpp facets_about_to_touch) to its final
  /// level: its cells refined on the forest and `fs` carried, again while one is coarser than the deepest
  /// cell in contact (max_level before any contact): several markings, one new stepper. Each marking is one
  /// of changes_.
  void refine_forecast_zone(ForestState& fs, const ApproachForecast& forecast, AdaptationRecord& rec);

  std::shared_ptr<const Problem> coarse_;
  SolverChoice choice_;
  StepperMaker make_;
  AdaptSpec spec_;
  BisectionForest forest_;
  std::vector<AdaptationRecord> log_;
  /// The forest's changes, in order: each adaptation's coarsening (its patches) then refinement (its cells).
  struct Change {
    std::vector<BisectionForest::Patch> coarsened;
    std::vector<int> refined;
  };
  std::vector<Change> changes_;
  std::vector<std::string> warnings_;
  bool warned_unknowns_ = false, warned_level_ = false;
};

/// Refuses (vpc::Error at spec.where) a problem whose mesh cannot be adapted yet: not 2D, several
/// bodies or contact pairs, a block of a distributed mesh.
void check_adaptable(const Problem& p, const AdaptSpec& spec);

/// The problem `coarse` on the mesh `mesh` (its parts, regions and every datum as they are).
std::shared_ptr<const Problem> problem_on_mesh(const Problem& coarse, Mesh mesh);

}  // namespace vpc
