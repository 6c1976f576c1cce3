#include "scheme/time_stepper.hpp"

#include "core/error.hpp"
#include "la/memory_estimate.hpp"
#include "scheme/stability.hpp"
#include "solvers/primal_active_set.hpp"
#include "solvers/solver_cost.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <tuple>
#include <utility>

namespace vpc {

namespace {

using Clock = std::chrono::steady_clock;

/// Below this many cells the elementwise loops run on one thread.
constexpr int kParallelCells = 4096;
/// Damage solvers kept for the step sizes in use: a run with a few step sizes factors
/// H = M + kκA once per size.
constexpr std::size_t kDamageSolversKept = 4;
/// Adds the step phases' times of `from` to `to` (substeps, rejected attempts).
void add_seconds(StepReport& to, const StepReport& from) {
  to.seconds_sources += from.seconds_sources;
  to.seconds_damage += from.seconds_damage;
  to.seconds_contact += from.seconds_contact;
  to.seconds_stress += from.seconds_stress;
}

/// The problem, after Problem::validate (which throws for a bad datum).
std::shared_ptr<const Problem> validated(std::shared_ptr<const Problem> p) {
  p->validate();
  return p;
}

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

MinimumAt minimum_at(std::span<const double> values, std::span<const int> index) {
  MinimumAt best;
  for (std::size_t i = 0; i < values.size(); ++i)
    best = minimum_at(best, {values[i], index.empty() ? static_cast<int>(i) : index[i]});
  return best;
}

MinimumAt minimum_at(const MinimumAt& a, const MinimumAt& b) {
  if (a.index < 0) return b;
  if (b.index < 0) return a;
  return b.value < a.value || (b.value == a.value && b.index < a.index) ? b : a;
}

TimeStepper::TimeStepper(std::shared_ptr<const Problem> problem, SolverChoice choice)
    : TimeStepper(problem, whole_mesh_part(validated(problem)), la::serial_backend(), std::move(choice)) {}

TimeStepper::TimeStepper(std::shared_ptr<const Problem> problem, MeshPart part,
                         std::shared_ptr<const la::Backend> backend, SolverChoice choice)
    : problem_(std::move(problem)), part_(std::move(part)), backend_(std::move(backend)), choice_(std::move(choice)) {
  const auto t0 = Clock::now();
  const Problem& p = *problem_;
  const Mesh& mesh = part_.mesh();
  const int d = mesh.dim();
  require(part_.n_global_dofs > 0, "{}: every node is clamped; nothing to solve", p.name);
  geo_ = compute_geometry(mesh);
  materials_ = p.material_list();

  // Loads uniform in space: (f(t), ψ_a e_i) = f_i(t) ∫ψ_a, with the same quadrature.
  const VectorField unit = [](const Point&, double) { return Point{1, 0, 0}; };
  auto basis_integral = [&](const VectorField& f0, const VectorField& f2) {
    const Vector F = assemble_load(mesh, geo_, part_.traction_facets, f0, f2, 0.0);
    return Vector(Eigen::Map<const Vector, 0, Eigen::InnerStride<>>(F.data(), mesh.n_nodes(), Eigen::InnerStride<>(d)));
  };
  if (p.f0 && p.f0_uniform) basis_integral_cells_ = basis_integral(unit, nullptr);
  if (p.f2 && p.f2_uniform) basis_integral_traction_ = basis_integral(nullptr, unit);

  if (!p.contact.obstacles.empty()) {  // the body's bounding box, over every process's nodes
    Point lo{0, 0, 0}, hi{0, 0, 0};
    for (int j = 0; j < 3; ++j) {
      double l = INFINITY, h = -INFINITY;
      for (int i = 0; i < mesh.n_nodes(); ++i) {
        l = std::min(l, mesh.node(i)[j]);
        h = std::max(h, mesh.node(i)[j]);
      }
      lo[j] = part_.comm.min(l);
      hi[j] = part_.comm.max(h);
    }
    miss_gap_ = contact_miss_gap(lo, hi);
  }
  for (int c = 0; c < mesh.n_cells() && !part_.dirichlet_nodes.empty(); ++c)
    for (int a = 0; a <= d; ++a)
      if (std::ranges::any_of(part_.dirichlet.begin() + mesh.cell(c)[a] * d,
                              part_.dirichlet.begin() + (mesh.cell(c)[a] + 1) * d, [](int k) { return k >= 0; })) {
        dirichlet_cells_.push_back(c);
        break;
      }
  assemble_and_factorize();

  // Initial state (3.4): u0 = 0, σ0 = 0 (so z0 = σ0 − ℰε(u0) = 0), β0 = P1 interpolant
  // (in [0, 1]: Problem::validate).
  f_ = la::Vector(part_.dof_layout);
  u_ = la::Vector(part_.dof_layout);
  phi_ = la::Vector(part_.node_layout);
  beta_ = la::Vector(part_.node_layout);
  state_.u = Vector::Zero(part_.dofs.n_full());
  state_.beta.resize(mesh.n_nodes());
  for (int i = 0; i < mesh.n_nodes(); ++i) state_.beta[i] = p.beta0 ? p.beta0(mesh.node(i), 0.0) : 1.0;
  state_.sigma.assign(mesh.n_cells(), SymTensor{});
  state_.eps.assign(mesh.n_cells(), SymTensor{});
  state_.z.assign(mesh.n_cells(), SymTensor{});
  state_.contact_block = p.contact.block_size(mesh.dim());  // the contact laws' block (1: normal laws)
  state_.lambda = Vector::Zero(part_.n_contact * state_.contact_block);
  u_free_ = Vector::Zero(part_.n_owned_dofs);
  // Error-controlled steps stay within the explicit G's stable step (scheme/stability.hpp).
  if (p.step_control) control_ = stable_step_control(p);
  for (const CellGeometry& g : geo_) volume_ += g.volume;
  volume_ = part_.comm.sum(volume_);
  const auto owned_beta = state_.beta.head(part_.n_owned_nodes).array();
  control_state_.n_beta_zero = part_.comm.sum(static_cast<double>((owned_beta <= 0).count()));
  control_state_.n_beta_one = part_.comm.sum(static_cast<double>((owned_beta >= 1).count()));
  setup_timing_.total = seconds_since(t0);
}

void TimeStepper::assemble_and_factorize() {
  const Problem& p = *problem_;
  const Mesh& mesh = part_.mesh();
  const int d = mesh.dim();
  auto stage = [&](const std::string& what, double seconds = -1) {
    if (choice_.on_setup_stage) choice_.on_setup_stage(what, seconds);
  };
  // Constant matrices: K of (3.9), factorized once; H = M + kκA of (3.8). Each
  // process assembles its cells; the backend sums the parts.
  stage("assembly");
  auto t1 = Clock::now();
  // K's dofs come in blocks of d per node unless some node has only some components
  // prescribed (a roller): then blocks of 1, and no rigid-body modes for multigrid.
  bool partial = false;
  for (std::size_t i = 0; i < part_.dirichlet.size() && !partial; i += d) {
    const auto fixed = std::count_if(part_.dirichlet.begin() + i, part_.dirichlet.begin() + i + d, [](int k) { return k >= 0; });
    partial = fixed > 0 && fixed < d;
  }
  const int block = part_.comm.any(partial) ? 1 : d;
  K_block_ = block;
  std::vector<Elasticity> elasticity;
  for (const Material& m : materials_) elasticity.push_back(m.elasticity);
  const SparseMatrix K_local = assemble_stiffness(mesh, geo_, elasticity, part_.cell_material, part_.dofs);
  K_ = backend_->assemble(K_local, *part_.dof_layout, block);
  K_local_nonzeros_ = static_cast<double>(K_local.nonZeros());
  M_local_ = assemble_mass(mesh, geo_);
  A_local_ = assemble_laplacian(mesh, geo_);
  M_ = backend_->assemble(M_local_, *part_.node_layout, 1);
  la::Vector lumped(part_.node_layout);
  lumped.local() = M_local_ * Vector::Ones(M_local_.cols());
  lumped.add_ghosts_to_owners();
  lumped_mass_ = lumped.owned();
  const SparseMatrix H_local = M_local_ + (p.first_step() * p.kappa) * A_local_;
  auto H = backend_->assemble(H_local, *part_.node_layout, 1);
  const long long damage_operator_nonzeros = H->nonzeros();
  setup_timing_.assembly = seconds_since(t1);
  stage("assembly", setup_timing_.assembly);

  stage(fmt::format("factorization of K ({} x {}, {} nonzeros; {})", part_.n_global_dofs, part_.n_global_dofs,
                    K_->nonzeros(), backend_->describe()));
  t1 = Clock::now();
  ContactConstraints constraints = contact_constraints();
  const bool nonlinear_law = nonlinear_in_dual(part_.comm, constraints);  // only the dual solves it
  contact_pick_ = pick_contact_solver(choice_.contact, part_.n_contact, backend_->linear_solver(), nonlinear_law);
  const bool primal = contact_pick_.name == "primal-active-set";
  K_factor_ = make_stiffness_factor(block);
  // Refuse a run that cannot fit before the costly factorizations (issue 11); the
  // factors' sizes come from their symbolic analyses (K's is reused), where the
  // backend has them (CHOLMOD).
  if (const auto K_size = K_factor_->analyze(*K_, "elastic stiffness K")) {
    const auto H_size = backend_->factor("H")->analyze(*H, "damage matrix H = M + k kappa A");
    const double mesh_bytes = 24.0 * mesh.n_nodes() + 4.0 * mesh.cell_array().size() +
                              (sizeof(CellGeometry) + 3.0 * sizeof(SymTensor)) * mesh.n_cells();
    const double matrix_bytes =
        12.0 * (K_local.nonZeros() + M_local_.nonZeros() + A_local_.nonZeros() + 2.0 * H_local.nonZeros());
    check_memory(estimate_run_memory(mesh_bytes, matrix_bytes, *K_size, H_size.value_or(FactorEstimate{}),
                                     choice_.damage == "active-set", primal ? 0 : part_.n_contact),
                 memory_limit(choice_.memory_limit), p.name);
    solver_cost_ = estimate_solver_cost(*K_size, static_cast<double>(K_->nonzeros()), part_.n_contact, p.expected_steps(),
                                        !primal);
    if (choice_.iterative_fallback && choice_.contact == "auto" && !nonlinear_law &&
        iterative_is_faster(*solver_cost_))
      throw IterativeIsFaster(fmt::format("{}: CG + GAMG is estimated to take less than half the direct solver's "
                                          "time ({})", p.name, solver_cost_->detail));
  }
  // The primal contact solver factors K with its active rows when it first solves.
  if (!primal) K_factor_->factorize(*K_, "elastic stiffness K");
  setup_timing_.factor_K = seconds_since(t1);
  stage("factorization of K", setup_timing_.factor_K);

  stage(fmt::format("factorization of H ({} x {}, {} nonzeros)", part_.n_global_nodes, part_.n_global_nodes,
                    damage_operator_nonzeros));
  t1 = Clock::now();
  damage_solver(p.first_step(), std::move(H));
  setup_timing_.factor_H = seconds_since(t1);
  stage("factorization of H", setup_timing_.factor_H);

  stage("contact set-up");
  t1 = Clock::now();
  if (primal) {
    // Rows off the axes are turned into one dof each by node-local reflections Q: K_rot = Q K Q,
    // assembled from the cells' matrices like K (Q acts within each node's dofs).
    std::shared_ptr<const la::SpdOperator> K_rot;
    if (part_.comm.any(contact_reflections(constraints.N).size() > 0)) {
      const SparseMatrix Q = contact_reflections(contact_matrix(false));
      K_rot = backend_->assemble(SparseMatrix(Q * K_local * Q), *part_.dof_layout, block);
    }
    contact_ = make_primal_active_set_solver(K_, std::move(K_rot), std::exchange(K_factor_, nullptr),
                                             std::move(constraints));
  } else {
    contact_ = make_contact_solver(contact_pick_.name, K_, K_factor_, std::move(constraints),
                                   la::factor_factory(backend_), choice_.contact_options);
  }
  setup_timing_.contact = seconds_since(t1);
  stage("contact set-up", setup_timing_.contact);
}

std::shared_ptr<la::Factor> TimeStepper::make_stiffness_factor(int block) const {
  const Mesh& mesh = part_.mesh();
  const int d = mesh.dim();
  std::shared_ptr<la::Factor> factor = backend_->factor("K");
  Vector coordinates(part_.n_owned_dofs);  // GAMG's rigid-body modes
  for (int i = 0; i < part_.n_owned_nodes; ++i)
    for (int c = 0; c < d; ++c)
      if (const int k = part_.dofs.free_index(part_.dofs.full_index(i, c)); k >= 0) coordinates[k] = mesh.node(i)[c];
  factor->set_coordinates(coordinates, block == d ? d : 0);
  return factor;
}

const la::Factor& TimeStepper::stiffness_factor() {
  if (!K_factor_) {
    K_factor_ = make_stiffness_factor(K_block_);
    K_factor_->factorize(*K_, "elastic stiffness K");
  }
  return *K_factor_;
}

SparseMatrix TimeStepper::contact_matrix(bool owned_only) const {
  const int d = part_.mesh().dim();
  std::vector<Eigen::Triplet<double>> t;
  int row = 0;
  for (const PartContactNode& node : part_.contact) {
    if (owned_only && !node.owned) continue;
    for (int i = 0; i < d; ++i)
      if (const int k = part_.dofs.free_index(part_.dofs.full_index(node.local_node, i)); node.direction[i] != 0 && k >= 0)
        t.emplace_back(row, k, node.direction[i]);
    ++row;
  }
  SparseMatrix N(row, owned_only ? part_.n_owned_dofs : part_.dofs.n_free());
  N.setFromTriplets(t.begin(), t.end());
  return N;
}

ContactConstraints TimeStepper::contact_constraints() const {
  ContactConstraints c;
  c.m = part_.n_contact;
  for (const PartContactNode& node : part_.contact)
    if (node.owned) c.rows.push_back(node.row);
  c.N = contact_matrix(true);
  c.gap = contact_gap(0.0);
  // Each row's law (contact/contact_law.hpp) and its compliance 1/k_i, k_i = c |Γ3|_i: the law
  // lumped at the node (ContactRow).
  c.laws = problem_->contact.laws();
  c.block = problem_->contact.block_size(part_.mesh().dim());
  std::vector<double> compliance;
  for (const PartContactNode& node : part_.contact)
    if (node.owned) {
      c.law.push_back(node.law);
      compliance.push_back(node.stiffness > 0 ? 1 / node.stiffness : 0.0);
    }
  c.compliance = Eigen::Map<Vector>(compliance.data(), static_cast<Eigen::Index>(compliance.size()));
  return c;
}

Vector TimeStepper::contact_gap(double t) const {
  const ContactSpec& spec = problem_->contact;
  std::vector<double> gaps;
  std::string bad;
  for (const PartContactNode& node : part_.contact) {
    if (!node.owned) continue;
    if (!spec.gap_moves && spec.obstacles.empty()) {
      gaps.push_back(node.gap);
      continue;
    }
    // A moving obstacle (SPEC §6): g(x, t_n) < 0 is an obstacle that pushes the body
    // back (N u ≤ g < 0 is still a feasible constraint); a value that is not a number
    // is an error, reported by every process.
    const Point& x = part_.mesh().node(node.local_node);
    gaps.push_back(contact_gap_at(spec, x, node.direction, t, miss_gap_, node.obstacles));
    if (!std::isfinite(gaps.back()) && bad.empty())
      bad = fmt::format("the gap g is not finite ({}) at t = {} at contact node {} ({}, {}, {})", gaps.back(), t,
                        part_.original_node[node.local_node], x[0], x[1], x[2]);
  }
  // This step's data (F_n, u_D and g at t_n, all evaluated by now) is finite (issue 26).
  la::collective(part_.comm, [&] {
    check_formulas(*problem_);
    require(bad.empty(), "{}", bad);
  });
  return Eigen::Map<Vector>(gaps.data(), static_cast<Eigen::Index>(gaps.size()));
}

double TimeStepper::factor_bytes() const {
  const la::Factor* contact = contact_->own_factor();
  double bytes = (K_factor_ ? K_factor_->factor_bytes() : 0.0) + (contact ? contact->factor_bytes() : 0.0);
  for (const DamageForStep& d : damage_) bytes += d.solver->factor_bytes();
  return bytes;
}

double TimeStepper::model_bytes() const {
  const Mesh& m = part_.mesh();
  // K and M as operators, M and A kept locally for halved steps (value + row index).
  const double matrices = 12.0 * (K_local_nonzeros_ + 2.0 * M_local_.nonZeros() + A_local_.nonZeros());
  const double mesh = 24.0 * m.n_nodes() + 4.0 * m.cell_array().size() + sizeof(CellGeometry) * geo_.size();
  const double state = 8.0 * (state_.u.size() + state_.beta.size() + u_free_.size()) +
                       3.0 * sizeof(SymTensor) * state_.sigma.size();
  return matrices + mesh + state;
}

int TimeStepper::n_factorizations() const {
  const la::Factor* contact = contact_->own_factor();
  int n = (K_factor_ ? K_factor_->n_factorizations() : 0) + (contact ? contact->n_factorizations() : 0) +
          dropped_factorizations_;
  for (const DamageForStep& d : damage_) n += d.solver->n_factorizations();
  return n;
}

Snapshot TimeStepper::snapshot() const {
  return {state_, u_free_, contact_->warm_state(), damage_current_->warm_state()};
}

Vector TimeStepper::contact_warm_state() const { return contact_->warm_state(); }
Vector TimeStepper::damage_warm_state() const { return damage_current_->warm_state(); }

void TimeStepper::restore(const Snapshot& s) {
  const bool same = s.state.u.size() == state_.u.size() && s.state.beta.size() == state_.beta.size() &&
                    s.state.sigma.size() == state_.sigma.size() && s.state.eps.size() == state_.eps.size() &&
                    s.state.z.size() == state_.z.size() && s.state.lambda.size() == state_.lambda.size() &&
                    s.u_free.size() == u_free_.size() && s.state.n >= 0 &&
                    (problem_->step_control ? s.state.t <= problem_->final_time : s.state.n <= problem_->n_steps);
  require(same, "{}: the saved state does not fit this problem (a different mesh, case or step count?)",
          problem_->name);
  state_ = s.state;
  u_free_ = s.u_free;
  contact_->set_warm_state(s.contact_warm);
  damage_current_->set_warm_state(s.damage_warm);
  rates_valid_ = false;  // recomputed from the restored state: the same values
}

Vector StepControlState::values() const {
  Vector v(6);
  v << k_next, sigma_scale, n_active, n_beta_zero, n_beta_one, rejected;
  return v;
}

StepControlState StepControlState::from_values(const Vector& v) {
  require(v.size() == 6, "the step-size state has {} values, expected 6", v.size());
  return {v[0], v[1], v[2], v[3], v[4], v[5]};
}

void TimeStepper::set_step_history(std::vector<double> times, const StepControlState& c) {
  require(times.size() == static_cast<std::size_t>(state_.n) + 1 && times.front() == 0 && times.back() == state_.t,
          "{}: the saved time levels do not end at the state's step {} (t = {})", problem_->name, state_.n, state_.t);
  times_ = std::move(times);
  control_state_ = c;
}

DamageSolver& TimeStepper::damage_solver(double k, std::unique_ptr<la::SpdOperator> H) {
  auto it = std::find_if(damage_.begin(), damage_.end(), [k](const DamageForStep& d) { return d.k == k; });
  if (it == damage_.end()) {
    const Vector warm = damage_current_ ? damage_current_->warm_state() : Vector();
    if (damage_.size() >= kDamageSolversKept) {  // the least recently used (never the current: it is last)
      dropped_factorizations_ += damage_.front().solver->n_factorizations();
      damage_.erase(damage_.begin());
    }
    if (!H) H = backend_->assemble(SparseMatrix(M_local_ + (k * problem_->kappa) * A_local_), *part_.node_layout, 1);
    ++damage_matrices_made_;
    damage_.push_back({k, make_damage_solver(choice_.damage, std::move(H), la::factor_factory(backend_),
                                             choice_.damage_reduced)});
    if (damage_current_) damage_.back().solver->set_warm_state(warm);
    damage_current_ = damage_.back().solver.get();
    return *damage_current_;
  }
  if (it + 1 != damage_.end()) std::rotate(it, it + 1, damage_.end());
  DamageSolver* next = damage_.back().solver.get();
  if (next != damage_current_) next->set_warm_state(damage_current_->warm_state());  // the warm start is the state's
  damage_current_ = next;
  return *next;
}

StepReport TimeStepper::step() {
  require(!done(), "{}: the run is already at the final time", problem_->name);
  const Problem& p = *problem_;
  const int n = state_.n + 1;
  StepReport rep = p.step_control ? controlled_step() : advance_or_halve(0, p.step_at(n), p.time_at(n));
  state_.n = rep.n = n;
  times_.push_back(state_.t);
  check_lagged_step(rep);
  control_state_.sigma_scale = std::max(control_state_.sigma_scale, rep.sigma_norm);
  control_state_.n_active = rep.contact.n_active;
  control_state_.n_beta_zero = rep.damage.n_lower;
  control_state_.n_beta_one = rep.damage.n_upper;
  return rep;
}

StepReport TimeStepper::advance_or_halve(int level, double k, double t_end) {
  if (level >= choice_.max_halvings) return advance(k, t_end);
  const Snapshot before = snapshot();
  StepReport rep = advance(k, t_end);
  if (rep.ok) return rep;  // the same on every process: rep is
  restore(before);
  const double t_mid = before.state.t + k / 2;
  const StepReport first = advance_or_halve(level + 1, k / 2, t_mid);
  if (!first.ok) return first;
  rep = advance_or_halve(level + 1, k / 2, t_end);
  rep.k = t_end - before.state.t;
  rep.error_estimate = std::max(rep.error_estimate, first.error_estimate);
  rep.substeps += first.substeps;
  add_seconds(rep, first);
  return rep;
}

bool TimeStepper::is_event(const StepReport& rep) const {
  const StepControlState& last = control_state_;
  return (control_->contact_events && rep.contact.n_active != last.n_active) ||
         (control_->damage_events && (rep.damage.n_lower > last.n_beta_zero || rep.damage.n_upper > last.n_beta_one));
}

StepReport TimeStepper::controlled_step() {
  const StepControl& c = *control_;
  const double T = problem_->final_time;
  const Snapshot before = snapshot();
  const double t0 = before.state.t;
  double k = control_state_.k_next > 0 ? control_state_.k_next : c.dt_initial;
  int rejected = 0;
  StepReport spent;  // the rejected attempts' times: part of the step's cost
  for (;;) {
    k = step_on_ladder(k, c.dt_min, c.dt_max);
    const double t_end = step_end(t0, k, T, c.landings);
    const double k_used = t_end == t0 + k ? k : t_end - t0;  // a ladder size, or shortened to land
    StepReport rep = advance(k_used, t_end);
    // r: the estimate over what the tolerance allows this step (an error per unit of time).
    const double r = rep.error_estimate / (c.tolerance * k_used);
    double retry = 0;  // the smaller step to redo it with (0: accept)
    if (!rep.ok)
      retry = k_used * c.cut;
    else if (k_used > c.event_dt * (1 + 1e-9) && is_event(rep))
      retry = std::max(c.event_dt, k_used * c.cut);
    else if (r > 1)
      retry = k_used * std::max(c.cut, c.safety / r);
    const bool at_floor = k_used <= c.dt_min * (1 + 1e-9) || rejected >= c.max_rejections;
    if (retry == 0 || at_floor) {
      rep.rejected = rejected;
      add_seconds(rep, spent);
      // The next step: the factor the estimate allows, within [cut, growth]; a step
      // shortened to land on a time does not shrink the next one below its proposal.
      const double allowed = r > 0 ? c.safety / r : c.growth;
      double next = k_used * std::clamp(allowed, c.cut, c.growth);
      if (k_used < k && r <= 1) next = std::max(next, std::min(k, k_used * allowed));
      if (is_event(rep)) next = std::min(next, c.event_dt);  // events come in runs: no rejection for each
      if (rep.ok) {
        control_state_.k_next = std::clamp(next, c.dt_min, c.dt_max);
        control_state_.rejected += rejected;
      }
      return rep;
    }
    add_seconds(spent, rep);
    restore(before);
    ++rejected;
    k = std::max(retry, c.dt_min);
  }
}

void TimeStepper::compute_rates() {
  const Mesh& mesh = part_.mesh();
  const int n_cells = mesh.n_cells();
  rates_G_.resize(n_cells);
  rates_phi_.resize(n_cells);
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    const Material& m = material(c);
    const PointState s{state_.sigma[c], state_.eps[c], cell_mean(mesh, state_.beta, c), m.elasticity.stress_dim(),
                       mesh.cell_centroid(c), state_.t};
    rates_G_[c] = m.law->rate(s);
    m.elasticity.restrict_stress(rates_G_[c]);
    rates_phi_[c] = m.source->rate(s);
  }
  rates_valid_ = true;
}

Vector TimeStepper::load(double t) const {
  const Problem& p = *problem_;
  const Mesh& mesh = part_.mesh();
  const int d = mesh.dim();
  const bool f0_once = basis_integral_cells_.size() > 0, f2_once = basis_integral_traction_.size() > 0;
  Vector F = assemble_load(mesh, geo_, part_.traction_facets, f0_once ? nullptr : p.f0, f2_once ? nullptr : p.f2, t);
  for (auto [once, f, w] : {std::tuple{f0_once, &p.f0, &basis_integral_cells_},
                            std::tuple{f2_once, &p.f2, &basis_integral_traction_}}) {
    if (!once) continue;
    const Point v = (*f)(Point{0, 0, 0}, t);
    for (int a = 0; a < mesh.n_nodes(); ++a)
      for (int i = 0; i < d; ++i) F[a * d + i] += v[i] * (*w)[a];
  }
  for (std::size_t k = 0; k < p.pressure.size(); ++k) add_pressure_load(mesh, part_.pressure_facets[k], p.pressure[k].p, t, F);
  return F;
}

void TimeStepper::contact_totals(StepReport& rep) const {
  const auto& obstacles = problem_->contact.obstacles;
  std::vector<double> sums(obstacles.size() + 1, 0.0);  // area, then the obstacles' forces
  for (const PartContactNode& node : part_.contact) {
    if (!node.owned) continue;
    const double lambda = state_.lambda[node.row];
    if (lambda > rep.contact.active_threshold) sums[0] += node.measure;
    if (obstacles.empty() || lambda == 0) continue;
    const int nearest = nearest_obstacle(obstacles, part_.mesh().node(node.local_node), node.direction, rep.t,
                                         node.obstacles);
    if (nearest >= 0) sums[static_cast<std::size_t>(nearest) + 1] += lambda;
  }
  part_.comm.sum(sums.data(), static_cast<int>(sums.size()));
  rep.contact_area = sums[0];
  rep.obstacle_force.assign(sums.begin() + 1, sums.end());
}

Vector TimeStepper::prescribed_displacement(double t) const {
  const auto& conditions = problem_->displacement;
  if (conditions.empty()) return {};
  const int d = part_.mesh().dim();
  Vector u_D = Vector::Zero(part_.dofs.n_full());
  for (const auto& [node, bits] : part_.dirichlet_nodes)
    for (int c = 0; c < d; ++c)
      if (const int k = part_.dirichlet[node * d + c]; k > 0) u_D[node * d + c] = conditions[k - 1].value[c](part_.mesh().node(node), t);
  return u_D;
}

void TimeStepper::reactions(StepReport& rep, const Vector& F) const {
  const Mesh& mesh = part_.mesh();
  const int d = mesh.dim();
  // r = (σ_n, ε(φ)) − F_n at the prescribed dofs; each cell and loaded facet lives on
  // one process, so the part's sums over its nodes (owned and ghost) add up to the whole.
  Vector r = Vector::Zero(part_.dofs.n_full());
  for (int c : dirichlet_cells_)
    for (int a = 0; a <= d; ++a)
      for (int i = 0; i < d; ++i) r[mesh.cell(c)[a] * d + i] += stress_divergence_entry(geo_[c], state_.sigma[c], d, a, i);
  // A part's reaction has the components it prescribes (a roller's: its normal one); each
  // prescribed dof counts once, for the first part that prescribes it there, so that the
  // reactions of all parts add up to the supports' total force.
  const auto& prescribes = part_.dirichlet_components;
  std::vector<double> sums(prescribes.size() * d, 0.0);
  for (const auto& [node, bits] : part_.dirichlet_nodes)
    for (int i = 0; i < d; ++i)
      for (std::size_t j = 0; j < prescribes.size(); ++j)
        if ((bits >> j & 1) && (prescribes[j] >> i & 1)) {
          sums[j * d + i] += r[node * d + i] - F[node * d + i];
          break;
        }
  part_.comm.sum(sums.data(), static_cast<int>(sums.size()));
  rep.reaction.clear();
  for (std::size_t j = 0; j < prescribes.size(); ++j)
    for (int i = 0; i < d; ++i)
      if (prescribes[j] >> i & 1) rep.reaction.push_back(sums[j * d + i]);
}

void TimeStepper::beta_range(StepReport& rep) const {
  const la::Comm& comm = part_.comm;
  const auto n = static_cast<std::size_t>(part_.n_owned_nodes);
  const MinimumAt mine = minimum_at({state_.beta.data(), n}, {part_.original_node.data(), n});
  // minimum_at's rule over the processes: the least value, then the least node holding it.
  const double lo = comm.min(mine.index < 0 ? INFINITY : mine.value);
  const double at = comm.min(mine.index >= 0 && mine.value == lo ? mine.index : INFINITY);
  rep.beta_min = lo;
  rep.beta_min_node = std::isfinite(at) ? static_cast<int>(at) : mine.index;
  rep.beta_max = comm.max(n ? state_.beta.head(static_cast<Eigen::Index>(n)).maxCoeff() : -INFINITY);
}

void TimeStepper::check_lagged_step(const StepReport& rep) {
  // An unstable mode of the explicit step has ΔG_n = (1 − kL) ΔG_{n−1}, kL > 2: it flips sign
  // and grows, which a stable step cannot do (|1 − kL| ≤ 1). A smooth extremum of G flips ΔG
  // once (through zero), a load that alternates step by step does not grow: the run stops after
  // two flips in a row (cos < −½: the mode carries most of ΔG) over which |ΔG| grew kUnstableGrowth times.
  constexpr double kUnstableGrowth = 4;
  const double growth = dG2_last_ > 0 ? std::sqrt(dG2_attempt_ / dG2_last_) : 0.0;
  const bool flips_and_grows = growth > 1 && dG_dot_attempt_ < -0.5 * std::sqrt(dG2_attempt_ * dG2_last_);
  growing_steps_ = flips_and_grows ? growing_steps_ + 1 : 0;
  growth_product_ = flips_and_grows ? growth_product_ * growth : 1.0;
  dG2_last_ = dG2_attempt_;
  std::swap(dG_last_, dG_attempt_);
  if (growing_steps_ < 2 || growth_product_ < kUnstableGrowth) return;
  // Name the material where ΔG is largest, and its least β where ΔG is (the β its L is worst at).
  const Mesh& mesh = part_.mesh();
  std::vector<double> largest(materials_.size(), 0.0), beta(materials_.size(), INFINITY);
  for (int c = 0; c < mesh.n_cells(); ++c) {
    double& l = largest[static_cast<std::size_t>(part_.cell_material[c])];
    l = std::max(l, dG_last_[c].dot(dG_last_[c]));
  }
  for (double& l : largest) l = part_.comm.max(l);
  const auto m = static_cast<std::size_t>(std::max_element(largest.begin(), largest.end()) - largest.begin());
  for (int c = 0; c < mesh.n_cells(); ++c)
    if (static_cast<std::size_t>(part_.cell_material[c]) == m && dG_last_[c].dot(dG_last_[c]) >= 0.25 * largest[m])
      beta[m] = std::min(beta[m], cell_mean(mesh, state_.beta, c));
  const double b = part_.comm.min(beta[m]);
  la::collective(part_.comm, [&] {
    fail("{}", unstable_step_message(*problem_, materials_[m], std::isfinite(b) ? b : 1.0, rep.n, rep.t, rep.k,
                                     growth_product_, growing_steps_));
  });
}

std::vector<double> TimeStepper::error_damping(const std::vector<SymTensor>& G_before) const {
  const Mesh& mesh = part_.mesh();
  const int n_cells = mesh.n_cells();
  std::vector<double> jd(n_cells, 0.0);
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    const SymTensor dG = rates_G_[c] - G_before[c];
    const double size = dG.norm(), s = state_.sigma[c].norm();
    if (size == 0 || s == 0) continue;
    // A difference quotient along ΔG (the laws' rates are Lipschitz in σ, not all differentiable),
    // with σ moved by a relative 1e-6.
    const double h = 1e-6 * s / size;
    const Material& m = material(c);
    const PointState moved{state_.sigma[c] + h * dG, state_.eps[c], cell_mean(mesh, state_.beta, c),
                           m.elasticity.stress_dim(), mesh.cell_centroid(c), state_.t};
    SymTensor rate = m.law->rate(moved);
    m.elasticity.restrict_stress(rate);
    jd[c] = dG.dot(rate - rates_G_[c]) / h;
  }
  return jd;
}

StepReport TimeStepper::advance(double k, double t_end) {
  const Mesh& mesh = part_.mesh();
  const la::Comm& comm = part_.comm;
  const int n_cells = mesh.n_cells();
  StepReport rep;
  rep.n = state_.n + 1;
  rep.t = t_end;
  rep.k = k;

  // Step 1: lagged sources G_{n−1}, φ_{n−1} per element, β at the centroid (computed
  // at the end of the step before, for its error estimate).
  auto t0 = Clock::now();
  if (!rates_valid_) compute_rates();
  const std::vector<SymTensor> G = std::move(rates_G_);
  const std::vector<double> phi = std::move(rates_phi_);
  rates_valid_ = false;
  rep.seconds_sources = seconds_since(t0);

  // Step 2: damage (3.8): the box QP with H = M + kκA, r = M β_{n−1} + k F_φ.
  t0 = Clock::now();
  phi_.local() = assemble_p0_source(mesh, geo_, phi);
  phi_.add_ghosts_to_owners();
  const Vector beta_before = state_.beta;  // the estimate's β_n − β_{n−1}
  Vector beta = state_.beta.head(part_.n_owned_nodes), rhs;
  M_->mult(beta, rhs);
  rhs += k * phi_.owned();
  rep.damage = damage_solver(k).solve(rhs, beta);
  beta_.owned() = beta;
  beta_.update_ghosts();
  state_.beta = beta_.local();
  rep.seconds_damage = seconds_since(t0);

  // Step 3: history (3.6): z_n = z_{n−1} + k G_{n−1}.
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) state_.z[c] += k * G[c];

  // Step 4: contact (3.9): K u_n = F_n − Bᵀz_n − Nᵀλ with Signorini conditions. With
  // prescribed displacements u = u_D + ũ (SPEC §6): K u_D joins the right-hand side as
  // the divergence of ℰε(u_D), and ũ vanishes at the prescribed dofs.
  t0 = Clock::now();
  const Vector F = load(rep.t), u_D = prescribed_displacement(rep.t);
  std::vector<SymTensor> lifted;
  if (u_D.size() > 0) {  // ε(u_D) vanishes outside the cells touching a prescribed dof
    lifted = state_.z;
    for (int c : dirichlet_cells_) lifted[c] += material(c).elasticity.apply(cell_strain(mesh, geo_[c], u_D, c));
  }
  f_.local() = restrict_to_free(part_.dofs, F - assemble_stress_divergence(mesh, geo_, u_D.size() > 0 ? lifted : state_.z));
  f_.add_ghosts_to_owners();
  contact_->set_gap(contact_gap(rep.t));
  rep.contact = contact_->solve(f_.owned(), u_free_, state_.lambda);
  contact_totals(rep);
  u_.owned() = u_free_;
  u_.update_ghosts();
  // Into u's own storage (a moved temporary would replace it): the Python module's views
  // of the state stay valid across steps (docs/python.md).
  state_.u.noalias() = extend_from_free(part_.dofs, u_.local());
  if (u_D.size() > 0) state_.u += u_D;
  rep.seconds_contact = seconds_since(t0);

  // Step 5: stress (3.6): σ_n = ℰε(u_n) + z_n.
  t0 = Clock::now();
  compute_strain(mesh, geo_, state_.u, state_.eps);
  double max_vm = 0;
#pragma omp parallel for schedule(static) reduction(max : max_vm) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    state_.sigma[c] = material(c).elasticity.apply(state_.eps[c]) + state_.z[c];
    max_vm = std::max(max_vm, state_.sigma[c].von_mises());
  }
  rep.max_von_mises = comm.max(max_vm);
  reactions(rep, F);
  rep.seconds_stress = seconds_since(t0);

  beta_range(rep);
  state_.t = rep.t;  // state_.n is the grid step: step() sets it

  // The error estimate (StepControl, scheme/time_grid.hpp): the local error (k/2)|x'(t_n) −
  // x'(t_{n−1})| of the explicit rate of z, G (3.6), and of β's rate in (3.8), M β' = F_φ − κAβ,
  // whose change over the step is F_φ(n) − F_φ(n−1) − κA(β_n − β_{n−1}) (M lumped; nodes at a
  // bound have no rate). G_n, φ_n are the next step's step 1. The sums run in cell and node
  // order on each process (an OpenMP reduction's order varies, and the estimate chooses steps).
  t0 = Clock::now();
  compute_rates();
  la::collective(comm, [&] { check_formulas(*problem_); });  // φ_n finite (issue 26)
  const std::vector<double> damping = error_damping(G);
  // |ΔG|², |Δβ'|², |σ_n|² (L2), ⟨ΔG, J ΔG⟩, (ΔG, ΔG of the last accepted step)
  double sums[5] = {0, 0, 0, 0, 0};
  std::vector<double> dphi(n_cells);
  dG_attempt_.resize(n_cells);
  const bool have_last = dG_last_.size() == static_cast<std::size_t>(n_cells);
  for (int c = 0; c < n_cells; ++c) {
    const double w = geo_[c].volume;
    const SymTensor dG = rates_G_[c] - G[c];
    sums[0] += w * dG.dot(dG);
    if (have_last) sums[4] += w * dG.dot(dG_last_[c]);
    dG_attempt_[c] = dG;
    sums[2] += w * state_.sigma[c].dot(state_.sigma[c]);
    sums[3] += w * damping[c];
    dphi[c] = rates_phi_[c] - phi[c];
  }
  phi_.local() = assemble_p0_source(mesh, geo_, dphi) - problem_->kappa * (A_local_ * (state_.beta - beta_before));
  phi_.add_ghosts_to_owners();
  for (int i = 0; i < part_.n_owned_nodes; ++i)
    if (beta[i] > 0 && beta[i] < 1) sums[1] += phi_.owned()[i] * phi_.owned()[i] / lumped_mass_[i];
  comm.sum(sums, 5);
  dG2_attempt_ = sums[0];
  dG_dot_attempt_ = sums[4];
  rep.sigma_norm = std::sqrt(sums[2]);
  const double sigma_scale = std::max(control_state_.sigma_scale, rep.sigma_norm);
  // The law damps an error in z along ΔG at the rate μ = −⟨ΔG, J ΔG⟩ / |ΔG|² (J = ∂G/∂σ); the
  // explicit step keeps a factor |1 − kμ| of it per step, a rate −ln|1 − kμ| / k (none from
  // kμ ≥ 2 on: the step is unstable). Such an error lasts about 1/μ, not until T, so the step's
  // share of the error at any time up to T is its local error times 1/(μT) (at most 1).
  const double mu = sums[0] > 0 ? -sums[3] / sums[0] : 0.0;
  const double mu_step = k * mu >= 2 ? 0.0 : std::min(mu, -std::log(std::abs(1 - k * mu)) / k);
  const double lasting = mu_step * problem_->final_time > 1 ? 1 / (mu_step * problem_->final_time) : 1.0;
  const double e_sigma = sigma_scale > 0 ? k / 2 * std::sqrt(sums[0]) / sigma_scale * lasting : 0.0;
  const double e_beta = k / 2 * std::sqrt(sums[1] / volume_);
  rep.error_estimate = std::max(e_sigma, e_beta);
  rep.seconds_sources += seconds_since(t0);

  const double tol = choice_.residual_tolerance;
  // allFinite, not a sum of squares: that overflows for a finite |u| > 1e154 (issue 26).
  const bool finite = comm.all(u_free_.allFinite() && beta.allFinite());
  rep.ok = rep.contact.converged && rep.damage.converged && rep.contact.residuals.max() <= tol &&
           rep.damage.kkt_residual <= tol && finite;
  return rep;
}

}  // namespace vpc
