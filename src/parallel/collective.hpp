#pragma once
// Errors in collective work: an error raised on any rank becomes the same
// vpc::CollectiveError on every rank, so that no rank waits in a collective call
// for one that failed, and the program reports it once (core/error.hpp).
#include "core/error.hpp"

#include <mpi.h>

#include <exception>
#include <string>

namespace vpc {

/// Throws, on every rank, CollectiveError with the message of the lowest rank
/// whose `failed` is true; returns if none failed. Collective.
void throw_if_failed_anywhere(MPI_Comm comm, bool failed, std::string message);

/// Runs `work` on every rank; if it throws on any rank, every rank throws the
/// error of the lowest rank that failed. `work` itself must not wait for other
/// ranks (they may have failed before meeting it). Collective.
template <typename F>
void collective(MPI_Comm comm, F&& work) {
  bool failed = false;
  std::string message;
  try {
    work();
  } catch (const std::exception& e) {
    failed = true;
    message = e.what();
  }
  throw_if_failed_anywhere(comm, failed, std::move(message));
}

/// Runs `work` on rank 0 only; its error is then every rank's. Collective.
template <typename F>
void on_root(MPI_Comm comm, F&& work) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  collective(comm, [&] {
    if (rank == 0) work();
  });
}

}  // namespace vpc
