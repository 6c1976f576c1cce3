#pragma once
// Checkpoints: the whole state of a run at step n, so that `vpcontact run CASE
// --resume OUTDIR` continues bit-identically after an interruption.
//
// Format (docs/reliability.md), little-endian, written atomically:
//   8 bytes  magic "VPCCKPT\0"
//   u32      format version (1)
//   u32      0 (reserved)
//   u64      payload size in bytes
//   u64      FNV-1a 64 checksum of the payload
//   payload: case name (u64 length + bytes); u64 problem fingerprint; i64 n; f64 t;
//            arrays (u64 count + f64 values): u, β, λ, u_free, σ, ε, z (6 per cell),
//            contact and damage solver warm states;
//            output: PVD entries (u64 count, then f64 time + string file each),
//            run totals (f64 ×7, i64 ×2, u8 all_ok).
// A file whose magic, version, size, checksum or fingerprint does not match is
// not a good checkpoint; resume takes the newest good one.
//
// The state is kept in the numbering of the mesh as read, gathered to rank 0 on
// any number of processes: a checkpoint written on P processes resumes on any
// other number, on any backend.
#include "io/run_output.hpp"
#include "scheme/time_stepper.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vpc {

struct Checkpoint {
  std::string case_name;
  std::uint64_t fingerprint = 0;
  Snapshot snapshot;
  std::vector<std::pair<double, std::string>> pvd;
  RunTotals totals;
};

/// A number identifying the discrete problem (global sizes, times, κ, names): a
/// checkpoint only resumes the problem it was written for, on any process count.
std::uint64_t problem_fingerprint(const TimeStepper& stepper);

/// The stepper's state and warm starts gathered to rank 0 in the numbering of
/// the mesh as read (on one process: its snapshot()); other processes get an
/// empty snapshot. Collective.
Snapshot gather_snapshot(const TimeStepper& stepper);

/// Writes the stepper's checkpoint (gather_snapshot) on rank 0, with the output's
/// PVD entries and run totals (rank 0's). Collective.
void write_checkpoint(const TimeStepper& stepper, const std::filesystem::path& dir, const std::string& case_name,
                      const std::vector<std::pair<double, std::string>>& pvd, const RunTotals& totals);

/// Where a resumed run continues: step, time (on every process), the PVD entries
/// and the run totals of the checkpoint (on rank 0; empty elsewhere).
struct ResumePoint {
  int n = 0;
  double t = 0;
  std::vector<std::pair<double, std::string>> pvd;
  RunTotals totals;
};

/// Rank 0 finds the newest good checkpoint for this problem in `dir` (`skipped`,
/// on rank 0: the files passed over and why) and every process restores its part
/// of it; nullopt on every process when there is none. Collective.
std::optional<ResumePoint> resume_from_checkpoint(TimeStepper& stepper, const std::filesystem::path& dir,
                                                  std::vector<std::string>* skipped = nullptr);

/// Writes OUTDIR/checkpoint_NNNNN.bin atomically and keeps only the newest `keep`;
/// removes those of later steps (damaged, or of a timeline this run replaced).
std::filesystem::path write_checkpoint(const std::filesystem::path& dir, const Checkpoint& c, int keep = 2);

/// When a run writes a checkpoint besides step 0 and its last step: every `every`
/// steps (0: never), or, with every < 0, after the first step that ends `seconds` of
/// wall time after the previous checkpoint (short runs then do not pay for writing
/// their whole state every step). Throws vpc::Error unless seconds > 0.
class CheckpointSchedule {
 public:
  CheckpointSchedule(int every, double seconds);
  /// Whether step n is due (by time: on this process's clock).
  bool due(int n) const;
  /// Whether due() depends on the clock (a distributed run takes rank 0's answer).
  bool by_time() const { return every_ < 0; }
  /// A checkpoint was just written.
  void written() { last_ = Clock::now(); }

 private:
  using Clock = std::chrono::steady_clock;
  int every_;
  double seconds_;
  Clock::time_point last_ = Clock::now();
};

/// Reads a checkpoint; throws vpc::Error naming the file and what is wrong.
Checkpoint read_checkpoint(const std::filesystem::path& file);

/// The newest good checkpoint in `dir` for this fingerprint (older ones are
/// tried when the newest is damaged); nullopt if there is none. `skipped`
/// receives one line per file passed over, saying why.
std::optional<Checkpoint> find_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint,
                                          std::vector<std::string>* skipped = nullptr);

}  // namespace vpc
