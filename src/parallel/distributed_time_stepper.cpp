#include "parallel/distributed_time_stepper.hpp"

#include "fem/assembly.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace vpc {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

PVec ghosted(MPI_Comm comm, PetscInt n_owned, PetscInt N, const std::vector<PetscInt>& ghosts) {
  PVec v;
  VPC_PETSC(VecCreateGhost(comm, n_owned, N, static_cast<PetscInt>(ghosts.size()), ghosts.data(), v.out()));
  VPC_PETSC(VecSet(v, 0.0));
  return v;
}

/// Writes the whole local form (owned, then ghost entries) of a ghosted vector
/// and adds the ghost entries into their owners: the global sum of the ranks'
/// local vectors.
void assemble_ghosted(Vec v, const Vector& local) {
  Vec lv = nullptr;
  VPC_PETSC(VecGhostGetLocalForm(v, &lv));
  PetscScalar* a = nullptr;
  VPC_PETSC(VecGetArray(lv, &a));
  std::copy(local.data(), local.data() + local.size(), a);
  VPC_PETSC(VecRestoreArray(lv, &a));
  VPC_PETSC(VecGhostRestoreLocalForm(v, &lv));
  VPC_PETSC(VecGhostUpdateBegin(v, ADD_VALUES, SCATTER_REVERSE));
  VPC_PETSC(VecGhostUpdateEnd(v, ADD_VALUES, SCATTER_REVERSE));
}

/// Copies the owners' values into the ghost entries.
void update_ghosts(Vec v) {
  VPC_PETSC(VecGhostUpdateBegin(v, INSERT_VALUES, SCATTER_FORWARD));
  VPC_PETSC(VecGhostUpdateEnd(v, INSERT_VALUES, SCATTER_FORWARD));
}

}  // namespace

Vector ghosted_local(Vec v) {
  Vec lv = nullptr;
  VPC_PETSC(VecGhostGetLocalForm(v, &lv));
  PetscInt n = 0;
  VPC_PETSC(VecGetSize(lv, &n));
  const PetscScalar* a = nullptr;
  VPC_PETSC(VecGetArrayRead(lv, &a));
  Vector out = Eigen::Map<const Vector>(a, n);
  VPC_PETSC(VecRestoreArrayRead(lv, &a));
  VPC_PETSC(VecGhostRestoreLocalForm(v, &lv));
  return out;
}

void require_petsc_engine_supports(const SolverChoice& choice) {
  auto serial_only = [](const std::string& option, const std::string& lacks) {
    return fmt::format("{}: serial-only for now (the PETSc engine {}); run it with --engine serial", option, lacks);
  };
  require(choice.contact == "active-set", "{}",
          serial_only("--contact-solver (solver.contact) " + choice.contact, "has the active-set contact solver only"));
  require(choice.damage == "active-set", "{}",
          serial_only("--damage-solver (solver.damage) " + choice.damage, "has the active-set damage solver only"));
  require(choice.max_halvings == 0, "{}",
          serial_only(fmt::format("--retry-halvings {}", choice.max_halvings), "does not retry failed steps"));
  require(choice.contact_options == ContactSolverOptions{}, "{}",
          serial_only("SolverChoice::contact_options other than the defaults (tolerance, max_iterations, omega, "
                      "max_cached_share)",
                      "does not take them"));
  require(choice.damage_reduced == ReducedSolve::automatic, "{}",
          serial_only("SolverChoice::damage_reduced other than automatic",
                      "has one reduced solve (a new factor; no capacitance method)"));
}

DistributedTimeStepper::DistributedTimeStepper(std::shared_ptr<const Problem> problem, DistributedMesh part,
                                               SolverChoice choice, PetscSolverOptions linear)
    : problem_(std::move(problem)), part_(std::move(part)), choice_(std::move(choice)) {
  const auto t0 = Clock::now();
  const Problem& p = *problem_;
  require_petsc_engine_supports(choice_);
  const MPI_Comm comm = part_.comm;
  comm_ = la::make_mpi_comm(comm);
  const Mesh& mesh = part_.mesh;
  const int d = mesh.dim();
  require(part_.n_global_dofs > 0, "{}: every node is clamped; nothing to solve", p.name);
  geo_ = compute_geometry(mesh);
  for (int f = 0; f < mesh.n_facets(); ++f) traction_facets_.push_back(f);

  auto stage = [&](const std::string& what, double seconds = -1) {  // as in TimeStepper
    if (choice_.on_setup_stage) choice_.on_setup_stage(what, seconds);
  };
  // Constant matrices: K of (3.9); M and H = M + kκA of (3.8); each rank adds its cells' part.
  stage("assembly");
  auto t1 = Clock::now();
  std::unique_ptr<la::PetscOperator> H;
  {
    const SparseMatrix K_local = assemble_stiffness(mesh, geo_, p.elasticity, part_.dofs);
    K_ = std::make_unique<la::PetscOperator>(comm_, K_local, part_.global_dof, part_.n_owned_dofs,
                                             part_.n_global_dofs, d);
    const SparseMatrix M_local = assemble_mass(mesh, geo_);
    const SparseMatrix A_local = assemble_laplacian(mesh, geo_);
    M_ = std::make_unique<la::PetscOperator>(comm_, M_local, part_.global_node, part_.n_owned_nodes,
                                             part_.n_global_nodes, 1);
    H = std::make_unique<la::PetscOperator>(comm_, SparseMatrix(M_local + (p.step() * p.kappa) * A_local),
                                            part_.global_node, part_.n_owned_nodes, part_.n_global_nodes, 1);
  }
  setup_timing_.assembly = seconds_since(t1);
  stage("assembly", setup_timing_.assembly);

  stage(fmt::format("factorization of K ({} global dofs, {})", part_.n_global_dofs, linear.kind));
  t1 = Clock::now();
  K_solver_ = std::make_unique<PetscLinearSolver>(comm, "vpc_K_", linear);
  {
    // Rigid-body modes (the near-null space of elasticity) for algebraic multigrid.
    PetscHandle<MatNullSpace, MatNullSpaceDestroy> rigid;
    if (linear.kind == "cg-gamg") {
      PVec xyz;
      VPC_PETSC(MatCreateVecs(K_->mat(), xyz.out(), nullptr));
      VPC_PETSC(VecSetBlockSize(xyz, d));
      PetscScalar* a = nullptr;
      VPC_PETSC(VecGetArray(xyz, &a));
      for (int i = 0; i < part_.n_owned_nodes; ++i)
        for (int c = 0; c < d; ++c) {
          const int k = part_.dofs.free_index(part_.dofs.full_index(i, c));
          if (k >= 0) a[k] = mesh.node(i)[c];
        }
      VPC_PETSC(VecRestoreArray(xyz, &a));
      VPC_PETSC(MatNullSpaceCreateRigidBody(xyz, rigid.out()));
    }
    K_solver_->factorize(K_->mat(), "elastic stiffness K", rigid.get());
  }
  setup_timing_.factor_K = seconds_since(t1);
  stage("factorization of K", setup_timing_.factor_K);
  stage(fmt::format("factorization of H ({} global nodes)", part_.n_global_nodes));
  t1 = Clock::now();
  damage_ = make_damage_solver("active-set", std::move(H), la::petsc_factor_factory(comm_, linear), choice_.damage_reduced);
  setup_timing_.factor_H = seconds_since(t1);
  stage("factorization of H", setup_timing_.factor_H);
  stage("contact set-up");
  t1 = Clock::now();
  contact_ = std::make_unique<DistributedContactSolver>(part_, K_->mat(), *K_solver_);
  setup_timing_.contact = seconds_since(t1);
  stage("contact set-up", setup_timing_.contact);

  // Initial state (3.4): u0 = 0, σ0 = 0 (so z0 = 0), β0 = the P1 interpolant (in [0, 1]:
  // Problem::validate, on the rank that read the case).
  state_.u = ghosted(comm, part_.n_owned_dofs, part_.n_global_dofs, part_.ghost_dofs());
  const auto nodes = std::make_shared<const la::Layout>(
      comm_, part_.n_owned_nodes, std::vector<long long>(part_.global_node.begin() + part_.n_owned_nodes, part_.global_node.end()),
      std::vector<long long>(part_.original_node.begin(), part_.original_node.begin() + part_.n_owned_nodes));
  state_.beta = la::Vector(nodes);
  fphi_ = la::Vector(nodes);
  VPC_PETSC(VecDuplicate(state_.u, F_.out()));
  Vector beta0(mesh.n_nodes());
  for (int i = 0; i < mesh.n_nodes(); ++i) beta0[i] = p.beta0 ? p.beta0(mesh.node(i), 0.0) : 1.0;
  state_.beta.local() = beta0;
  state_.sigma.assign(mesh.n_cells(), SymTensor{});
  state_.eps.assign(mesh.n_cells(), SymTensor{});
  state_.z.assign(mesh.n_cells(), SymTensor{});
  state_.lambda = Vector::Zero(part_.n_contact);
  setup_timing_.total = seconds_since(t0);
}

int DistributedTimeStepper::n_factorizations() const {
  return K_solver_->n_factorizations() + damage_->n_factorizations();
}

void DistributedTimeStepper::restore(int n, double t, const Vector& u_nodes, const Vector& beta_nodes,
                                     std::vector<SymTensor> sigma, std::vector<SymTensor> eps,
                                     std::vector<SymTensor> z, const Vector& lambda) {
  const int n_cells = part_.mesh.n_cells();
  require(u_nodes.size() == part_.dofs.n_full() && beta_nodes.size() == part_.n_local_nodes() &&
              static_cast<int>(sigma.size()) == n_cells && static_cast<int>(eps.size()) == n_cells &&
              static_cast<int>(z.size()) == n_cells && lambda.size() == part_.n_contact && n >= 0 &&
              n <= problem_->n_steps,
          "{}: the saved state does not fit this problem (a different mesh, case or step count?)", problem_->name);
  auto set_local_form = [](Vec v, const Vector& values) {
    Vec lv = nullptr;
    VPC_PETSC(VecGhostGetLocalForm(v, &lv));
    PetscScalar* a = nullptr;
    VPC_PETSC(VecGetArray(lv, &a));
    std::copy(values.data(), values.data() + values.size(), a);
    VPC_PETSC(VecRestoreArray(lv, &a));
    VPC_PETSC(VecGhostRestoreLocalForm(v, &lv));
  };
  set_local_form(state_.u, restrict_to_free(part_.dofs, u_nodes));
  state_.beta.local() = beta_nodes;
  state_.sigma = std::move(sigma);
  state_.eps = std::move(eps);
  state_.z = std::move(z);
  state_.lambda = lambda;
  state_.n = n;
  state_.t = t;
}

Vector DistributedTimeStepper::local_u() const { return extend_from_free(part_.dofs, ghosted_local(state_.u)); }

Vector DistributedTimeStepper::local_beta() const { return state_.beta.local(); }

MinimumAt DistributedTimeStepper::beta_minimum() const {
  const Vector beta = local_beta();
  const auto n = static_cast<std::size_t>(part_.n_owned_nodes);
  const MinimumAt mine = minimum_at({beta.data(), n}, {part_.original_node.data(), n});
  // MPI_MINLOC keeps the smaller index among equal values: minimum_at's rule.
  struct {
    double value;
    int index;
  } in{mine.value, mine.index}, out;
  if (mine.index < 0) in = {INFINITY, std::numeric_limits<int>::max()};  // a rank without owned nodes
  MPI_Allreduce(&in, &out, 1, MPI_DOUBLE_INT, MPI_MINLOC, part_.comm);
  return {out.value, out.index};
}

StepReport DistributedTimeStepper::step() {
  require(!done(), "{}: the run is already at the final time", problem_->name);
  const Problem& p = *problem_;
  const Mesh& mesh = part_.mesh;
  const MPI_Comm comm = part_.comm;
  const int n_cells = mesh.n_cells();
  const int n = state_.n + 1;
  const double k = p.step();
  StepReport rep;
  rep.n = n;
  rep.t = n == p.n_steps ? p.final_time : n * k;  // the grid time, exactly

  // Step 1: lagged sources G_{n−1}, φ_{n−1} on the owned cells, β at the centroid.
  auto t0 = Clock::now();
  const Vector beta_old = local_beta();
  std::vector<SymTensor> G(n_cells);
  std::vector<double> phi(n_cells);
  for (int c = 0; c < n_cells; ++c) {
    const PointState s{state_.sigma[c], state_.eps[c], cell_mean(mesh, beta_old, c), p.elasticity.stress_dim(),
                       mesh.cell_centroid(c), state_.t};
    G[c] = p.law->rate(s);
    p.elasticity.restrict_stress(G[c]);
    phi[c] = p.source->rate(s);
  }
  rep.seconds_sources = seconds_since(t0);

  // Step 2: damage (3.8): the box QP with H = M + kκA, r = M β_{n−1} + k F_φ.
  t0 = Clock::now();
  fphi_.local() = assemble_p0_source(mesh, geo_, phi);
  fphi_.add_ghosts_to_owners();
  Vector rhs, beta_n = state_.beta.owned();
  M_->mult(beta_n, rhs);
  rhs += k * fphi_.owned();
  rep.damage = damage_->solve(rhs, beta_n);
  state_.beta.owned() = beta_n;
  state_.beta.update_ghosts();
  rep.seconds_damage = seconds_since(t0);

  // Step 3: history (3.6): z_n = z_{n−1} + k G_{n−1}.
  for (int c = 0; c < n_cells; ++c) state_.z[c] += k * G[c];

  // Step 4: contact (3.9): K u_n = F_n − Bᵀz_n − Nᵀλ with Signorini conditions.
  t0 = Clock::now();
  const Vector F_local =
      restrict_to_free(part_.dofs, assemble_load(mesh, geo_, traction_facets_, p.f0, p.f2, rep.t) -
                                       assemble_stress_divergence(mesh, geo_, state_.z));
  assemble_ghosted(F_, F_local);
  rep.contact = contact_->solve(F_, state_.u, state_.lambda);
  update_ghosts(state_.u);
  rep.seconds_contact = seconds_since(t0);

  // Step 5: stress (3.6): σ_n = ℰε(u_n) + z_n on the owned cells.
  t0 = Clock::now();
  compute_strain(mesh, geo_, local_u(), state_.eps);
  double max_vm = 0;
  for (int c = 0; c < n_cells; ++c) {
    state_.sigma[c] = p.elasticity.apply(state_.eps[c]) + state_.z[c];
    max_vm = std::max(max_vm, state_.sigma[c].von_mises());
  }
  rep.max_von_mises = allreduce_max(comm, max_vm);
  rep.seconds_stress = seconds_since(t0);

  // β range over the owned nodes.
  const MinimumAt lo = beta_minimum();
  rep.beta_min = lo.value;
  rep.beta_min_node = lo.index;
  const Vector beta = local_beta();
  double hi = -1e300;
  for (int i = 0; i < part_.n_owned_nodes; ++i) hi = std::max(hi, beta[i]);
  rep.beta_max = allreduce_max(comm, hi);
  state_.t = rep.t;
  state_.n = n;

  PetscReal nu = 0;
  VPC_PETSC(VecNorm(state_.u, NORM_2, &nu));
  const double nb = comm_.sum(state_.beta.owned().squaredNorm());
  const double tol = choice_.residual_tolerance;
  rep.ok = rep.contact.converged && rep.damage.converged && rep.contact.residuals.max() <= tol &&
           rep.damage.kkt_residual <= tol && std::isfinite(nu) && std::isfinite(nb);
  return rep;
}

}  // namespace vpc
