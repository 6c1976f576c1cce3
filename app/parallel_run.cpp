#include "parallel_run.hpp"

#include "core/mpi_start.hpp"
#include "parallel/petsc_engine.hpp"
#include "la/petsc.hpp"
#include "la/blas.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <thread>

namespace vpc {

namespace {

/// A barrier that sleeps: ranks waiting while rank 0 runs a case alone (SolverRequest::auto_route) would
/// otherwise spin in MPI's blocking calls, on a core rank 0's threads could use.
void wait_for_every_rank(MPI_Comm comm) {
  MPI_Request request;
  MPI_Ibarrier(comm, &request);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

}  // namespace

int parallel_run(const RunOptions& o, const EngineTask& task) {
  const auto before = std::chrono::steady_clock::now();
  if (PetscInitializeNoArguments() != 0) {
    fmt::print(stderr, "vpcontact: error: PETSc/MPI could not be initialized\n");
    return 2;
  }
  mpi_start_seconds() = std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();
  // One thread per rank (pure MPI) unless OMP_NUM_THREADS says otherwise; the
  // BLAS inside MUMPS likewise.
  if (!std::getenv("OMP_NUM_THREADS")) omp_set_num_threads(1);
  set_blas_threads(1);
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const int rank = comm_rank(comm), size = comm_size(comm);
  int rc = 0;
  catch_interrupts();
  try {
    la::collective(la::make_mpi_comm(comm), [&] {  // choices every rank rejects alike, before any set-up
      if (!o.linear_solver.empty()) la::check_linear_solver(o.linear_solver);
    });
    rc = task(petsc_engine(comm, o.linear_solver));
  } catch (const Interrupted& e) {  // every rank alike (the engine asks every rank)
    if (rank == 0) fmt::print(stderr, "\nvpcontact: {}\n", e.what());
    rc = 128 + e.signal;
  } catch (const CollectiveError& e) {
    if (rank == 0) fmt::print(stderr, "vpcontact: error: {}\n", e.what());
    rc = 1;
  } catch (const std::exception& e) {
    // One rank's failure must not leave the others waiting in a collective call.
    std::fflush(stdout);
    fmt::print(stderr, "vpcontact: error{}: {}\n", size > 1 ? fmt::format(" (rank {} of {})", rank, size) : "",
               e.what());
    std::fflush(stderr);
    if (size > 1) MPI_Abort(comm, 1);
    rc = 1;
  }
  wait_for_every_rank(comm);
  PetscFinalize();
  return rc;
}

int auto_run(const EngineTask& task) {
  bool started = false;
  struct Finalize {  // after the task, which has freed every PETSc object
    const bool& started;
    ~Finalize() {
      if (started) PetscFinalize();
    }
  } finalize{started};
  return task(auto_engine([&started] {
    if (!started) {
      require(PetscInitializeNoArguments() == 0, "PETSc/MPI could not be initialized");
      started = true;
      if (!std::getenv("OMP_NUM_THREADS")) omp_set_num_threads(1);  // as parallel_run
      set_blas_threads(1);
      catch_interrupts();
    }
    return PETSC_COMM_WORLD;
  }));
}

}  // namespace vpc
