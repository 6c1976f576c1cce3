// Checkpoints in pieces (io/checkpoint.hpp) written on W ranks and resumed on others:
//   mpirun -np P vpcontact_mpi_checkpoint CASE --dir DIR --write W --resume R1,R2,... [--n N] [--steps S]
//                                              [--contact-solver NAME] [--damage-solver NAME] [--tolerance 1e-10]
// The first W ranks run the case to step S/2, writing checkpoints at step 1 and S/2, then on
// to the end (the uninterrupted run). Each piece file must hold about its share: no piece
// over 1.5 × total / W plus what piece 0 adds (λ, the contact warm state, the run's data).
// Then for each R (the first R ranks on the PETSc backend; 0: the serial engine on rank 0)
// a fresh stepper resumes from the checkpoint: its state, gathered on rank 0, must be the
// written state bit for bit (u, β, λ, σ, ε, z, friction's slip fields, u on the free dofs, both warm states); run
// to the end, it must agree with the uninterrupted run to the tolerance (u, β, λ, σ, ε, z): not bit
// for bit, as sums are taken in another order on another rank count, and the PETSc engine on
// several ranks does not repeat its last bits from run to run even on the same count. Last, with a piece of step S/2 damaged and then missing, a resume
// on all P ranks must take step 1 and say why. Prints PASSED only if all hold.
#include "../file_damage.hpp"
#include "petsc_main.hpp"
#include "cases/builtin_cases.hpp"
#include "io/checkpoint.hpp"
#include "la/petsc.hpp"
#include "parallel/distributed_mesh.hpp"
#include "scheme/time_stepper.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

int failures = 0;  // on rank 0

void check(bool ok, const std::string& what) {
  if (ok) return;
  ++failures;
  fmt::print("FAILED: {}\n", what);
  std::fflush(stdout);
}

/// The first `n` ranks of `world` (MPI_COMM_NULL on the others).
MPI_Comm first_ranks(MPI_Comm world, int n) {
  MPI_Comm sub;
  MPI_Comm_split(world, vpc::comm_rank(world) < n ? 0 : MPI_UNDEFINED, 0, &sub);
  return sub;
}

/// A stepper for `c` on `comm` (PETSc backend), or on one process (serial engine) for MPI_COMM_NULL.
std::unique_ptr<vpc::TimeStepper> make_stepper(const vpc::Case& c, MPI_Comm comm) {
  if (comm == MPI_COMM_NULL) return std::make_unique<vpc::TimeStepper>(c.problem, c.solvers);
  return std::make_unique<vpc::TimeStepper>(c.problem, vpc::distribute_mesh(comm, *c.problem),
                                            vpc::la::make_petsc_backend(vpc::la::make_mpi_comm(comm), {}), c.solvers);
}

std::vector<double> flat(const std::vector<vpc::SymTensor>& t) {
  std::vector<double> v;
  for (const auto& s : t) v.insert(v.end(), s.c.begin(), s.c.end());
  return v;
}

/// The largest difference between two gathered snapshots relative to each array's max norm
/// (0: bit for bit; 1e300 when sizes differ): the state, and with `warm` the solvers' warm
/// states (penalty–duality's multipliers converge only to its tolerance).
double difference(const vpc::Snapshot& a, const vpc::Snapshot& b, bool warm) {
  double worst = 0;
  auto compare = [&](const double* x, const double* y, std::size_t nx, std::size_t ny) {
    if (nx != ny) {
      worst = 1e300;
      return;
    }
    double diff = 0, norm = 1e-300;
    for (std::size_t i = 0; i < nx; ++i) {
      if (x[i] == y[i]) continue;
      diff = std::max(diff, std::abs(x[i] - y[i]));
    }
    for (std::size_t i = 0; i < ny; ++i) norm = std::max(norm, std::abs(y[i]));
    if (diff > 0) worst = std::max(worst, std::max(diff / norm, 1e-300));
  };
  auto vec = [&](const vpc::Vector& x, const vpc::Vector& y) {
    compare(x.data(), y.data(), static_cast<std::size_t>(x.size()), static_cast<std::size_t>(y.size()));
  };
  vec(a.state.u, b.state.u);
  vec(a.state.beta, b.state.beta);
  vec(a.state.lambda, b.state.lambda);
  vec(a.state.slip_step, b.state.slip_step);  // friction's (empty without)
  vec(a.state.slip, b.state.slip);
  vec(a.state.contact_status, b.state.contact_status);
  if (warm) {
    vec(a.u_free, b.u_free);
    vec(a.contact_warm, b.contact_warm);
    vec(a.damage_warm, b.damage_warm);
  }
  for (auto [x, y] : {std::pair{&a.state.sigma, &b.state.sigma}, std::pair{&a.state.eps, &b.state.eps},
                      std::pair{&a.state.z, &b.state.z}}) {
    const auto fx = flat(*x), fy = flat(*y);
    compare(fx.data(), fy.data(), fx.size(), fy.size());
  }
  if (a.state.n != b.state.n || a.state.t != b.state.t) worst = 1e300;
  return worst;
}

using vpc::test::flip_a_byte;

int run(int argc, char** argv) {
  const MPI_Comm world = PETSC_COMM_WORLD;
  const int rank = vpc::comm_rank(world), size = vpc::comm_size(world);
  vpc::require(argc >= 2, "usage: vpcontact_mpi_checkpoint CASE --dir DIR --write W --resume R1,R2,... [--n N] [--steps S]");
  vpc::CaseOverrides ov;
  vpc::MeshRequest mesh;
  int write = size;
  double tolerance = 1e-10;
  fs::path dir;
  std::vector<int> resume;
  std::optional<std::string> contact, damage;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--n") mesh.cells = std::stoi(value);
    else if (key == "--steps") ov.steps = std::stoi(value);
    else if (key == "--write") write = std::stoi(value);
    else if (key == "--dir") dir = value;
    else if (key == "--tolerance") tolerance = std::stod(value);
    else if (key == "--resume") {
      std::stringstream list(value);
      for (std::string r; std::getline(list, r, ',');) resume.push_back(std::stoi(r));
    } else if (key == "--contact-solver") contact = value;
    else if (key == "--damage-solver") damage = value;
    else vpc::fail("unknown option '{}'", key);
  }
  vpc::Case c = vpc::load_case(argv[1], ov, mesh);
  if (contact) c.solvers.contact = *contact;
  if (damage) c.solvers.damage = *damage;
  const int n_steps = c.problem->n_steps, middle = n_steps / 2;
  vpc::require(write >= 2 && write <= size && middle >= 2 && !dir.empty(), "--write {} on {} ranks, {} steps, --dir '{}'",
               write, size, n_steps, dir.string());
  if (rank == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  MPI_Barrier(world);

  // The run that writes: W ranks, checkpoints at steps 1 and S/2, then uninterrupted to the end.
  vpc::Snapshot written, final;  // gathered on rank 0
  MPI_Comm writers = first_ranks(world, write);
  if (writers != MPI_COMM_NULL) {
    auto a = make_stepper(c, writers);
    while (a->state().n < middle) {
      a->step();
      if (a->state().n == 1 || a->state().n == middle) vpc::write_checkpoint(*a, dir, c.problem->name, {}, {});
    }
    written = vpc::gather_snapshot(*a);
    while (!a->done()) a->step();
    final = vpc::gather_snapshot(*a);
    if (rank == 0) {
      std::vector<std::uintmax_t> sizes;
      std::uintmax_t total = 0;
      for (int r = 0; r < write; ++r) {
        const fs::path f = dir / (r == 0 ? fmt::format("checkpoint_{:05d}.bin", middle)
                                         : fmt::format("checkpoint_{:05d}.p{:04d}-of-{:04d}.bin", middle, r, write));
        sizes.push_back(fs::exists(f) ? fs::file_size(f) : 0);
        total += sizes.back();
      }
      // What piece 0 holds besides its blocks: λ and the contact warm state (8 B a row
      // each), the run's data and the table of pieces (a few hundred bytes).
      const double extra = 16.0 * a->part().n_contact + 1024, limit = 1.5 * static_cast<double>(total) / write + extra;
      fmt::print("{}: {} nodes, {} cells; checkpoint of step {} on {} ranks: pieces of {} bytes (total {}, "
                 "limit {:.0f} each)\n",
                 c.problem->name, a->part().n_global_nodes, a->part().n_global_cells, middle, write,
                 fmt::join(sizes, ", "), total, limit);
      for (int r = 0; r < write; ++r)
        check(sizes[r] > 0 && static_cast<double>(sizes[r]) <= limit,
              fmt::format("piece {} holds {} bytes of {} (limit {:.0f})", r, sizes[r], total, limit));
    }
    MPI_Comm_free(&writers);
  }
  MPI_Barrier(world);

  // Resumed on R ranks (0: the serial engine on rank 0).
  for (int r : resume) {
    MPI_Comm comm = first_ranks(world, std::max(r, 1));
    if (comm != MPI_COMM_NULL && (r > 0 || rank == 0)) {
      auto b = make_stepper(c, r > 0 ? comm : MPI_COMM_NULL);
      std::vector<std::string> skipped;
      const auto at = vpc::resume_from_checkpoint(*b, dir, &skipped);
      const vpc::Snapshot restored = vpc::gather_snapshot(*b);
      const std::string on = r > 0 ? fmt::format("{} rank{}", r, r > 1 ? "s" : "") : "the serial engine";
      if (rank == 0) {
        check(at && at->n == middle && skipped.empty(), fmt::format("resume on {}: the checkpoint of step {}", on, middle));
        const double d = difference(restored, written, true);
        check(d == 0, fmt::format("resume on {}: the restored state differs from the written one by {:.2e}", on, d));
      }
      while (!b->done()) b->step();
      const vpc::Snapshot ended = vpc::gather_snapshot(*b);
      if (rank == 0) {
        const double d = difference(ended, final, false);
        check(d <= tolerance, fmt::format("resume on {}: the last step differs from the uninterrupted run by {:.2e} "
                                          "(tolerance {:.0e})", on, d, tolerance));
        fmt::print("written on {} ranks, resumed on {}: restored bit for bit; the last step {} the uninterrupted run "
                   "(largest relative difference {:.1e})\n",
                   write, on, d == 0 ? "equals" : "agrees with", d);
      }
    }
    if (comm != MPI_COMM_NULL) MPI_Comm_free(&comm);
    MPI_Barrier(world);
  }

  // A damaged, then a missing piece of step S/2: every rank passes it over (whichever rank
  // checks that piece), and the resume takes step 1.
  const fs::path piece = dir / fmt::format("checkpoint_{:05d}.p{:04d}-of-{:04d}.bin", middle, write - 1, write);
  for (const std::string reason : {"checksum mismatch (damaged file)", "is missing"}) {
    if (rank == 0) {
      if (reason == "is missing") fs::remove(piece);
      else flip_a_byte(piece);
    }
    MPI_Barrier(world);
    auto b = make_stepper(c, world);
    std::vector<std::string> skipped;
    const auto at = vpc::resume_from_checkpoint(*b, dir, &skipped);
    if (rank == 0) {
      const bool said = skipped.size() == 1 && skipped[0].find(reason) != std::string::npos &&
                        skipped[0].find(fmt::format("checkpoint_{:05d}", middle)) != std::string::npos;
      check(at && at->n == 1 && said, fmt::format("a piece of step {} with '{}': resumed from step {} ({})", middle,
                                                  reason, at ? at->n : -1, skipped.empty() ? "" : skipped[0]));
      fmt::print("a piece of step {} on {} ranks: skipped ({}), resumed from step {}\n", middle, size,
                 skipped.empty() ? "" : skipped[0], at ? at->n : -1);
    }
  }
  const bool ok = vpc::allreduce_and(world, failures == 0);
  if (rank == 0) {
    fs::remove_all(dir);
    fmt::print("{}\n", ok ? "PASSED" : "FAILED");
  }
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return vpc::test::petsc_main(argc, argv, "vpcontact_mpi_checkpoint", run); }
