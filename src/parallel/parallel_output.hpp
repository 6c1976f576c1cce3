#pragma once
// What a distributed run writes, with the files and columns of RunOutput
// (io/run_output.hpp), so that ParaView and scripts/vpcontact_plot.py read both:
//   solution_NNNNN.pvtu + solution.pvd   fields at output times; each rank writes its
//     piece solution_NNNNN_pRRRR.vtu (its cells and their nodes, binary appended)
//     and rank 0 the .pvtu that lists them and the .pvd collection
//   history.csv, probes.csv, summary.json   written once, by rank 0
#include "io/run_output.hpp"
#include "parallel/distributed_time_stepper.hpp"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace vpc {

class ParallelOutput {
 public:
  /// Collective: every rank must construct it with the same options.
  ParallelOutput(const DistributedTimeStepper& stepper, OutputOptions options, std::string linear_solver);
  /// Writes the initial state (step 0). Collective.
  void start();
  /// Continues the files of an interrupted run from step n (history and probes
  /// keep their rows up to n; VTU files of later steps are removed). Collective.
  void resume(int n, std::vector<std::pair<double, std::string>> pvd, const RunTotals& totals);
  const std::vector<std::pair<double, std::string>>& pvd_entries() const { return pvd_; }
  const RunTotals& totals() const { return totals_; }
  /// Records one accepted step; writes the fields at output steps. Collective.
  void record(const StepReport& report);
  /// Writes summary.json; `wall_seconds`: the whole run's time. Collective.
  void finish(double wall_seconds);
  const std::filesystem::path& directory() const { return options_.directory; }

 private:
  struct Probe {
    Point x;
    bool mine = false;  // this rank owns the cell the probe lies in
    ProbeLocation where;
  };
  void write_fields();
  void write_probe_row();
  bool is_output_step(int n) const;
  bool wants(const std::string& field) const;

  const DistributedTimeStepper& stepper_;
  OutputOptions options_;
  std::string linear_solver_;
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  std::vector<Probe> probes_;
  std::ofstream history_, probe_csv_;
  std::vector<std::pair<double, std::string>> pvd_;
  RunTotals totals_;
};

}  // namespace vpc
