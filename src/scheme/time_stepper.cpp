#include "scheme/time_stepper.hpp"

#include "core/error.hpp"
#include "scheme/contact_gap.hpp"
#include "scheme/pair_slider.hpp"
#include "scheme/step_data.hpp"
#include "scheme/surface_fields.hpp"

#include <chrono>
#include <utility>

namespace vpc {

namespace {

/// The problem's one-process part, after Problem::validate (which throws for a bad datum), cut with
/// the contact rows its checks built.
MeshPart validated_whole_part(const std::shared_ptr<const Problem>& p) { return whole_mesh_part(p, p->validate()); }

}  // namespace

TimeStepper::TimeStepper(std::shared_ptr<const Problem> problem, SolverChoice choice)
    : TimeStepper(problem, validated_whole_part(problem), la::serial_backend(), std::move(choice)) {}

TimeStepper::TimeStepper(std::shared_ptr<const Problem> problem_in, MeshPart part_in,
                         std::shared_ptr<const la::Backend> backend_in, SolverChoice choice)
    : choice_(std::move(choice)),
      sys_(std::move(problem_in), std::move(part_in), std::move(backend_in), choice_),
      slider_(make_pair_slider(sys_)),
      solvers_(set_up_solvers(sys_, choice_, *slider_, setup_timing_, solver_cost_)),
      step_(sys_.part, sys_.problem->contact) {
  const auto t0 = std::chrono::steady_clock::now();
  const Problem& p = *sys_.problem;
  const MeshPart& part = sys_.part;
  const Mesh& mesh = part.mesh();
  setup_timing_.assembly = sys_.assembly_seconds;
  setup_timing_.mesh = sys_.mesh_memory;
  setup_timing_.assembled = sys_.assembly_memory;
  // Initial state (3.4): u0 = 0, σ0 = 0 (so z0 = σ0 − ℰε(u0) = 0), β0 = P1 interpolant
  // (in [0, 1]: Problem::validate).
  state_.u = Vector::Zero(part.dofs.n_full());
  state_.beta = p.initial_damage(mesh, part.cell_body);
  state_.sigma.assign(mesh.n_cells(), SymTensor{});
  state_.eps.assign(mesh.n_cells(), SymTensor{});
  state_.z.assign(mesh.n_cells(), SymTensor{});
  state_.contact_block = p.contact.block_size(mesh.dim());  // the contact laws' block (1: normal laws)
  state_.lambda = Vector::Zero(part.n_contact * state_.contact_block);
  if (state_.contact_block > 1) {
    state_.slip_step = Vector::Zero(part.n_contact * (state_.contact_block - 1));
    state_.slip = Vector::Zero(part.n_contact);
    state_.contact_status = Vector::Zero(part.n_contact);
  }
  state_.surface = initial_surface_state(p.contact, part.n_contact);
  if (!state_.surface.empty()) set_initial_surface_state(sys_, checked_contact_gap(sys_, state_.t), state_);
  u_free_ = Vector::Zero(part.n_owned_dofs);
  if (records_gap(sys_)) record_gap_left(sys_, checked_contact_gap(sys_, state_.t), state_);
  const auto owned_beta = state_.beta.head(part.n_owned_nodes).array();
  control_state_.n_beta_zero = part.comm.sum(static_cast<double>((owned_beta <= 0).count()));
  control_state_.n_beta_one = part.comm.sum(static_cast<double>((owned_beta >= 1).count()));
  setup_timing_.total = sys_.build_seconds + setup_timing_.factor_K + setup_timing_.factor_H + setup_timing_.contact +
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

StepReport TimeStepper::step() {
  const Problem& p = problem();
  require(!done(), "{}: the run is already at the final time", p.name);
  const int n = state_.n + 1;
  StepReport rep = p.step_control ? controlled_step(attempts(), *sys_.control, control_state_, p.final_time)
                                  : advance_or_halve(attempts(), 0, choice_.max_halvings, p.step_at(n), p.time_at(n));
  state_.n = rep.n = n;
  times_.push_back(state_.t);
  backstop_.check_accepted(sys_, state_, rep);
  control_state_.accept(rep);
  return rep;
}

StepReport TimeStepper::advance(double k, double t_end) {
  slide();  // large sliding: the rows at x + u_{n−1}
  StepTaken taken = step_.take(sys_, solvers_, choice_, state_, u_free_, k, t_end);  // SPEC §2's steps 1–5
  StepReport& rep = taken.report;
  auto t0 = std::chrono::steady_clock::now();
  report_step(sys_, state_, taken.data.F, rep);
  rep.seconds_stress += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // G_n, φ_n: the error estimate's, then the next step's step 1.
  t0 = std::chrono::steady_clock::now();
  const LaggedRates& now = step_.rates(sys_, state_);
  la::collective(comm(), [&] { check_formulas(problem()); });  // φ_n finite (issue 26)
  ErrorEstimate e = estimate_error(sys_, state_, taken, now, k, backstop_.last(), control_state_.sigma_scale);
  rep.error_estimate = e.error;
  rep.sigma_norm = e.sigma_norm;
  backstop_.attempted(std::move(e.dG), e.dG2, e.dG_dot_last);
  rep.seconds_sources += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  rep.ok = step_accepted(comm(), rep, choice_.residual_tolerance, u_free_,
                         state_.beta.head(sys_.part.n_owned_nodes));
  return rep;
}

StepAttempts TimeStepper::attempts() {
  return {[this](double k, double t_end) { return advance(k, t_end); }, [this] { return snapshot(); },
          [this](const Snapshot& s) { restore(s); }};
}

const la::LinearSolver& TimeStepper::stiffness_factor() {
  if (!solvers_.K_factor) {
    solvers_.K_factor = sys_.make_stiffness_factor();
    solvers_.K_factor->factorize(*sys_.K, "elastic stiffness K");
  }
  return *solvers_.K_factor;
}

double TimeStepper::factor_bytes() const {
  const la::LinearSolver* contact = solvers_.contact->own_factor();
  return (solvers_.K_factor ? solvers_.K_factor->factor_bytes() : 0.0) + (contact ? contact->factor_bytes() : 0.0) +
         solvers_.damage.factor_bytes();
}

double TimeStepper::model_bytes() const {
  const Mesh& m = mesh();
  // K and M as operators, M and A kept locally for halved steps (value + row index).
  const double matrices = 12.0 * (sys_.K_local_nonzeros + 2.0 * sys_.M_local.nonZeros() + sys_.A_local.nonZeros());
  const double mesh = 24.0 * m.n_nodes() + 4.0 * m.cell_array().size() + sizeof(CellGeometry) * sys_.geo.size();
  const double state = 8.0 * (state_.u.size() + state_.beta.size() + u_free_.size()) +
                       3.0 * sizeof(SymTensor) * state_.sigma.size();
  return matrices + mesh + state;
}

int TimeStepper::n_factorizations() const {
  const la::LinearSolver* contact = solvers_.contact->own_factor();
  return (solvers_.K_factor ? solvers_.K_factor->n_factorizations() : 0) +
         (contact ? contact->n_factorizations() : 0) + solvers_.damage.n_factorizations();
}

long long TimeStepper::n_linear_iterations() const {
  const la::LinearSolver* contact = solvers_.contact->own_factor();
  return (solvers_.K_factor ? solvers_.K_factor->iterations() : 0) + (contact ? contact->iterations() : 0);
}

Snapshot TimeStepper::snapshot() const {
  return {state_, u_free_, solvers_.contact->warm_state(), solvers_.damage.current().warm_state()};
}

std::pair<double, double> TimeStepper::data_mismatch() const {
  double prescribed = 0, penetration = 0;
  const Vector u_D = prescribed_displacement(sys_, state_.t);
  const std::vector<int>& condition = sys_.part.dirichlet;
  for (std::size_t i = 0; i < condition.size(); ++i)
    if (condition[i] >= 0)
      prescribed = std::max(prescribed, std::abs(state_.u[static_cast<Eigen::Index>(i)] -
                                                 (u_D.size() ? u_D[static_cast<Eigen::Index>(i)] : 0.0)));
  if (sys_.part.n_contact > 0) {
    const Vector left = rows_gap_left(sys_, checked_contact_gap(sys_, state_.t), state_);
    if (left.size() > 0) penetration = std::max(0.0, -left.minCoeff());
  }
  return {comm().max(prescribed), comm().max(penetration)};
}

Vector TimeStepper::contact_warm_state() const { return solvers_.contact->warm_state(); }
Vector TimeStepper::damage_warm_state() const { return solvers_.damage.current().warm_state(); }

void TimeStepper::slide() {
  // The one change to the discrete system after set-up: its contact set, replaced, never edited.
  if (std::shared_ptr<const ContactSet> moved = slider_->slide(sys_, state_.u)) {
    sys_.contact = std::move(moved);
    remake_contact_solver(sys_, choice_, solvers_, slider_->stiffness());
  }
}

void TimeStepper::restore(const Snapshot& s) {
  require(snapshot_fits(s, state_, u_free_.size(), problem()),
          "{}: the saved state does not fit this problem (a different mesh, case or step count?)", problem().name);
  state_ = s.state;
  u_free_ = s.u_free;
  slide();  // the rows at x + u_{n−1} of the restored state
  if (records_gap(sys_)) record_gap_left(sys_, checked_contact_gap(sys_, state_.t), state_);
  solvers_.contact->set_warm_state(s.contact_warm);
  solvers_.damage.current().set_warm_state(s.damage_warm);
  step_.forget_rates();  // recomputed from the restored state: the same values
}

void TimeStepper::set_step_history(std::vector<double> times, const StepControlState& c) {
  require(times.size() == static_cast<std::size_t>(state_.n) + 1 && times.front() == 0 && times.back() == state_.t,
          "{}: the saved time levels do not end at the state's step {} (t = {})", problem().name, state_.n, state_.t);
  times_ = std::move(times);
  control_state_ = c;
}

}  // namespace vpc
