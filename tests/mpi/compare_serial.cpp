// The one TimeStepper on the PETSc backend (P ranks) against the serial backend, step by step:
//   mpirun -np P vpcontact_mpi_compare CASE [--n N] [--steps S] [--kappa K] [--linear mumps|cg-gamg|cg-hypre]
//                                           [--tolerance 1e-10] [--elasticity KIND] [--contact-solver NAME]
//                                           [--damage-solver NAME] [--halvings H] [--reduced reduced-factor]
//                                           [--max-cached-share S] [--residual-tolerance R] [--set KEY=VALUE]...
// The test-only contact laws (tests/support/test_laws.hpp) are registered, so that --set can name them.
// Every rank checks that its step reports are ok (contact and damage KKT residuals
// within the tolerance of SolverChoice) and equal on all ranks; rank 0 runs the
// serial stepper beside the distributed one and compares u, β, λ (contact forces)
// and σ after every step, relative to their max norms. Exit 0 only if all hold.
#include "petsc_main.hpp"
#include "test_laws.hpp"
#include "cases/builtin_cases.hpp"
#include "io/checkpoint.hpp"
#include "la/petsc.hpp"
#include "parallel/distributed_mesh.hpp"
#include "scheme/time_stepper.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace {

/// ‖a − b‖∞ / max(‖b‖∞, floor).
double rel_diff(const vpc::Vector& a, const vpc::Vector& b, double floor = 1e-300) {
  if (a.size() != b.size()) return 1e300;
  if (a.size() == 0) return 0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), floor);
}

/// Before contact, penalty–duality's λ is round-off about 0 (~1e-16): compared
/// relative to at least this force, far below the cases' contact forces (≥ 0.1).
constexpr double kForceFloor = 1e-6;

int run(int argc, char** argv) {
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const int rank = vpc::comm_rank(comm), size = vpc::comm_size(comm);
  vpc::require(argc >= 2, "usage: vpcontact_mpi_compare CASE [--n N] [--steps S] [--kappa K] [--linear KIND] [--elasticity KIND]");
  const std::string name = argv[1];
  vpc::test::register_test_laws();
  vpc::CaseOverrides ov;
  vpc::MeshRequest mesh;
  vpc::PetscSolverOptions linear;
  double tolerance = 1e-10;
  std::string elasticity;  // --elasticity KIND replaces the case's ℰ (same E, ν)
  // Solver choices beyond the case's (every one the serial backend takes, the PETSc backend takes too).
  std::optional<std::string> contact, damage, reduced;
  std::optional<int> halvings;
  std::optional<double> max_cached_share, residual_tolerance;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--n") mesh.cells = std::stoi(value);
    else if (key == "--steps") ov.steps = std::stoi(value);
    else if (key == "--kappa") ov.kappa = std::stod(value);
    else if (key == "--linear") linear.kind = value;
    else if (key == "--tolerance") tolerance = std::stod(value);
    else if (key == "--elasticity") elasticity = value;
    else if (key == "--contact-solver") contact = value;
    else if (key == "--damage-solver") damage = value;
    else if (key == "--halvings") halvings = std::stoi(value);
    else if (key == "--reduced") reduced = value;
    else if (key == "--max-cached-share") max_cached_share = std::stod(value);
    else if (key == "--residual-tolerance") residual_tolerance = std::stod(value);
    else if (key == "--set") ov.sets.push_back(value);
    else vpc::fail("unknown option '{}'", key);
  }
  vpc::Case c = vpc::load_case(name, ov, mesh);
  if (contact) c.solvers.contact = *contact;
  if (damage) c.solvers.damage = *damage;
  if (halvings) c.solvers.max_halvings = *halvings;
  if (max_cached_share) c.solvers.contact_options.max_cached_share = *max_cached_share;
  if (residual_tolerance) c.solvers.residual_tolerance = *residual_tolerance;
  if (reduced) {
    vpc::require(*reduced == "reduced-factor", "--reduced: expected reduced-factor, got '{}'", *reduced);
    c.solvers.damage_reduced = vpc::ReducedSolve::reduced_factor;
  }
  // E.g. plane strain for paper-2d: σ33 and z33 are carried by both engines.
  if (!elasticity.empty())
    c.problem->elasticity = vpc::Elasticity::from_name(elasticity, c.problem->elasticity.young(),
                                                       c.problem->elasticity.poisson());
  std::unique_ptr<vpc::TimeStepper> serial;
  if (rank == 0) serial = std::make_unique<vpc::TimeStepper>(c.problem, c.solvers);
  vpc::TimeStepper dist(c.problem, vpc::distribute_mesh(comm, *c.problem),
                        vpc::la::make_petsc_backend(vpc::la::make_mpi_comm(comm), linear), c.solvers);
  const auto& part = dist.part();
  if (rank == 0)
    fmt::print("{} on {} ranks ({} linear solver): {} nodes, {} cells, {} free dofs, {} contact nodes, {} steps\n",
               name, size, linear.kind, part.n_global_nodes, part.n_global_cells, part.n_global_dofs, part.n_contact,
               c.problem->n_steps);
  fmt::print("  rank {}: {} cells, {} owned + {} ghost nodes, {} owned dofs\n", rank, part.mesh().n_cells(),
             part.n_owned_nodes, part.n_local_nodes() - part.n_owned_nodes, part.n_owned_dofs);
  std::fflush(stdout);
  MPI_Barrier(comm);

  bool ok = true;
  double worst[4] = {0, 0, 0, 0};  // u, β, λ, σ
  double worst_surface = 0;        // the contact laws' per-node state
  int rank_failures = 0;
  while (!dist.done()) {
    const vpc::StepReport r = dist.step();
    // The checks of the step hold on this rank, and every rank has the same report.
    const double force_min = vpc::allreduce_min(comm, r.contact.total_force);
    const double force_max = vpc::allreduce_max(comm, r.contact.total_force);
    const bool same = force_min == force_max &&
                      vpc::allreduce_min(comm, r.damage.kkt_residual) == vpc::allreduce_max(comm, r.damage.kkt_residual);
    if (!r.ok || !same) {
      fmt::print("  rank {}: step {} FAILED the checks: ok = {}, same report on all ranks = {}, contact residual "
                 "{:.2e}, damage KKT residual {:.2e}\n",
                 rank, r.n, r.ok, same, r.contact.residuals.max(), r.damage.kkt_residual);
      ++rank_failures;
    }
    // u, β, σ on rank 0 in the numbering of the mesh as read (the checkpoints' gather).
    const vpc::Snapshot gathered = vpc::gather_snapshot(dist);
    const vpc::Vector &u = gathered.state.u, &beta = gathered.state.beta;
    vpc::Vector sigma(static_cast<Eigen::Index>(gathered.state.sigma.size()) * 6);
    for (size_t k = 0; k < gathered.state.sigma.size(); ++k)
      for (int j = 0; j < 6; ++j) sigma[static_cast<Eigen::Index>(k) * 6 + j] = gathered.state.sigma[k][j];
    if (rank == 0) {
      const vpc::StepReport rs = serial->step();
      const auto& st = serial->state();
      vpc::Vector sigma_serial(st.sigma.size() * 6);
      for (size_t k = 0; k < st.sigma.size(); ++k)
        for (int j = 0; j < 6; ++j) sigma_serial[k * 6 + j] = st.sigma[k][j];
      const double e[4] = {rel_diff(u, st.u), rel_diff(beta, st.beta), rel_diff(dist.state().lambda, st.lambda, kForceFloor),
                           rel_diff(sigma, sigma_serial)};
      for (int j = 0; j < 4; ++j) worst[j] = std::max(worst[j], e[j]);
      // The contact laws' per-node state (State::surface), replicated like λ: the same fields, values within the tolerance.
      bool surface = dist.state().surface.size() == st.surface.size();
      for (std::size_t f = 0; surface && f < st.surface.size(); ++f) {
        const double d = rel_diff(dist.state().surface[f].values, st.surface[f].values, kForceFloor);
        worst_surface = std::max(worst_surface, d);
        surface = dist.state().surface[f].name == st.surface[f].name && d <= tolerance;
      }
      if (!surface) fmt::print("  step {}: the per-node state differs from the serial run's\n", r.n);
      if (std::max({e[0], e[1], e[2], e[3]}) > tolerance || rs.contact.n_active != r.contact.n_active || !surface) {
        fmt::print("  step {}: differs from the serial run: u {:.2e}, beta {:.2e}, lambda {:.2e}, sigma {:.2e}; active "
                   "{} vs {}\n",
                   r.n, e[0], e[1], e[2], e[3], r.contact.n_active, rs.contact.n_active);
        ok = false;
      }
      if (r.n == c.problem->n_steps || r.n % 10 == 0)
        fmt::print("  step {:3d} t = {:.3f}: total force {:.12e} (serial {:.12e}), active {}, beta_min {:.12f} ({} nodes at beta = 1), "
                   "contact residual {:.1e}, damage KKT {:.1e}\n",
                   r.n, r.t, r.contact.total_force, rs.contact.total_force, r.contact.n_active, r.beta_min, r.damage.n_upper,
                   r.contact.residuals.max(), r.damage.kkt_residual);
    }
  }
  ok = vpc::allreduce_and(comm, ok && rank_failures == 0);
  if (rank == 0)
    fmt::print("{}: largest relative differences from the serial run over all steps: u {:.2e}, beta {:.2e}, "
               "lambda {:.2e}, sigma {:.2e}{} (tolerance {:.0e}); checks on every rank: {}\n{}\n",
               name, worst[0], worst[1], worst[2], worst[3],
               serial && !serial->state().surface.empty() ? fmt::format(", per-node state {:.2e}", worst_surface) : "",
               tolerance, rank_failures == 0 ? "ok" : "FAILED",
               ok ? "PASSED" : "FAILED");
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return vpc::test::petsc_main(argc, argv, "vpcontact_mpi_compare", run); }
