#pragma once
// Checkpoints: the whole state of a run at step n, so that `vpcontact run CASE
// --resume OUTDIR` continues bit-identically after an interruption.
//
// Format (docs/reliability.md), little-endian, each file written atomically:
//   8 bytes  magic "VPCCKPT\0"
//   u32      format version: 6 (the whole state in one file) or 7 (one piece of several)
//   u32      λ's numbers per contact node (State::contact_block) where above 1, else 0
//            (reserved before: every earlier file reads as 1)
//   u64      payload size in bytes
//   u64      FNV-1a 64 checksum of the payload
//   payload: case name (u64 length + bytes); u64 problem fingerprint; the problem key it is
//              made of (string: problem_key);
//            the case's keys (Case::keys: u64 count, then string key + string value each; none
//              in pieces 1 … P − 1); i64 n; f64 t;
//            the time grid: f64 T, i64 N: with N > 0 the time levels t_0 … t_n are those of
//              the uniform grid t_i = i T / N (Problem::time_at) and their array is empty
//              (0: the levels are stored: a non-uniform or error-controlled grid);
//            version 7 only: u64 P (pieces), u64 r (this piece), u64 ×4: its blocks
//              [node_begin, node_end) and [cell_begin, cell_end) of the numbering of the mesh as read;
//            arrays (u64 count + f64 values): u, β, λ (contact_block per contact node), u_free,
//              σ, ε, z (6 per cell) (the state's stored fields, io/state_fields.hpp),
//              contact and damage solver warm states, the time levels t_0 … t_n (or none, as
//              above), the step-size state (StepControlState) (version 7: the node and cell
//              arrays restricted to the piece's blocks; λ, the contact warm state, the times
//              and the step-size state in piece 0 only);
//            with friction only (contact block > 1): the arrays of the slip increment (block − 1
//              per contact node), the accumulated slip and the status (1 each) (piece 0 only);
//            version 6 and piece 0: PVD entries (u64 count, then f64 time + string file each),
//              run totals (f64 ×7, i64 ×2, u8 all_ok, i64; with friction f64 ×4 more: the
//              friction residuals' maxima and the dissipation), the changes on resume (u64
//              count, then i64 step + strings key, value before, value after each);
//            piece 0 of version 7: u64 payload size and u64 checksum of each of pieces 1 … P − 1.
// Versions 4 and 5 (earlier programs) are versions 6 and 7 without the case's keys, the time
// grid (their levels are always stored) and the changes on resume: read_checkpoint reads
// them, a resume refuses them (their case cannot be compared with this one).
// One process writes checkpoint_NNNNN.bin in version 6, the whole state in one file. P
// processes write P pieces, each its own contiguous blocks of the node and cell arrays
// (la::BlockSplit, PETSc's split): checkpoint_NNNNN.bin (piece 0) and
// checkpoint_NNNNN.pRRRR-of-PPPP.bin, so no process holds more than its share of the
// state. Piece 0 is renamed into place last and lists the others' sizes and checksums:
// a checkpoint is good when its piece 0 and every piece it lists are there and match
// (magic, version, size, checksum, fingerprint, step, blocks); resume takes the newest
// good one. Each process of any count, on any backend, reads only the parts of the
// pieces that overlap its block of the new split, and one exchange hands the values
// to the processes that own (or ghost) those nodes and cells.
#include "io/case.hpp"
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

/// A uniform grid t_i = i T / N (T exactly at i = N: Problem::time_at), which a checkpoint
/// stores instead of its time levels t_0 … t_n when they are this grid's: its size then does
/// not grow with the steps.
struct UniformGrid {
  double final_time = 0;
  std::int64_t steps = 0;  // N; 0: no grid (the levels are stored)
  /// t_0 … t_n of the grid.
  std::vector<double> levels(std::int64_t n) const;
  /// The grid of `p` when it is uniform and `times` (t_0 … t_n) are its levels; else none.
  static UniformGrid of(const Problem& p, const std::vector<double>& times);
};

struct Checkpoint {
  std::string case_name;
  std::uint64_t fingerprint = 0;
  std::string problem_key;
  CaseKeys case_keys;  // the case it was written for (none in versions 4 and 5)
  Snapshot snapshot;
  std::vector<double> times;  // t_0 … t_n
  UniformGrid grid;           // steps > 0: `times` are its levels and the file stores the grid
  Vector step_control;        // StepControlState::values()
  std::vector<std::pair<double, std::string>> pvd;
  RunTotals totals;
};

/// What identifies the discrete problem, as named fields "case=…|nodes=…|kappa=…|…" (global
/// sizes, κ, the laws' descriptions): a checkpoint only resumes the problem it was written
/// for, on any process count. T and the steps are not in it: a resume checks the time levels
/// up to the checkpoint (checkpoint_fits), so that a run can be continued to a later T or
/// with other steps after the checkpoint.
std::string problem_key(const TimeStepper& stepper);
/// The FNV-1a hash of problem_key.
std::uint64_t problem_fingerprint(const TimeStepper& stepper);
/// The fields in which two problem keys differ: "kappa = 0.1 in the checkpoint, 0.2 in this case; …".
std::string problem_key_difference(const std::string& saved, const std::string& now);

/// Whether a key of the case may change when a run is resumed (docs/cases.md, "Continuing a
/// run"; the one list): T and the steps ([time]: the steps up to the checkpoint are checked
/// apart, time_levels_difference), the output's settings ([output], but its probes, which are
/// probes.csv's columns), the solvers' ([solver]) and the case's description. Any other
/// change (the mesh, the laws and their parameters, the boundary conditions, the loads, the
/// contact and friction data, …) makes another problem, which the checkpoint's state does
/// not belong to.
bool may_change_on_resume(std::string_view key);
/// The keys whose values differ between a checkpoint's case and this one, in key order (the
/// value "" where a case does not give the key; step 0).
std::vector<ResumeChange> case_changes(const CaseKeys& checkpoint, const CaseKeys& now);
/// "key: before → after" (values made printable; "(not given)" for "").
std::string describe_change(const ResumeChange& c);
/// Why a checkpoint at step n with time levels `times` (t_0 … t_n) cannot be continued by
/// `problem`: its T ends before t_n, or its fixed grid differs at a step ≤ n (the step and
/// both times); empty when it can.
std::string time_levels_difference(const Problem& problem, const std::vector<double>& times);

/// The stepper's state and warm starts gathered to rank 0 in the numbering of
/// the mesh as read (on one process: its snapshot()); other processes get an
/// empty snapshot. Collective. For comparisons of small runs: rank 0 holds it all.
Snapshot gather_snapshot(const TimeStepper& stepper);

/// Writes the stepper's checkpoint with the output's PVD entries and run totals
/// (rank 0's) and keeps the newest `keep`: on one process the version-6 file, on P
/// one piece per process. `pieces` > 1 on one process writes that many pieces, as
/// that many processes would (tests). The time levels are stored as their grid where they
/// are the problem's uniform grid's (UniformGrid::of). Collective.
/// `keys`: the case's (Case::keys with the solvers' settings), which a resume compares.
void write_checkpoint(const TimeStepper& stepper, const std::filesystem::path& dir, const std::string& case_name,
                      const std::vector<std::pair<double, std::string>>& pvd, const RunTotals& totals,
                      int pieces = 0, int keep = 2, const CaseKeys& keys = {});

/// Where a resumed run continues: step, time (on every process), the PVD entries
/// and the run totals of the checkpoint, with this resume's changes of the case appended, and
/// those changes (on rank 0; empty elsewhere).
struct ResumePoint {
  int n = 0;
  double t = 0;
  std::vector<std::pair<double, std::string>> pvd;
  RunTotals totals;
  std::vector<ResumeChange> changed;
};

/// Finds the newest good checkpoint for this problem in `dir` (`skipped`, on rank 0:
/// the checkpoints passed over and why; each process checks the checksums of some of
/// the pieces) and every process restores its part of it, reading only the pieces'
/// entries of its block; nullopt on every process when there is none. The newest
/// checkpoint whose first file is intact must have been written for the case `keys`
/// (Case::keys), but for the keys that may change on resume: otherwise, or when it is of
/// a format that did not record its case (4, 5), throws vpc::CollectiveError naming each
/// key that differs, its value in the checkpoint and now. Collective.
std::optional<ResumePoint> resume_from_checkpoint(TimeStepper& stepper, const std::filesystem::path& dir,
                                                  std::vector<std::string>* skipped = nullptr,
                                                  const CaseKeys& keys = {});

/// Writes the whole state `c` as OUTDIR/checkpoint_NNNNN.bin (version 6) atomically
/// and keeps only the newest `keep` checkpoints; removes those of later steps
/// (damaged, or of a timeline this run replaced) and pieces of step n left from an
/// earlier write.
std::filesystem::path write_checkpoint(const std::filesystem::path& dir, const Checkpoint& c, int keep = 2);
/// Writes `c` whole (version 6) as the file `path`, atomically, nothing else touched: a state kept beside a
/// checkpoint (an adaptive run's undo, run/stepper_engine.cpp), read back by read_checkpoint.
void write_state_file(const std::filesystem::path& path, const Checkpoint& c);

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

/// Reads a whole checkpoint (checkpoint_NNNNN.bin and, in pieces, every piece it
/// lists) into one process's memory; throws vpc::Error naming the file and what is
/// wrong. For tools and tests: a resume reads only its blocks.
Checkpoint read_checkpoint(const std::filesystem::path& file);

/// The newest good checkpoint in `dir` for this fingerprint (older ones are
/// tried when the newest is damaged), read whole; nullopt if there is none.
/// `skipped` receives one line per checkpoint passed over, saying why.
std::optional<Checkpoint> find_checkpoint(const std::filesystem::path& dir, std::uint64_t fingerprint,
                                          std::vector<std::string>* skipped = nullptr);

}  // namespace vpc
