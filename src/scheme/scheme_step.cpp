#include "scheme/scheme_step.hpp"

#include "fem/assembly.hpp"
#include "scheme/contact_gap.hpp"
#include "scheme/surface_fields.hpp"

#include <chrono>
#include <utility>

namespace vpc {

namespace {

/// Runs work and adds its wall time to `seconds`.
template <class F>
void timed(double& seconds, F&& work) {
  const auto t0 = std::chrono::steady_clock::now();
  work();
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

StepTaken SchemeStep::take(const DiscreteSystem& sys, SchemeSolvers& solvers, const SolverChoice& choice, State& s,
                           Vector& u_free, double k, double t_end) {
  StepTaken out;
  StepReport& rep = out.report;
  rep.n = s.n + 1;
  rep.t = t_end;
  rep.k = k;
  out.beta_before = s.beta;
  // Step 1: the lagged sources G_{n−1}, φ_{n−1}.
  timed(rep.seconds_sources, [&] { out.lagged = take_rates(sys, s); });
  // Step 2, (3.8): β_n.
  timed(rep.seconds_damage, [&] { rep.damage = solve_damage(sys, solvers.damage, choice, s, out.lagged.phi, k); });
  // Step 3, (3.6): z_n.
  update_history(s, out.lagged.G, k);
  // Step 4, (3.9): u_n and λ_n, with the data of t_n.
  timed(rep.seconds_contact, [&] {
    out.data = step_data(sys, t_end);
    out.data.gap_shift = surface_gap_shift(sys, s);  // the laws' per-node state at t_{n−1} moves g
    if (out.data.gap_shift.size() > 0) out.data.gap += out.data.gap_shift;
    out.data.bond = surface_bond(sys, s, k);  // adhesion: α carried over the step from t_{n−1}
    const Vector u_before = s.surface.empty() ? Vector() : Vector(s.u);  // the surface laws' slip along prescribed dofs
    rep.contact = solve_contact(sys, *solvers.contact, s, u_free, out.data);
    rep.surface = update_surface_state(sys, out.data.gap, k, u_before, t_end, s);  // the laws' per-node state at t_n (s.u: u_n, ghosts current)
    record_gap_left(sys, out.data.gap_shift.size() > 0 ? Vector(out.data.gap - out.data.gap_shift) : out.data.gap, s);
  });
  // Step 5, (3.6): ε_n, σ_n.
  timed(rep.seconds_stress, [&] { rep.max_von_mises = update_stress(sys, s); });
  s.t = t_end;  // s.n counts accepted steps: the caller's
  return out;
}

LaggedRates lagged_rates(const DiscreteSystem& sys, const State& s) {
  const Mesh& mesh = sys.part.mesh();
  const int n_cells = mesh.n_cells();
  LaggedRates r{std::vector<SymTensor>(n_cells), std::vector<double>(n_cells)};
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    const Material& m = sys.material(c);
    const PointState p{s.sigma[c], s.eps[c], cell_mean(mesh, s.beta, c), m.elasticity.stress_dim(),
                       mesh.cell_centroid(c), s.t};
    r.G[c] = m.law->rate(p);
    m.elasticity.restrict_stress(r.G[c]);
    r.phi[c] = m.source->rate(p);
  }
  return r;
}

SchemeStep::SchemeStep(const MeshPart& part, const ContactSpec& contact)
    : f_(part.dof_layout), phi_(part.node_layout), u_(part.dof_layout), beta_(part.node_layout),
      friction_(step_friction(contact)) {}

const LaggedRates& SchemeStep::rates(const DiscreteSystem& sys, const State& s) {
  if (!rates_) rates_ = lagged_rates(sys, s);
  return *rates_;
}

LaggedRates SchemeStep::take_rates(const DiscreteSystem& sys, const State& s) {
  if (!rates_) rates_ = lagged_rates(sys, s);
  LaggedRates r = std::move(*rates_);
  rates_.reset();
  return r;
}

DamageReport SchemeStep::solve_damage(const DiscreteSystem& sys, DamageSolvers& damage, const SolverChoice& choice,
                                      State& s, const std::vector<double>& phi, double k) {
  phi_.local() = assemble_p0_source(sys.part.mesh(), sys.geo, phi);
  phi_.add_ghosts_to_owners();
  Vector beta = s.beta.head(sys.part.n_owned_nodes), rhs;
  sys.M->mult(beta, rhs);
  rhs += k * phi_.owned();
  const DamageReport rep = damage.for_step(sys, choice, k).solve(rhs, beta);
  beta_.owned() = beta;
  beta_.update_ghosts();
  s.beta = beta_.local();
  return rep;
}

void update_history(State& s, const std::vector<SymTensor>& G, double k) {
  const int n_cells = static_cast<int>(s.z.size());
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) s.z[c] += k * G[c];
}

ContactReport SchemeStep::solve_contact(const DiscreteSystem& sys, ContactSolver& contact, State& s, Vector& u_free,
                                        const StepData& data) {
  // With prescribed displacements u = u_D + ũ (SPEC §6): K u_D joins the right-hand side as
  // the divergence of ℰε(u_D), and ũ vanishes at the prescribed dofs.
  const Mesh& mesh = sys.part.mesh();
  const Vector& u_D = data.u_D;
  std::vector<SymTensor> lifted;
  if (u_D.size() > 0) {  // ε(u_D) vanishes outside the cells touching a prescribed dof
    lifted = s.z;
    for (int c : sys.dirichlet_cells) lifted[c] += sys.material(c).elasticity.apply(cell_strain(mesh, sys.geo[c], u_D, c));
  }
  f_.local() = restrict_to_free(sys.part.dofs, data.F - assemble_stress_divergence(mesh, sys.geo, u_D.size() > 0 ? lifted : s.z));
  f_.add_ghosts_to_owners();
  contact.set_gap(data.gap);
  if (sys.problem->contact.adhesive()) contact.set_bond(data.bond);  // SPEC §9: the bonds' tension branches
  friction_->before_solve(sys, s, data, contact);  // SPEC §7: Δ = T u_n − h, h from u_{n−1} and the obstacle's motion
  const ContactReport rep = contact.solve(f_.owned(), u_free, s.lambda);
  friction_->after_solve(sys, contact, u_free, rep, s);
  u_.owned() = u_free;
  u_.update_ghosts();
  // Into u's own storage (a moved temporary would replace it): the Python module's views
  // of the state stay valid across steps (docs/python.md).
  s.u.noalias() = extend_from_free(sys.part.dofs, u_.local());
  if (u_D.size() > 0) s.u += u_D;
  return rep;
}

double update_stress(const DiscreteSystem& sys, State& s) {
  const Mesh& mesh = sys.part.mesh();
  const int n_cells = mesh.n_cells();
  compute_strain(mesh, sys.geo, s.u, s.eps);
  double max_vm = 0;
#pragma omp parallel for schedule(static) reduction(max : max_vm) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    s.sigma[c] = sys.material(c).elasticity.apply(s.eps[c]) + s.z[c];
    max_vm = std::max(max_vm, s.sigma[c].von_mises());
  }
  return sys.part.comm.max(max_vm);
}

}  // namespace vpc
