#include "scheme/time_stepper.hpp"

#include "core/error.hpp"
#include "la/memory_estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <tuple>

namespace vpc {

namespace {

using Clock = std::chrono::steady_clock;

/// Below this many cells the elementwise loops run on one thread.
constexpr int kParallelCells = 4096;
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
    : problem_(std::move(problem)), choice_(std::move(choice)) {
  const auto t0 = Clock::now();
  const Problem& p = *problem_;
  p.validate();
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim();
  geo_ = compute_geometry(mesh);

  // V^h: P1 vectors vanishing on Γ1 (2.4).
  dofs_ = DofMap(mesh.n_nodes(), d, mesh.nodes_of_parts(p.clamped));
  require(dofs_.n_free() > 0, "{}: every node is clamped; nothing to solve", p.name);

  // Γ2: the given parts, or everything that is neither Γ1 nor Γ3.
  traction_facets_ = traction_facets(p);

  // Loads uniform in space: (f(t), ψ_a e_i) = f_i(t) ∫ψ_a, with the same quadrature.
  const VectorField unit = [](const Point&, double) { return Point{1, 0, 0}; };
  auto basis_integral = [&](const VectorField& f0, const VectorField& f2) {
    const Vector F = assemble_load(mesh, geo_, traction_facets_, f0, f2, 0.0);
    return Vector(Eigen::Map<const Vector, 0, Eigen::InnerStride<>>(F.data(), mesh.n_nodes(), Eigen::InnerStride<>(d)));
  };
  if (p.f0 && p.f0_uniform) basis_integral_cells_ = basis_integral(unit, nullptr);
  if (p.f2 && p.f2_uniform) basis_integral_traction_ = basis_integral(nullptr, unit);

  // Constant matrices: K of (3.9), factorized once; H = M + kκA of (3.8).
  auto stage = [&](const std::string& what, double seconds = -1) {
    if (choice_.on_setup_stage) choice_.on_setup_stage(what, seconds);
  };
  stage("assembly");
  auto t1 = Clock::now();
  K_ = std::make_shared<const la::SparseOperator>(assemble_stiffness(mesh, geo_, p.elasticity, dofs_));
  M_ = assemble_mass(mesh, geo_);
  laplacian_ = assemble_laplacian(mesh, geo_);
  const SparseMatrix H = M_ + (p.step() * p.kappa) * laplacian_;
  setup_timing_.assembly = seconds_since(t1);
  stage("assembly", setup_timing_.assembly);
  stage(fmt::format("factorization of K ({} x {}, {} nonzeros)", K_->matrix().rows(), K_->matrix().cols(),
                    K_->matrix().nonZeros()));
  t1 = Clock::now();
  K_factor_ = la::make_cholmod_factor("K");
  {
    // Refuse a run that cannot fit before the costly factorizations (issue 11);
    // the factors' sizes come from their symbolic analyses (K's is reused).
    const double mesh_bytes = 24.0 * mesh.n_nodes() + 4.0 * mesh.cell_array().size() +
                              (sizeof(CellGeometry) + 3.0 * sizeof(SymTensor)) * mesh.n_cells();
    const double matrix_bytes = 12.0 * (K_->matrix().nonZeros() + M_.nonZeros() + laplacian_.nonZeros() + 2.0 * H.nonZeros());
    check_memory(estimate_run_memory(mesh_bytes, matrix_bytes, *K_factor_->analyze(*K_, "elastic stiffness K"),
                                     estimate_cholmod_factor(H, "damage matrix H = M + k kappa A"),
                                     choice_.damage == "active-set",
                                     static_cast<double>(mesh.nodes_of_parts(p.contact.parts).size())),
                 memory_limit(choice_.memory_limit), p.name);
  }
  K_factor_->factorize(*K_, "elastic stiffness K");
  setup_timing_.factor_K = seconds_since(t1);
  stage("factorization of K", setup_timing_.factor_K);
  stage(fmt::format("factorization of H ({} x {}, {} nonzeros)", H.rows(), H.cols(), H.nonZeros()));
  t1 = Clock::now();
  damage_ = make_damage_solver(choice_.damage, H, 1e-13, 200000, choice_.damage_reduced);
  setup_timing_.factor_H = seconds_since(t1);
  stage("factorization of H", setup_timing_.factor_H);

  stage("contact set-up");
  t1 = Clock::now();
  setup_contact();
  ContactConstraints constraints{static_cast<int>(N_.rows()), {}, N_, gap_};
  for (int i = 0; i < constraints.m; ++i) constraints.rows.push_back(i);
  contact_ = make_contact_solver(choice_.contact, K_, K_factor_, std::move(constraints), la::make_cholmod_factor,
                                 choice_.contact_options);
  setup_timing_.contact = seconds_since(t1);
  stage("contact set-up", setup_timing_.contact);

  // Initial state (3.4): u0 = 0, σ0 = 0 (so z0 = σ0 − ℰε(u0) = 0), β0 = P1 interpolant
  // (in [0, 1]: Problem::validate).
  state_.u = Vector::Zero(dofs_.n_full());
  state_.beta.resize(mesh.n_nodes());
  for (int i = 0; i < mesh.n_nodes(); ++i) state_.beta[i] = p.beta0 ? p.beta0(mesh.node(i), 0.0) : 1.0;
  state_.sigma.assign(mesh.n_cells(), SymTensor{});
  state_.eps.assign(mesh.n_cells(), SymTensor{});
  state_.z.assign(mesh.n_cells(), SymTensor{});
  state_.lambda = Vector::Zero(static_cast<Eigen::Index>(contact_nodes_.size()));
  u_free_ = Vector::Zero(dofs_.n_free());
  setup_timing_.total = seconds_since(t0);
}

void TimeStepper::setup_contact() {
  const Problem& p = *problem_;
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim();
  std::vector<char> clamped(mesh.n_nodes(), 0);
  for (int node : mesh.nodes_of_parts(p.clamped)) clamped[node] = 1;
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> gaps;
  for (const ContactRow& r : contact_rows(p, clamped)) {
    const int row = static_cast<int>(contact_nodes_.size());
    for (int c = 0; c < d; ++c)
      if (r.direction[c] != 0) t.emplace_back(row, dofs_.free_index(dofs_.full_index(r.node, c)), r.direction[c]);
    contact_nodes_.push_back(r.node);
    contact_dir_.push_back(r.direction);
    gaps.push_back(r.gap);
  }
  N_.resize(static_cast<Eigen::Index>(contact_nodes_.size()), dofs_.n_free());
  N_.setFromTriplets(t.begin(), t.end());
  gap_ = Eigen::Map<Vector>(gaps.data(), static_cast<Eigen::Index>(gaps.size()));
}

double TimeStepper::factor_bytes() const { return K_factor_->factor_bytes() + damage_->factor_bytes(); }

double TimeStepper::model_bytes() const {
  const Mesh& m = problem_->mesh;
  const double matrices = 12.0 * (K_->matrix().nonZeros() + M_.nonZeros() + N_.nonZeros());  // value + row index
  const double mesh = 24.0 * m.n_nodes() + 4.0 * m.cell_array().size() + sizeof(CellGeometry) * geo_.size();
  const double state = 8.0 * (state_.u.size() + state_.beta.size() + u_free_.size()) +
                       3.0 * sizeof(SymTensor) * state_.sigma.size();
  return matrices + mesh + state;
}

int TimeStepper::n_factorizations() const { return K_factor_->n_factorizations() + damage_->n_factorizations(); }

Snapshot TimeStepper::snapshot() const {
  return {state_, u_free_, contact_->warm_state(), damage_->warm_state()};
}

void TimeStepper::restore(const Snapshot& s) {
  const bool same = s.state.u.size() == state_.u.size() && s.state.beta.size() == state_.beta.size() &&
                    s.state.sigma.size() == state_.sigma.size() && s.state.eps.size() == state_.eps.size() &&
                    s.state.z.size() == state_.z.size() && s.state.lambda.size() == state_.lambda.size() &&
                    s.u_free.size() == u_free_.size() && s.state.n >= 0 && s.state.n <= problem_->n_steps;
  require(same, "{}: the saved state does not fit this problem (a different mesh, case or step count?)",
          problem_->name);
  state_ = s.state;
  u_free_ = s.u_free;
  contact_->set_warm_state(s.contact_warm);
  damage_->set_warm_state(s.damage_warm);
}

DamageSolver& TimeStepper::damage_solver(int level) {
  if (level == 0) return *damage_;
  if (static_cast<int>(halved_damage_.size()) < level) halved_damage_.resize(level);
  auto& solver = halved_damage_[level - 1];
  if (!solver) {
    const double k = problem_->step() / (1 << level);
    solver = make_damage_solver(choice_.damage, SparseMatrix(M_ + (k * problem_->kappa) * laplacian_), 1e-13, 200000,
                                choice_.damage_reduced);
  }
  return *solver;
}

StepReport TimeStepper::step() {
  require(!done(), "{}: the run is already at the final time", problem_->name);
  const Problem& p = *problem_;
  const int n = state_.n + 1;
  // The grid time t_n = n k, exactly (sums of k would accumulate round-off).
  StepReport rep = advance_or_halve(0, n == p.n_steps ? p.final_time : n * p.step());
  state_.n = rep.n = n;
  return rep;
}

StepReport TimeStepper::advance_or_halve(int level, double t_end) {
  if (level >= choice_.max_halvings) return advance(level, t_end);
  const Snapshot before = snapshot();
  StepReport rep = advance(level, t_end);
  if (rep.ok) return rep;
  restore(before);
  const double t_mid = before.state.t + problem_->step() / (1 << (level + 1));
  const StepReport first = advance_or_halve(level + 1, t_mid);
  if (!first.ok) return first;
  rep = advance_or_halve(level + 1, t_end);
  rep.substeps += first.substeps;
  rep.seconds_sources += first.seconds_sources;
  rep.seconds_damage += first.seconds_damage;
  rep.seconds_contact += first.seconds_contact;
  rep.seconds_stress += first.seconds_stress;
  return rep;
}

Vector TimeStepper::load(double t) const {
  const Problem& p = *problem_;
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim();
  const bool f0_once = basis_integral_cells_.size() > 0, f2_once = basis_integral_traction_.size() > 0;
  Vector F = assemble_load(mesh, geo_, traction_facets_, f0_once ? nullptr : p.f0, f2_once ? nullptr : p.f2, t);
  for (auto [once, f, w] : {std::tuple{f0_once, &p.f0, &basis_integral_cells_},
                            std::tuple{f2_once, &p.f2, &basis_integral_traction_}}) {
    if (!once) continue;
    const Point v = (*f)(Point{0, 0, 0}, t);
    for (int a = 0; a < mesh.n_nodes(); ++a)
      for (int i = 0; i < d; ++i) F[a * d + i] += v[i] * (*w)[a];
  }
  return F;
}

StepReport TimeStepper::advance(int level, double t_end) {
  const Problem& p = *problem_;
  const Mesh& mesh = p.mesh;
  const int n_cells = mesh.n_cells();
  const double k = p.step() / (1 << level);
  StepReport rep;
  rep.n = state_.n + 1;
  rep.t = t_end;

  // Step 1: lagged sources G_{n−1}, φ_{n−1} per element, β at the centroid.
  auto t0 = Clock::now();
  std::vector<SymTensor> G(n_cells);
  std::vector<double> phi(n_cells);
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    const PointState s{state_.sigma[c], state_.eps[c], cell_mean(mesh, state_.beta, c), p.elasticity.stress_dim(),
                       mesh.cell_centroid(c), state_.t};
    G[c] = p.law->rate(s);
    p.elasticity.restrict_stress(G[c]);
    phi[c] = p.source->rate(s);
  }
  rep.seconds_sources = seconds_since(t0);

  // Step 2: damage (3.8): the box QP with H = M + kκA, r = M β_{n−1} + k F_φ.
  t0 = Clock::now();
  const Vector rhs = M_ * state_.beta + k * assemble_p0_source(mesh, geo_, phi);
  rep.damage = damage_solver(level).solve(rhs, state_.beta);
  rep.seconds_damage = seconds_since(t0);

  // Step 3: history (3.6): z_n = z_{n−1} + k G_{n−1}.
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) state_.z[c] += k * G[c];

  // Step 4: contact (3.9): K u_n = F_n − Bᵀz_n − Nᵀλ with Signorini conditions.
  t0 = Clock::now();
  const Vector F = restrict_to_free(dofs_, load(rep.t) - assemble_stress_divergence(mesh, geo_, state_.z));
  rep.contact = contact_->solve(F, u_free_, state_.lambda);
  state_.u = extend_from_free(dofs_, u_free_);
  rep.seconds_contact = seconds_since(t0);

  // Step 5: stress (3.6): σ_n = ℰε(u_n) + z_n.
  t0 = Clock::now();
  compute_strain(mesh, geo_, state_.u, state_.eps);
  double max_vm = 0;
#pragma omp parallel for schedule(static) reduction(max : max_vm) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    state_.sigma[c] = p.elasticity.apply(state_.eps[c]) + state_.z[c];
    max_vm = std::max(max_vm, state_.sigma[c].von_mises());
  }
  rep.max_von_mises = max_vm;
  rep.seconds_stress = seconds_since(t0);

  const MinimumAt lo = minimum_at({state_.beta.data(), static_cast<std::size_t>(state_.beta.size())});
  rep.beta_min = lo.value;
  rep.beta_min_node = lo.index;
  rep.beta_max = state_.beta.maxCoeff();
  state_.t = rep.t;  // state_.n is the grid step: step() sets it

  const double tol = choice_.residual_tolerance;
  rep.ok = rep.contact.converged && rep.damage.converged && rep.contact.residuals.max() <= tol &&
           rep.damage.kkt_residual <= tol && std::isfinite(state_.u.norm()) && std::isfinite(state_.beta.norm());
  return rep;
}

}  // namespace vpc
