#include "scheme/discrete_system.hpp"

#include "core/error.hpp"
#include "core/stopwatch.hpp"
#include "fem/assembly.hpp"
#include "la/memory_estimate.hpp"
#include "problem/stability.hpp"
#include "scheme/step_data.hpp"
#include "scheme/surface_fields.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace vpc {

namespace {

using Clock = std::chrono::steady_clock;


/// K's dofs come in blocks of d per node unless some node has only some components
/// prescribed (a roller): then blocks of 1, and no rigid-body modes for multigrid. Collective.
int stiffness_block(const MeshPart& part) {
  const int d = part.mesh().dim();
  bool partial = false;
  for (std::size_t i = 0; i < part.dirichlet.size() && !partial; i += d) {
    const auto fixed = std::count_if(part.dirichlet.begin() + i, part.dirichlet.begin() + i + d, [](int k) { return k >= 0; });
    partial = fixed > 0 && fixed < d;
  }
  return part.comm.any(partial) ? 1 : d;
}

/// A of (3.8) and its factor κ: with one body A and Problem::kappa (as before bodies); with
/// several, Σ_c κ_c A_c (κ_c of the cell's body: no damage flux crosses a contact, SPEC §8) and 1.
SparseMatrix damage_laplacian(const Problem& p, const MeshPart& part, const std::vector<CellGeometry>& geo, double& kappa) {
  if (p.bodies.empty()) {
    kappa = p.kappa;
    return assemble_laplacian(part.mesh(), geo);
  }
  std::vector<double> weight(part.cell_body.size());
  for (std::size_t c = 0; c < weight.size(); ++c) weight[c] = p.kappa_of(part.cell_body[c]);
  kappa = 1;
  return assemble_laplacian(part.mesh(), geo, weight);
}

}  // namespace

DiscreteSystem::DiscreteSystem(std::shared_ptr<const Problem> problem_in, MeshPart part_in,
                               std::shared_ptr<const la::Backend> backend_in, const SolverChoice& choice)
    : problem(std::move(problem_in)), part(std::move(part_in)), backend(std::move(backend_in)) {
  const auto t0 = Clock::now();
  mesh_memory = process_memory();
  const Problem& p = *problem;
  const Mesh& mesh = part.mesh();
  const int d = mesh.dim();
  require(part.n_global_dofs > 0, "{}: every node is clamped; nothing to solve", p.name);
  geo = compute_geometry(mesh);
  materials = p.material_list();
  // Error-controlled steps stay within the explicit G's stable step (problem/stability.hpp).
  if (p.step_control) control = stable_step_control(p);
  first_step = control ? control->dt_initial : p.step_at(1);
  for (const CellGeometry& g : geo) volume += g.volume;
  volume = part.comm.sum(volume);

  // Loads uniform in space: (f(t), ψ_a e_i) = f_i(t) ∫ψ_a, with the same quadrature.
  const VectorField unit = [](const Point&, double) { return Point{1, 0, 0}; };
  auto basis_integral = [&](const VectorField& f0, const VectorField& f2) {
    const Vector F = assemble_load(mesh, geo, part.traction_facets, f0, f2, 0.0);
    return Vector(Eigen::Map<const Vector, 0, Eigen::InnerStride<>>(F.data(), mesh.n_nodes(), Eigen::InnerStride<>(d)));
  };
  if (p.f0 && p.f0_uniform) basis_integral_cells = basis_integral(unit, nullptr);
  if (p.f2 && p.f2_uniform) basis_integral_traction = basis_integral(nullptr, unit);

  contact = std::make_shared<const ContactSet>(p, part, std::exchange(part.contact, {}));
  for (int c = 0; c < mesh.n_cells() && !part.dirichlet_nodes.empty(); ++c)
    for (int a = 0; a <= d; ++a)
      if (std::ranges::any_of(part.dirichlet.begin() + mesh.cell(c)[a] * d,
                              part.dirichlet.begin() + (mesh.cell(c)[a] + 1) * d, [](int k) { return k >= 0; })) {
        dirichlet_cells.push_back(c);
        break;
      }

  // Constant matrices: K of (3.9), factorized once; H = M + kκA of (3.8). Each
  // process assembles its cells; the backend sums the parts.
  choice.stage("assembly");
  const auto t1 = Clock::now();
  K_block = stiffness_block(part);
  std::vector<Elasticity> elasticity;
  for (const Material& m : materials) elasticity.push_back(m.elasticity);
  K_local = assemble_stiffness(mesh, geo, elasticity, part.cell_material, part.dofs);
  K = backend->assemble(K_local, *part.dof_layout, K_block);
  K_local_nonzeros = static_cast<double>(K_local.nonZeros());
  if (!declared_surface_state(p.contact).empty()) K_diagonal = K->diagonal();
  M_local = assemble_mass(mesh, geo);
  A_local = damage_laplacian(p, part, geo, kappa);
  M = backend->assemble(M_local, *part.node_layout, 1);
  la::Vector lumped(part.node_layout);
  lumped.local() = M_local * Vector::Ones(M_local.cols());
  lumped.add_ghosts_to_owners();
  lumped_mass = lumped.owned();
  constant_damage = constant_damage_nodes(p, part, materials);
  const SparseMatrix H_local = M_local + (first_step * kappa) * A_local;
  H_first = backend->assemble(H_local, *part.node_layout, 1);
  H_first_local_nonzeros = static_cast<double>(H_local.nonZeros());
  assembly_seconds = seconds_since(t1);
  assembly_memory = process_memory();
  choice.stage("assembly", assembly_seconds);
  build_seconds = seconds_since(t0);
}

std::vector<char> constant_damage_nodes(const Problem& p, const MeshPart& part, const std::vector<Material>& materials) {
  const Mesh& mesh = part.mesh();
  const Vector beta0 = p.initial_damage(mesh, part.cell_body);
  const std::vector<int> node_body = node_bodies(mesh, part.cell_body);
  const int n_bodies = 1 + static_cast<int>(p.bodies.size());
  std::vector<char> constant(static_cast<std::size_t>(n_bodies), 1);
  for (int c = 0; c < mesh.n_cells(); ++c)
    if (!materials[part.cell_material[c]].source->vanishes()) constant[part.cell_body[c]] = 0;
  std::vector<double> lo(n_bodies, INFINITY), hi(n_bodies, -INFINITY);
  // Over the owned nodes (every node once over the ranks, each with a cell of its rank's: its body);
  // a ghost with no cell here (a spread pair row's master) would be taken for body 0's.
  for (int i = 0; i < part.n_owned_nodes; ++i) {
    lo[node_body[i]] = std::min(lo[node_body[i]], beta0[i]);
    hi[node_body[i]] = std::max(hi[node_body[i]], beta0[i]);
  }
  for (int b = 0; b < n_bodies; ++b)  // the same reductions, in the same order, on every rank
    constant[b] = part.comm.all(constant[b] != 0) && part.comm.min(lo[b]) == part.comm.max(hi[b]);
  std::vector<char> held(static_cast<std::size_t>(part.n_owned_nodes));
  for (int i = 0; i < part.n_owned_nodes; ++i) held[i] = constant[node_body[i]];
  return held;
}

std::shared_ptr<la::LinearSolver> DiscreteSystem::make_stiffness_factor() const {
  const Mesh& mesh = part.mesh();
  const int d = mesh.dim();
  std::shared_ptr<la::LinearSolver> factor = backend->factor("K");
  Vector coordinates(part.n_owned_dofs);  // GAMG's rigid-body modes
  std::vector<int> body(static_cast<std::size_t>(part.n_owned_dofs));  // its aggregates stay in one body
  const std::vector<int> node_body = node_bodies(mesh, part.cell_body);
  for (int i = 0; i < part.n_owned_nodes; ++i)
    for (int c = 0; c < d; ++c)
      if (const int k = part.dofs.free_index(part.dofs.full_index(i, c)); k >= 0) {
        coordinates[k] = mesh.node(i)[c];
        body[static_cast<std::size_t>(k)] = node_body[static_cast<std::size_t>(i)];
      }
  factor->set_coordinates(coordinates, K_block == d ? d : 0);
  factor->set_fields(body);
  return factor;
}

ContactConstraints contact_constraints(const DiscreteSystem& sys) {
  return sys.contact->constraints(*sys.problem, sys.part, checked_contact_gap(sys, 0.0));
}

double mesh_and_state_bytes(double nodes, double cell_entries, double cells) {
  return 24.0 * nodes + 4.0 * cell_entries + (sizeof(CellGeometry) + 3.0 * sizeof(SymTensor)) * cells;
}

std::optional<SolverCost> check_before_factorizing(const DiscreteSystem& sys, la::LinearSolver& K_factor,
                                                   const SolverChoice& choice, bool primal) {
  const Problem& p = *sys.problem;
  const Mesh& mesh = sys.part.mesh();
  const auto K_size = K_factor.analyze(*sys.K, "elastic stiffness K");
  if (!K_size) return std::nullopt;
  const auto H_size = sys.backend->factor("H")->analyze(*sys.H_first, "damage matrix H = M + k kappa A");
  const double mesh_bytes = mesh_and_state_bytes(mesh.n_nodes(), static_cast<double>(mesh.cell_array().size()),
                                                 mesh.n_cells());
  const double matrix_bytes = 12.0 * (sys.K_local_nonzeros + sys.M_local.nonZeros() + sys.A_local.nonZeros() +
                                      2.0 * sys.H_first_local_nonzeros);
  check_memory(estimate_run_memory(mesh_bytes, matrix_bytes, *K_size, H_size.value_or(FactorEstimate{}),
                                   choice.damage == "active-set",
                                   primal ? 0 : sys.part.n_contact * p.contact.block_size(mesh.dim())),
               memory_limit(choice.memory_limit), p.name);
  SolverCost cost = estimate_solver_cost(*K_size, static_cast<double>(sys.K->nonzeros()),
                                         sys.part.n_contact * p.contact.block_size(mesh.dim()),
                                         p.expected_steps(), !primal);
  return cost;
}

}  // namespace vpc
