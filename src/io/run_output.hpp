#pragma once
// What a run writes into its output directory, on one process or many:
//   solution_NNNNN.vtu + solution.pvd  fields at output times (the table of the state's
//                                      fields, io/state_fields.hpp), zlib-compressed
//                                      by default (io/vtu_writer.hpp); on several
//                                      processes each writes its piece
//                                      solution_NNNNN_pRRRR.vtu (with a "rank" cell
//                                      field) and rank 0 the solution_NNNNN.pvtu
//                                      that the .pvd lists
//   history.csv                        one row per step: contact and damage solver
//                                      iterations and residuals, active set, β range
//                                      (the table of its columns, io/history_columns.hpp)
//   probes.csv                         u, σ, β at the probe points, every step
//   summary.json                       the run's data, final values and checks, and
//                                      what made it (version, commit, command line, date)
// The shared files (CSV, .pvd, .pvtu, summary.json) are written by rank 0.
#include "adapt/mesh_adaptivity.hpp"
#include "io/vtu_writer.hpp"
#include "scheme/sliding_pairs.hpp"
#include "scheme/time_stepper.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace vpc {

struct OutputOptions {
  std::filesystem::path directory;  // empty: output/<case name>
  int every = 10;              // VTU every this many steps (and at the final step); 0: final only
  std::vector<double> times;   // or: VTU at the steps nearest these times (replaces `every`)
  bool vtu = true;             // write VTU/PVD at all
  std::vector<std::string> fields;  // VTU fields to write; empty: all (field_names(): io/state_fields.hpp)
  std::vector<Point> probes;
  VtuEncoding encoding;             // [output] compression: zlib (default) or none
  // For summary.json: the program's command line (argv) and when the run started
  // (unset: when the output was set up).
  std::vector<std::string> command_line;
  std::chrono::system_clock::time_point started{};
  // [case] units: the units the case's numbers are in ("SI", "mm-N-MPa" or free text),
  // for the figures' labels only; the scheme never uses them.
  std::string units = "SI";

  /// The names accepted in `fields`.
  static const std::vector<std::string>& field_names();
  /// The field a name in `fields` stands for: the name itself, or the field an
  /// old name is kept for (damage: beta), or one of the contact laws' per-node state
  /// (`surface`, State::surface's names); empty when it names no field.
  static std::string field(const std::string& name, const std::vector<std::string>& surface = {});
};

/// A probe: the cell containing the point and the point's barycentric coordinates.
struct ProbeLocation {
  Point x;
  int cell = -1;
  std::array<double, 4> lambda{};
};
/// Locates x in the mesh; throws vpc::Error if no cell contains it.
ProbeLocation locate_point(const Mesh& mesh, const Point& x);

/// The stress components written to probes.csv, in order (indices of SymTensor):
/// Elasticity::stress_components (plane strain: 11, 22, 33, 12).
std::vector<int> tensor_components(const Elasticity& e);

// The CSV formats.
/// history.csv: the header line, and the row of one step (both end in a newline), from
/// the table of its columns (io/history_columns.hpp).
std::string history_header(const Problem& p, const MeshPart& part, bool adaptive = false);
std::string history_row(const StepReport& r);
/// probes.csv: the header line for `n_probes` probes in d dimensions.
std::string probes_header(const Elasticity& e, std::size_t n_probes);
/// For --resume: keeps the header and the rows whose first field (the step) is
/// ≤ n, drops a partly written last line; rewritten atomically.
void truncate_csv(const std::filesystem::path& path, int n);

/// A key of the case that a --resume changed (one that may change: io/checkpoint.hpp,
/// may_change_on_resume), at the step it continued from; values as Case::keys has them
/// ("" where the key is not given).
struct ResumeChange {
  long long step = 0;
  std::string key, before, after;
};

/// What the summary aggregates over the steps of a run (kept in checkpoints).
struct RunTotals {
  double max_contact_residual = 0, max_damage_residual = 0;
  int max_contact_iterations = 0, max_damage_iterations = 0;
  bool all_ok = true;
  /// Active contact nodes of the last step, as the contact solver counts them
  /// (penalty–duality: multipliers above its threshold); −1 before the first step.
  long long last_n_active = -1;
  /// Friction (0 without): the largest of each friction residual over the steps and the
  /// frictional dissipation summed over them.
  double max_friction_bound = 0, max_stick_slip = 0, max_slip_direction = 0, dissipation = 0;
  double seconds_sources = 0, seconds_damage = 0, seconds_contact = 0, seconds_stress = 0, seconds_output = 0;
  /// The keys each --resume of the run changed, in order (summary.json "changed_on_resume").
  std::vector<ResumeChange> resume_changes;
  void add(const StepReport& r);
};

/// The active contact nodes summary.json reports: the last step's count by the
/// solver's own rule, or (no step yet) the nodes whose normal force (normal_forces) is > 0.
long long active_contact_nodes(const RunTotals& totals, const Vector& normal_force);

/// What summary.json says about a run beyond the problem's data: global values,
/// gathered by RunOutput on rank 0.
struct RunSummary {
  int dimension = 0;
  long long nodes = 0, cells = 0, free_dofs = 0, contact_nodes = 0;
  double h_min = 0, h_max = 0;
  int steps = 0;  // the step reached
  double k_min = 0, k_max = 0;  // the smallest and largest step taken
  long long rejected = 0;       // error-controlled steps rejected
  double t = 0, total_contact_force = 0, max_von_mises = 0, beta_min = 0, beta_max = 0;
  long long active_contact_nodes = 0;
  /// Friction (a frictional run only: −1 without): the contact nodes that stick and slip
  /// after the last step (State::contact_status).
  long long n_stick = -1, n_slip = -1;
  Point beta_min_location{0, 0, 0};
  std::vector<Point> probes;
  RunTotals totals;
  double wall_seconds = 0;
  SetupTiming setup;
  /// Memory (summary.json "memory_bytes"): as each set-up stage ended (SetupTiming) and at the
  /// summary, the largest rank's resident and peak sizes; and each rank's peak at the summary.
  std::vector<std::pair<std::string, ProcessMemory>> memory;
  std::vector<long long> peak_per_rank;
  int factorizations = 0;
  long long linear_iterations = 0;  // TimeStepper::n_linear_iterations
  int ranks = 0;  // > 0: a run over MPI ("engine": "petsc", "ranks", "linear_solver")
  std::string linear_solver;
  std::string contact_solver;  // the one in use ("auto" resolved)
  std::vector<double> output_times;  // the times of the VTU files and the final time (obstacles' positions)
  struct SymmetryPlane {
    std::string part;
    int axis = 0;  // the plane x_axis = coordinate
    double coordinate = 0;
  };
  std::vector<SymmetryPlane> symmetry_planes;
  /// A run with mesh adaptivity ([adapt]): each adaptation (summary.json "adaptations").
  bool adaptive = false;
  std::vector<AdaptationRecord> adaptations;
  /// Per small-sliding contact pair: how far its slave nodes have slid from their t = 0 masters at
  /// the last step (scheme/sliding_pairs.hpp; summary.json "small_sliding").
  std::vector<PairSlide> pair_slides;
};

/// The text of summary.json (valid JSON whatever the names and paths hold).
std::string summary_json(const Problem& problem, const RunSummary& summary, const OutputOptions& options);

/// A time as ISO 8601 UTC, e.g. 2024-05-01T12:00:00Z.
std::string iso8601_utc(std::chrono::system_clock::time_point t);

/// Checks `options` and completes them for the case `case_name`: the default
/// directory, the fields by their current names (`surface`: the contact laws' per-node state's,
/// fields too), the start time. Throws vpc::Error.
void prepare_output_options(OutputOptions& options, const std::string& case_name,
                            const std::vector<std::string>& surface = {});

/// The one writer of a run's files, for every backend and process count. Every
/// member is collective (each process writes its piece; rank 0 the shared files).
class RunOutput {
 public:
  /// Locates the probes. The directory exists (begin_run, run/run_case.hpp made it).
  RunOutput(const TimeStepper& stepper, OutputOptions options);
  /// Writes the initial state (step 0).
  void start();
  /// Continues the files of an interrupted run from step `n` (the state of the
  /// stepper): history.csv and probes.csv keep their rows up to step n, the PVD
  /// collection its entries up to n (VTU files, pieces and .pvtu of later steps are
  /// removed). `pvd` and `totals` matter on rank 0 only.
  void resume(int n, std::vector<std::pair<double, std::string>> pvd, const RunTotals& totals);
  /// Records one accepted step; writes VTU at output steps.
  void record(const StepReport& report);
  /// On rank 0 (the others do not keep them).
  const RunTotals& totals() const { return totals_; }
  const std::vector<std::pair<double, std::string>>& pvd_entries() const { return pvd_; }
  /// Writes summary.json; `wall_seconds` is the whole run's time.
  void finish(double wall_seconds);

  const std::filesystem::path& directory() const { return options_.directory; }

  /// What an adaptive run ([adapt]) adds: cell fields for the VTU files (the level and the indicator),
  /// made when a file is written, and the adaptations' log for summary.json (kept by the caller), whose
  /// presence also adds history.csv's cells, unknowns and adaptations columns. Before start().
  struct Adaptation {
    std::function<std::vector<VtuField>()> cell_fields;
    const std::vector<AdaptationRecord>* log = nullptr;
  };
  void set_adaptation(Adaptation a) { adaptation_ = std::move(a); }
  /// The stepper now runs on another mesh (an adaptation; the same problem otherwise): later rows and
  /// files are of it, the probes located again. The old stepper may go after this.
  void remesh(const TimeStepper& stepper);

 private:
  struct Probe {
    ProbeLocation where;  // the point; its cell and coordinates where `mine`
    bool mine = false;    // this process owns the probe (the cell containing it best)
  };
  Probe locate_probe(const Point& x) const;
  bool root() const { return stepper_->comm().rank() == 0; }
  void record_untimed(const StepReport& report);
  void open_csv(bool append);
  void write_fields();
  void write_probe_row();
  bool is_output_step(int n, double t_n) const;
  void warn_small_sliding(const StepReport& report);
  RunSummary summary(double wall_seconds) const;

  const TimeStepper* stepper_;
  OutputOptions options_;
  Adaptation adaptation_;
  std::vector<Probe> probes_;
  std::ofstream history_, probe_csv_;  // rank 0
  std::vector<std::pair<double, std::string>> pvd_;
  RunTotals totals_;
  bool warned_small_sliding_ = false;  // once a run (warn_small_sliding)
};

}  // namespace vpc
