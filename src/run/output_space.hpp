#pragma once
// What a run's output will take on disk, estimated before it writes (at `check` and when a run
// starts or resumes), against the free space of its directory: history.csv and probes.csv grow
// by a row a step and the VTU files by one per output step, so a run of 10^8 steps would fill a
// disk hours into the run (issue 48). The estimate is refused when it does not fit.
//   const OutputEstimate e = estimate_output(stepper, case.output, 0);
//   require_output_space(e, free_space(dir), dir);   // throws vpc::Error naming what to change
#include "io/run_output.hpp"
#include "scheme/time_stepper.hpp"

#include <filesystem>
#include <string>

namespace vpc {

/// Bytes a run will write from a step to its end (an estimate from the sizes: the columns, the
/// probes, the mesh and the fields, the steps and output steps; each exact number of a CSV row at
/// a usual 17-digit length, zlib-compressed VTU data at 60 % of its size; it errs high: 1.0 MB for
/// 0.61 MB written by the 1000 steps of tests/data/reported/resume_changed_law.toml).
struct OutputEstimate {
  long long steps = 0;         // the steps counted (N, or from the checkpoint's to N)
  bool steps_estimated = false;  // error-controlled steps: N from T / dt_initial
  double history_row = 0;      // bytes of a history.csv row
  double history = 0, probes = 0, vtu = 0, checkpoints = 0;
  long long vtu_files = 0;
  double total() const { return history + probes + vtu + checkpoints; }
  /// "about 36.2 GiB (history.csv 34 GiB: 1e+08 steps of 340 B; probes.csv …; …)".
  std::string describe() const;
};

/// The output of the run of `stepper` with `options` from step `from` (0: a fresh run) to the
/// end. Only sizes known on every process (global counts): the same everywhere, no communication.
OutputEstimate estimate_output(const TimeStepper& stepper, const OutputOptions& options, int from);

/// The bytes that the file system holding `dir` (or, before it is made, its nearest existing
/// parent) has free for this user; infinity where the system does not say.
double free_space(const std::filesystem::path& dir);

/// Throws vpc::Error when `e` exceeds `available` bytes: the estimate, the free space of `dir`
/// and what to change. Returns a warning where it takes more than half of them, else "".
std::string require_output_space(const OutputEstimate& e, double available, const std::filesystem::path& dir);

}  // namespace vpc
