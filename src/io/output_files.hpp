#pragma once
// The files a run owns in its output directory, in one place for the serial
// and the distributed run loops: the check that the directory is usable, made
// before any setup, and the clean-up of an earlier run's outputs and of stale
// temporary files (write_file_atomic's NAME.tmp.PID).
#include <filesystem>
#include <vector>

namespace vpc {

/// Creates `dir` if needed and checks that a file can be created in it; throws
/// vpc::Error naming the directory and the OS's reason.
void prepare_output_directory(const std::filesystem::path& dir);

/// Whether `name` (a file name) is one a run or `vpcontact plot` writes:
/// solution.pvd, solution_*.vtu (serial files and per-rank pieces),
/// solution_*.pvtu, history.csv, probes.csv, summary.json, checkpoint_*.bin.
bool is_run_output(const std::string& name);

/// Removes an earlier run's outputs from `dir` before a fresh run writes there
/// (stale solution_*.vtu would otherwise sit next to the new solution.pvd):
/// the files of is_run_output, the figures (figures/*.png|pdf|svg, and the
/// folder if it is then empty) and temporary files. Nothing else is touched.
/// Returns what was removed; throws vpc::Error (with the OS's reason) if a file
/// cannot be removed.
std::vector<std::filesystem::path> remove_run_outputs(const std::filesystem::path& dir);

/// Removes the temporary files NAME.tmp.PID left in `dir` by an interrupted
/// write; returns how many. Never throws (used at exit too).
int remove_temporary_files(const std::filesystem::path& dir);

}  // namespace vpc
