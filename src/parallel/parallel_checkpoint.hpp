#pragma once
// Checkpoints of a distributed run in the serial format (io/checkpoint.hpp): the
// state is gathered to rank 0 in the numbering of the mesh as read, so a
// checkpoint written on P ranks resumes on any number of ranks, and in the
// serial engine; a serial run's checkpoint resumes on the PETSc engine too.
#include "io/checkpoint.hpp"
#include "parallel/distributed_time_stepper.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace vpc {

/// The fingerprint problem_fingerprint() gives the serial TimeStepper of the same problem.
std::uint64_t problem_fingerprint(const DistributedTimeStepper& stepper);

/// Gathers the state to rank 0, which writes OUTDIR/checkpoint_NNNNN.bin. Collective.
void write_checkpoint(const DistributedTimeStepper& stepper, const std::filesystem::path& dir,
                      const std::string& case_name, const std::vector<std::pair<double, std::string>>& pvd,
                      const RunTotals& totals);

/// Rank 0 finds the newest good checkpoint for this problem in `dir` and every
/// rank restores its part of it; returns the step, PVD entries and totals
/// (the same on every rank), or nullopt when there is none. Collective.
struct ResumePoint {
  int n = 0;
  double t = 0;
  std::vector<std::pair<double, std::string>> pvd;
  RunTotals totals;
};
std::optional<ResumePoint> resume_from_checkpoint(DistributedTimeStepper& stepper, const std::filesystem::path& dir,
                                                  std::vector<std::string>* skipped = nullptr);

}  // namespace vpc
