// A distributed set-up builds each contact datum once (issue 49), from the case file to the
// steppers ready (set_up_petsc: the case read and checked, the solver plan, the parts cut and
// sent, each rank's assembly and contact solver):
//   mpirun -np P vpcontact_mpi_setup_builds CASE [--set key=value ...]
// The rank that holds the whole mesh (rank 0) builds the contact rows (contact_rows) and each
// pair's mortar coupling once, the other ranks none; where each rank builds its own block of a
// generated mesh (Problem::block) each builds its block's rows once. Every rank builds its part's
// contact matrix (contact_matrix) once.
#include "cases/builtin_cases.hpp"
#include "la/comm.hpp"
#include "mortar/mortar_coupling.hpp"
#include "parallel/petsc_engine.hpp"
#include "part/contact_matrix.hpp"
#include "petsc_main.hpp"
#include "problem/contact_rows.hpp"

#include <fmt/format.h>

#include <string>

namespace {

int run(int argc, char** argv) {
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const vpc::la::Comm c = vpc::la::make_mpi_comm(comm);
  vpc::require(argc >= 2, "usage: vpcontact_mpi_setup_builds CASE [--set key=value ...]");
  const std::string name = argv[1];
  vpc::CaseOverrides ov;
  for (int i = 2; i + 1 < argc; i += 2) {
    vpc::require(std::string(argv[i]) == "--set", "unknown option '{}'", argv[i]);
    ov.sets.push_back(argv[i + 1]);
  }
  bool block = false;
  std::size_t pairs = 0;
  const auto load = [&](const vpc::MeshRequest& mesh) {
    vpc::Case loaded = vpc::load_case(name, ov, mesh);
    block = loaded.problem->block != nullptr;
    pairs = loaded.problem->contact.pairs.size();
    return loaded;
  };
  vpc::RunOptions options;
  options.quiet = true;
  const long long rows = vpc::contact_rows_builds(), mortar = vpc::mortar::mortar_coupling_builds(),
                  matrix = vpc::contact_matrix_builds();
  const std::unique_ptr<vpc::Run> set_up = vpc::set_up_petsc(comm, load, options);
  const long long built[3] = {vpc::contact_rows_builds() - rows, vpc::mortar::mortar_coupling_builds() - mortar,
                              vpc::contact_matrix_builds() - matrix};
  const bool holds_rows = block || c.rank() == 0;  // whose mesh its rows come from
  const long long expected[3] = {holds_rows ? 1 : 0, holds_rows ? static_cast<long long>(pairs) : 0, 1};
  const char* what[3] = {"contact rows", "mortar couplings", "contact matrices"};
  int failures = 0;
  for (int k = 0; k < 3; ++k) {
    fmt::print("rank {}: {} {} built (expected {})\n", c.rank(), built[k], what[k], expected[k]);
    failures += built[k] != expected[k];
  }
  std::fflush(stdout);
  failures = static_cast<int>(c.sum(static_cast<double>(failures)));
  if (c.rank() == 0)
    fmt::print("{} on {} ranks{}: {}\n", name, c.size(), block ? " (blocks)" : "", failures ? "FAILED" : "PASSED");
  return failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) { return vpc::test::petsc_main(argc, argv, "vpcontact_mpi_setup_builds", run); }
