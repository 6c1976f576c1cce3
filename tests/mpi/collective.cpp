// la::collective / la::on_root (la/comm.hpp) on every rank: an error raised on one rank (here the
// last, or rank 0 only) becomes the same CollectiveError on every rank, with
// that rank's message; work that succeeds everywhere throws nothing.
#include "la/petsc.hpp"

#include <fmt/format.h>

#include <string>

namespace {

/// The message `work` makes every rank throw; "" if none.
template <typename F>
std::string caught(const vpc::la::Comm& comm, F&& work) {
  try {
    work(comm);
  } catch (const vpc::CollectiveError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  const vpc::la::Comm comm = vpc::la::make_mpi_comm(MPI_COMM_WORLD);
  const int rank = comm.rank(), size = comm.size();
  int failures = 0;
  auto expect = [&](const std::string& what, const std::string& got, const std::string& want) {
    if (got == want) return;
    fmt::print("FAILED on rank {}: {}: got '{}', want '{}'\n", rank, what, got, want);
    ++failures;
  };
  expect("no error", caught(comm, [](const vpc::la::Comm& c) { vpc::la::collective(c, [] {}); }), "");
  expect("the last rank fails",
         caught(comm, [&](const vpc::la::Comm& c) {
           vpc::la::collective(c, [&] { vpc::require(rank != size - 1, "rank {} cannot", rank); });
         }),
         fmt::format("rank {} cannot", size - 1));
  expect("every rank fails: the lowest rank's message",
         caught(comm, [&](const vpc::la::Comm& c) { vpc::la::collective(c, [&] { vpc::fail("rank {} cannot", rank); }); }),
         "rank 0 cannot");
  expect("on_root",
         caught(comm, [](const vpc::la::Comm& c) { vpc::la::on_root(c, [] { vpc::fail("only rank 0 saw it"); }); }),
         "only rank 0 saw it");
  const long long all = comm.sum(static_cast<long long>(failures));
  if (rank == 0 && all == 0) fmt::print("collective errors on {} ranks: PASSED\n", size);
  MPI_Finalize();
  return all == 0 ? 0 : 1;
}
