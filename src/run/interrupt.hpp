#pragma once
// SIGINT (Ctrl-C) and SIGTERM (a cluster's wall-time limit) during a run: the
// handler only records the signal; the run loop stops after the step under way,
// writes a checkpoint and prints the command that continues the run; the exit
// code is 128 + the signal (130, 143). A second signal ends the process at once
// (for a long factorization that cannot stop in between). During the set-up of a
// run on one process (SetUpStopsAtOnce), which has nothing to keep, the first
// signal ends the process at once, saying so: meshing or factorizing may take
// minutes.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vpc {

/// Installs the handlers (idempotent).
void catch_interrupts();

/// The signal received since catch_interrupts (SIGINT or SIGTERM), 0 if none.
int interrupt_signal();

/// "SIGINT" or "SIGTERM".
const char* signal_name(int signal);

/// Thrown where a run stops for a signal before its time steps (set-up);
/// main() reports it and exits with 128 + signal.
struct Interrupted : std::runtime_error {
  explicit Interrupted(int s);
  int signal;
};

/// Throws Interrupted if a signal has arrived.
void stop_if_interrupted();

/// A checkpoint exists (written or resumed from): what a second signal keeps.
void note_checkpoint();

/// While one exists, the first signal ends the process at once with "interrupted
/// by SIGINT during set-up; nothing was computed" and 128 + the signal. Not where
/// other processes would wait in a collective call (the PETSc engine).
class SetUpStopsAtOnce {
 public:
  SetUpStopsAtOnce();  // a signal already received is thrown (Interrupted)
  ~SetUpStopsAtOnce();
  SetUpStopsAtOnce(const SetUpStopsAtOnce&) = delete;
  SetUpStopsAtOnce& operator=(const SetUpStopsAtOnce&) = delete;
};

/// `s` quoted for a POSIX shell so that pasting it gives back exactly `s`:
/// unchanged when it holds only safe characters, else in single quotes ('\'' for ').
std::string shell_quote(std::string_view s);

/// The command line that continues the run in `dir`: this process's arguments
/// without any --resume/-o/--output, then `--resume DIR`; under mpirun (size >
/// 0) prefixed with `mpirun -np SIZE`. Every word quoted for a POSIX shell.
std::string resume_command(const std::vector<std::string>& argv, const std::filesystem::path& dir, int mpi_size = 0);

}  // namespace vpc
