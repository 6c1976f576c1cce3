#include "verification/convergence.hpp"

#include "core/error.hpp"
#include "core/stopwatch.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/state_fields.hpp"
#include "scheme/step_failure.hpp"
#include "verification/refine.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>

namespace vpc {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void log_line(const std::function<void(const std::string&)>& log, const std::string& s) {
  if (log) log(s);
}

/// Elementwise maximum of two sets of norms (β gradient excluded: it is summed).
void take_max(ErrorNorms& acc, const ErrorNorms& e) {
  acc.u_energy = std::max(acc.u_energy, e.u_energy);
  acc.u_l2 = std::max(acc.u_l2, e.u_l2);
  acc.sigma_l2 = std::max(acc.sigma_l2, e.sigma_l2);
  acc.beta_l2 = std::max(acc.beta_l2, e.beta_l2);
  acc.contact_force = std::max(acc.contact_force, e.contact_force);
}

/// One run of the scheme inside a study, with what is accumulated about it.
struct LevelRun {
  int level = 0;       // position in the study (the reference is last)
  int mesh_level = 0;  // level in the mesh hierarchy
  std::shared_ptr<const Problem> problem;
  std::unique_ptr<TimeStepper> stepper;
  std::unique_ptr<DiscreteNorms> norms;
  LevelResult result;
  ErrorNorms err_max, diff_max;
  double err_grad_sum = 0, diff_grad_sum = 0;
  double contact_iter_sum = 0, damage_iter_sum = 0;
  int n_stepped = 0;
  bool stepped_now = false;
  State gathered;  // a distributed stepper's state on rank 0, in the numbering of the level's mesh

  bool distributed() const { return stepper->backend().engine() == "petsc"; }
  const State& state() const { return distributed() ? gathered : stepper->state(); }
  int n_steps() const { return problem->n_steps; }
  /// After set-up and each step: a distributed state to rank 0. Collective.
  void gather() {
    if (distributed()) gathered = gather_snapshot(*stepper).state;
  }
};

/// Norms of (fine − prolonged coarse) on the fine run's mesh at the current time.
ErrorNorms compare_runs(const LevelRun& coarse, const LevelRun& fine, const MeshHierarchy& meshes) {
  const int d = fine.problem->mesh.dim();
  const State& c = coarse.state();
  const State& f = fine.state();
  ErrorNorms e;
  const Vector du = f.u - meshes.prolong_p1(c.u, coarse.mesh_level, fine.mesh_level, d);
  const Vector db = f.beta - meshes.prolong_p1(c.beta, coarse.mesh_level, fine.mesh_level, 1);
  std::vector<SymTensor> ds = meshes.prolong_p0(c.sigma, coarse.mesh_level, fine.mesh_level);
  for (size_t i = 0; i < ds.size(); ++i) ds[i] = f.sigma[i] - ds[i];
  e.u_energy = fine.norms->energy(du);
  e.u_l2 = fine.norms->l2_vector(du);
  e.sigma_l2 = fine.norms->l2(ds);
  e.beta_l2 = fine.norms->l2(db);
  e.beta_grad = fine.norms->h1_seminorm(db);
  e.contact_force = std::abs(normal_forces(f).sum() - normal_forces(c).sum());  // λ's normal force per node
  return e;
}

ErrorNorms compare_exact(const LevelRun& run, const ExactSolution& exact, const std::vector<QuadraturePoint>& rule) {
  const FieldErrors fe = errors_against_exact(run.problem->mesh, run.norms->geometry(), run.problem->elasticity,
                                              run.state(), exact, run.state().t, rule);
  ErrorNorms e;
  e.u_energy = fe.u_energy;
  e.u_l2 = fe.u_l2;
  e.sigma_l2 = fe.sigma_l2;
  e.beta_l2 = fe.beta_l2;
  e.beta_grad = fe.beta_grad;
  e.contact_force = kNaN;
  return e;
}

void fill_sizes(LevelResult& r, const LevelRun& run) {
  const Mesh& m = run.problem->mesh;
  r.level = run.level;
  r.h = m.size_range().second;
  r.k = run.problem->largest_step();  // k = max k_n (Theorem 3.5)
  r.n_cells = m.n_cells();
  r.n_nodes = m.n_nodes();
  r.n_free_dofs = static_cast<int>(run.stepper->part().n_global_dofs);
  r.n_contact_nodes = run.stepper->part().n_contact;
  r.n_steps = run.n_steps();
}

/// Advances a run by one step and records its solver statistics. A failed step
/// (a solver did not converge or a residual is above tolerance) is an error when
/// `strict`, else it is counted.
void advance(LevelRun& run, bool strict = true) {
  const auto t0 = Clock::now();
  const StepReport rep = run.stepper->step();
  run.result.seconds += seconds_since(t0);
  if (!rep.ok) ++run.result.n_failed_steps;
  require(rep.ok || !strict, "convergence study: level {} step {} (t = {}) failed: {}", run.level, rep.n, rep.t,
          step_failure(rep, run.stepper->solvers().residual_tolerance));
  run.gather();
  ++run.n_stepped;
  run.result.n_rejected += rep.rejected;
  if (run.problem->step_control) {  // error-controlled: the steps taken and the largest
    run.result.n_steps = run.n_stepped;
    run.result.k = std::max(run.result.k, rep.k);
  }
  run.contact_iter_sum += rep.contact.iterations;
  run.damage_iter_sum += rep.damage.iterations;
  run.result.contact_iterations.max = std::max(run.result.contact_iterations.max, rep.contact.iterations);
  run.result.damage_iterations.max = std::max(run.result.damage_iterations.max, rep.damage.iterations);
  run.result.max_active_contact = std::max(run.result.max_active_contact, rep.contact.n_active);
  if (run.n_stepped > 1 && rep.contact.n_active != run.result.active_contact) ++run.result.contact_set_changes;
  if (run.n_stepped > 1 && (rep.damage.n_lower != run.result.beta_at_zero || rep.damage.n_upper != run.result.beta_at_one))
    ++run.result.damage_set_changes;
  run.result.beta_at_zero = rep.damage.n_lower;
  run.result.beta_at_one = rep.damage.n_upper;
  run.result.active_contact = rep.contact.n_active;
}

void finish(LevelRun& run) {
  run.result.contact_iterations.mean = run.n_stepped ? run.contact_iter_sum / run.n_stepped : 0;
  run.result.damage_iterations.mean = run.n_stepped ? run.damage_iter_sum / run.n_stepped : 0;
}

std::string g(double v) { return std::isfinite(v) ? fmt::format("{:.3e}", v) : std::string("nan"); }
std::string r2(double v) { return std::isfinite(v) ? fmt::format("{:.2f}", v) : std::string("-"); }

}  // namespace

std::string to_string(RefinementSequence s) {
  switch (s) {
    case RefinementSequence::HK: return "hk";
    case RefinementSequence::H: return "h";
    default: return "k";
  }
}

RefinementSequence refinement_sequence_from_name(const std::string& name) {
  if (name == "hk") return RefinementSequence::HK;
  if (name == "h") return RefinementSequence::H;
  if (name == "k") return RefinementSequence::K;
  fail("unknown refinement sequence '{}'; expected hk (h and k halved together), h or k", name);
}

ProblemFactory same_data_on(std::shared_ptr<const Problem> base) {
  return [base](const Mesh& mesh, int n_steps) {
    auto p = std::make_shared<Problem>(*base);
    p->mesh = mesh;
    p->n_steps = n_steps;
    p->step_control.reset();
    p->step_times.clear();
    p->step_sizes.clear();
    if (!base->step_times.empty()) {  // each step of the base grid split into `split` equal steps
      const int split = n_steps / base->n_steps;
      require(split >= 1 && split * base->n_steps == n_steps,
              "convergence study: {} steps do not refine the case's grid of {} steps", n_steps, base->n_steps);
      FixedGrid g;
      for (int n = 1; n <= base->n_steps; ++n) {
        const double a = base->time_at(n - 1), b = base->time_at(n), k = base->step_at(n) / split;
        for (int j = 1; j < split; ++j) g.times.push_back(a + j * k);
        g.times.push_back(b);
        g.sizes.insert(g.sizes.end(), static_cast<std::size_t>(split), k);
      }
      p->set_fixed_grid(std::move(g));
    }
    return std::shared_ptr<const Problem>(p);
  };
}

const std::vector<std::string>& ErrorNorms::names() {
  static const std::vector<std::string> n = {"u_energy", "u_l2", "sigma_l2", "beta_l2", "beta_grad", "contact_force"};
  return n;
}

std::vector<double> ErrorNorms::values() const { return {u_energy, u_l2, sigma_l2, beta_l2, beta_grad, contact_force}; }

double ConvergenceResult::rate(const std::vector<LevelResult>& of, int l,
                               const std::function<double(const LevelResult&)>& value) const {
  if (l <= 0 || l >= static_cast<int>(of.size())) return kNaN;
  const double e0 = value(of[l - 1]), e1 = value(of[l]);
  const bool by_k = sequence == RefinementSequence::K;
  auto parameter = [&](const LevelResult& L) { return by_k ? (L.tolerance > 0 ? L.tolerance : L.k) : L.h; };
  const double p0 = parameter(of[l - 1]), p1 = parameter(of[l]);
  if (!(e0 > 0) || !(e1 > 0) || !std::isfinite(e0) || !std::isfinite(e1) || !(p0 > p1)) return kNaN;
  return std::log(e0 / e1) / std::log(p0 / p1);
}

ConvergenceResult run_convergence(const std::string& case_name, const Mesh& base_mesh, const ProblemFactory& factory,
                                  std::shared_ptr<const ExactSolution> exact, const ConvergenceOptions& o) {
  const auto t_start = Clock::now();
  require(o.levels >= 2, "convergence study: at least 2 levels are needed to measure a rate (got {})", o.levels);
  require(o.levels <= 8, "convergence study: at most 8 levels (got {})", o.levels);
  require(exact || o.reference_offset >= 1, "convergence study: the reference must be finer than every level");
  require(o.base_steps >= 1, "convergence study: the base number of steps must be >= 1 (got {})", o.base_steps);
  // Runs: the fixed-grid levels, the error-controlled levels (if any), the reference.
  const bool controlled = o.step_control.has_value();
  const int n_fixed = o.levels, n_measured = controlled ? 2 * o.levels : o.levels;
  const int n_runs = n_measured + (exact ? 0 : 1);
  const int ref_level = o.levels - 1 + o.reference_offset;  // study level of the reference
  const bool refine_h = o.sequence != RefinementSequence::K;
  const bool refine_k = o.sequence != RefinementSequence::H;
  const int max_level = exact ? o.levels - 1 : ref_level;
  const MeshHierarchy meshes(base_mesh, refine_h ? max_level : 0);
  // The base grid's times: where every run is compared when some levels control their steps.
  const std::shared_ptr<const Problem> base = factory(meshes.mesh(0), o.base_steps);
  std::vector<double> base_times;
  for (int n = 1; n <= o.base_steps; ++n) base_times.push_back(base->time_at(n));

  std::vector<LevelRun> runs(n_runs);
  for (int i = 0; i < n_runs; ++i) {
    LevelRun& r = runs[i];
    const bool adaptive = i >= n_fixed && i < n_measured;
    r.level = i < n_measured ? i % o.levels : ref_level;
    r.mesh_level = refine_h ? r.level : 0;
    const long n_steps = static_cast<long>(o.base_steps) << (refine_k && !adaptive ? r.level : 0);
    require(n_steps <= 1 << 22, "convergence study: level {} would need {} time steps", r.level, n_steps);
    const auto t0 = Clock::now();
    r.problem = factory(meshes.mesh(r.mesh_level), static_cast<int>(n_steps));
    if (adaptive) {  // tolerance / 2^l, landing on the base grid's times
      auto p = std::make_shared<Problem>(*r.problem);
      StepControl c = *o.step_control;
      c.tolerance /= refine_k ? 1 << r.level : 1;
      c.landings.insert(c.landings.end(), base_times.begin(), base_times.end());
      p->step_control = c.completed(p->final_time);
      p->n_steps = 0;
      p->step_times.clear();
      p->step_sizes.clear();
      r.problem = p;
    }
    r.stepper = o.make_stepper ? o.make_stepper(r.problem, o.solvers) : std::make_unique<TimeStepper>(r.problem, o.solvers);
    r.gather();
    r.norms = std::make_unique<DiscreteNorms>(r.problem->mesh, r.problem->elasticity);
    fill_sizes(r.result, r);
    if (adaptive) {
      r.result.tolerance = r.problem->step_control->tolerance;
      r.result.k = r.result.n_steps = 0;  // the steps it takes
    }
    log_line(o.log, fmt::format("  {} level {}: {} cells, {} free dofs, {} contact nodes, h = {:.4g}, {} "
                                "(setup {:.2f} s)",
                                i < n_measured ? (adaptive ? "error-controlled" : "run") : "reference", r.level,
                                r.result.n_cells, r.result.n_free_dofs, r.result.n_contact_nodes, r.result.h,
                                adaptive ? fmt::format("tolerance {:.4g}", r.result.tolerance)
                                         : fmt::format("k = {:.4g}", r.result.k),
                                seconds_since(t0)));
  }
  const int d = base_mesh.dim();
  const int qm = o.quadrature_points > 0 ? o.quadrature_points : (d <= 2 ? 3 : 2);
  const std::vector<QuadraturePoint> rule = conical_product_rule(d, qm);
  // The run each measured one is compared with for the differences of consecutive levels:
  // the next level of its kind, the reference after the last (none against an exact solution).
  auto next_of = [&](int i) {
    const int end = i < n_fixed ? n_fixed : n_measured;
    return i + 1 < end ? i + 1 : (exact ? -1 : n_runs - 1);
  };

  // The comparisons made whenever a measured run reaches one of its time levels (or, with
  // error-controlled levels, one of the base grid's times), where the states are: on rank
  // 0 of a distributed study. `k`: the weight of the time level in the β gradient's sum.
  const bool root = runs.front().stepper->comm().rank() == 0;
  auto compare = [&](int i, bool at_start, double k) {
    if (!root) return;
    LevelRun& r = runs[i];
    const ErrorNorms e = exact ? compare_exact(r, *exact, rule) : compare_runs(r, runs.back(), meshes);
    take_max(r.err_max, e);
    if (!at_start) r.err_grad_sum += k * e.beta_grad * e.beta_grad;
    if (const int j = next_of(i); j >= 0) {
      const LevelRun& next = runs[j];
      require(std::abs(next.state().t - r.state().t) <= 1e-9 * r.problem->final_time,
              "convergence study: levels {} and {} are at different times", r.level, next.level);
      const ErrorNorms dn = compare_runs(r, next, meshes);
      take_max(r.diff_max, dn);
      if (!at_start) r.diff_grad_sum += k * dn.beta_grad * dn.beta_grad;
    }
  };

  for (int i = 0; i < n_measured; ++i) compare(i, true, 0);
  if (controlled) {
    double before = 0;
    for (std::size_t j = 0; j < base_times.size(); ++j) {
      const double t = base_times[j];
      for (LevelRun& r : runs)
        while (!r.stepper->done() && r.stepper->state().t < t - 1e-12 * base->final_time) advance(r);
      for (int i = 0; i < n_measured; ++i) compare(i, false, t - before);
      before = t;
      log_line(o.log, fmt::format("  t = {:.4g} ({}/{} base times, {:.1f} s)", t, j + 1, base_times.size(),
                                  seconds_since(t_start)));
    }
  } else {
    int n_fine = 0;
    for (const LevelRun& r : runs) n_fine = std::max(n_fine, r.n_steps());
    const int report_every = std::max(1, n_fine / 10);
    for (int m = 1; m <= n_fine; ++m) {
      for (LevelRun& r : runs) {
        r.stepped_now = m % (n_fine / r.n_steps()) == 0;
        if (r.stepped_now) advance(r);
      }
      for (int i = 0; i < o.levels; ++i)
        if (runs[i].stepped_now) compare(i, false, runs[i].problem->step_at(runs[i].stepper->state().n));
      if (m % report_every == 0)
        log_line(o.log, fmt::format("  t = {:.4g} ({}/{} fine steps, {:.1f} s)", runs.back().stepper->state().t, m,
                                    n_fine, seconds_since(t_start)));
    }
  }

  ConvergenceResult out;
  out.case_name = case_name;
  out.sequence = o.sequence;
  out.exact = exact != nullptr;
  out.at_base_times = controlled;
  for (int i = 0; i < n_runs; ++i) {
    LevelRun& r = runs[i];
    finish(r);
    r.result.error = r.err_max;
    r.result.error.beta_grad = std::sqrt(r.err_grad_sum);
    r.result.difference = r.diff_max;
    r.result.difference.beta_grad = std::sqrt(r.diff_grad_sum);
    if (i >= n_measured || next_of(i) < 0) r.result.difference = ErrorNorms{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
    if (exact) {
      r.result.difference.contact_force = kNaN;
      r.result.error.contact_force = kNaN;
    }
    if (i < n_fixed)
      out.levels.push_back(r.result);
    else if (i < n_measured)
      out.adaptive.push_back(r.result);
    else
      out.reference = r.result;
  }
  out.seconds = seconds_since(t_start);
  return out;
}

namespace {

const char* sequence_words(RefinementSequence s) {
  switch (s) {
    case RefinementSequence::HK: return "h and k halved together";
    case RefinementSequence::H: return "h halved, k fixed";
    default: return "k halved, h fixed";
  }
}

const std::vector<std::string>& norm_titles() {
  static const std::vector<std::string> t = {"|u|_E", "|u|_L2", "|sig|_L2", "|beta|_L2", "grad beta", "force"};
  return t;
}

double pick(const ErrorNorms& e, size_t j) { return e.values()[j]; }

}  // namespace

std::string format_convergence_table(const ConvergenceResult& r) {
  std::string s;
  const size_t n_norms = r.exact ? 5 : 6;
  s += fmt::format("{}: {}; errors against {}\n", r.case_name, sequence_words(r.sequence),
                   r.exact ? std::string("the exact solution")
                           : fmt::format("the reference (level {}: h = {:.4g}, k = {:.4g}, {} free dofs)",
                                         r.reference.level, r.reference.h, r.reference.k, r.reference.n_free_dofs));
  auto table = [&](const char* title, bool diff) {
    s += fmt::format("{}\n{:>3} {:>9} {:>9} {:>6} {:>8}", title, "lvl", "h", "k", "N", "dofs");
    for (size_t j = 0; j < n_norms; ++j) s += fmt::format(" | {:>9} {:>5}", norm_titles()[j], "rate");
    s += "\n";
    for (size_t l = 0; l < r.levels.size(); ++l) {
      const LevelResult& L = r.levels[l];
      if (diff && l + 1 == r.levels.size() && r.exact) break;
      s += fmt::format("{:>3} {:>9.3e} {:>9.3e} {:>6} {:>8}", L.level, L.h, L.k, L.n_steps, L.n_free_dofs);
      for (size_t j = 0; j < n_norms; ++j) {
        const auto value = [&](const LevelResult& x) { return pick(diff ? x.difference : x.error, j); };
        s += fmt::format(" | {:>9} {:>5}", g(value(L)), r2(r.rate(static_cast<int>(l), value)));
      }
      s += "\n";
    }
  };
  const char* over = r.at_base_times ? "max over the base grid's times" : "max over n";
  table(fmt::format("{} ({}; grad beta: (k sum_n |grad e_n|^2)^1/2):",
                    r.exact ? "errors" : "errors against the reference", over).c_str(),
        false);
  table("differences of consecutive levels |w_l - w_{l+1}| (their rates are free of the reference's bias):", true);
  if (!r.adaptive.empty()) {
    s += fmt::format("error-controlled levels ({}; N: steps taken, rej: rejected, k: largest step; rates against "
                     "{}):\n{:>3} {:>9} {:>9} {:>9} {:>6} {:>5}",
                     over, r.sequence == RefinementSequence::K ? "the tolerance" : "h", "lvl", "h", "tolerance", "k",
                     "N", "rej");
    for (size_t j = 0; j < n_norms; ++j) s += fmt::format(" | {:>9} {:>5}", norm_titles()[j], "rate");
    s += "\n";
    for (size_t l = 0; l < r.adaptive.size(); ++l) {
      const LevelResult& L = r.adaptive[l];
      s += fmt::format("{:>3} {:>9.3e} {:>9.3e} {:>9.3e} {:>6} {:>5}", L.level, L.h, L.tolerance, L.k, L.n_steps,
                       L.n_rejected);
      for (size_t j = 0; j < n_norms; ++j) {
        const auto value = [&](const LevelResult& x) { return pick(x.error, j); };
        s += fmt::format(" | {:>9} {:>5}", g(value(L)), r2(r.rate(r.adaptive, static_cast<int>(l), value)));
      }
      s += "\n";
    }
  }
  s += fmt::format("{:>3} {:>8} {:>6} {:>8} {:>6} {:>7} {:>7} {:>7} {:>7} {:>8} {:>8} {:>8}\n", "lvl", "contact",
                   "max", "damage", "max", "active", "act(T)", "act.chg", "bnd.chg", "beta=0", "beta=1", "seconds");
  auto iter_row = [&](const LevelResult& L, const std::string& name) {
    s += fmt::format("{:>3} {:>8.2f} {:>6} {:>8.2f} {:>6} {:>7} {:>7} {:>7} {:>7} {:>8} {:>8} {:>8.2f}\n", name,
                     L.contact_iterations.mean, L.contact_iterations.max, L.damage_iterations.mean,
                     L.damage_iterations.max, L.max_active_contact, L.active_contact, L.contact_set_changes,
                     L.damage_set_changes, L.beta_at_zero, L.beta_at_one, L.seconds);
  };
  for (const auto& L : r.levels) iter_row(L, std::to_string(L.level));
  if (!r.exact) iter_row(r.reference, "ref");
  s += fmt::format("(solver iterations per step, mean and max; active: most active contact nodes, act(T) at T; "
                   "act.chg/bnd.chg: steps where the number of active contact nodes / of nodes at beta = 0 or 1 "
                   "changed; beta=0, beta=1: nodes at the bounds at T; total {:.1f} s)\n",
                   r.seconds);
  return s;
}

void write_convergence_csv(const ConvergenceResult& r, const std::string& path, bool adaptive) {
  std::string s = fmt::format("# case={} sequence={} against={}\n", r.case_name, to_string(r.sequence),
                              r.exact ? "exact" : fmt::format("reference-level-{}", r.reference.level));
  s += "level,h,k,n_steps,n_cells,n_nodes,n_free_dofs,n_contact_nodes";
  for (const auto& n : ErrorNorms::names()) s += fmt::format(",err_{0},rate_{0}", n);
  for (const auto& n : ErrorNorms::names()) s += fmt::format(",diff_{0},diff_rate_{0}", n);
  s += ",contact_iter_mean,contact_iter_max,damage_iter_mean,damage_iter_max,max_active_contact,active_contact,"
       "contact_set_changes,damage_set_changes,beta_at_zero,beta_at_one,seconds,tolerance,n_rejected\n";
  const std::vector<LevelResult>& levels = adaptive ? r.adaptive : r.levels;
  auto row = [&](const LevelResult& L, int index, bool is_reference) {
    s += fmt::format("{},{:.17g},{:.17g},{},{},{},{},{}", is_reference ? std::string("ref") : std::to_string(L.level),
                     L.h, L.k, L.n_steps, L.n_cells, L.n_nodes, L.n_free_dofs, L.n_contact_nodes);
    for (size_t j = 0; j < ErrorNorms::names().size(); ++j) {
      const auto v = [&](const LevelResult& x) { return pick(x.error, j); };
      s += fmt::format(",{:.10e},{:.6f}", is_reference ? kNaN : v(L), is_reference ? kNaN : r.rate(levels, index, v));
    }
    for (size_t j = 0; j < ErrorNorms::names().size(); ++j) {
      const auto v = [&](const LevelResult& x) { return pick(x.difference, j); };
      s += fmt::format(",{:.10e},{:.6f}", is_reference ? kNaN : v(L), is_reference ? kNaN : r.rate(levels, index, v));
    }
    s += fmt::format(",{:.4f},{},{:.4f},{},{},{},{},{},{},{},{:.3f},{:.6g},{}\n", L.contact_iterations.mean,
                     L.contact_iterations.max, L.damage_iterations.mean, L.damage_iterations.max, L.max_active_contact,
                     L.active_contact, L.contact_set_changes, L.damage_set_changes, L.beta_at_zero, L.beta_at_one,
                     L.seconds, L.tolerance, L.n_rejected);
  };
  for (size_t l = 0; l < levels.size(); ++l) row(levels[l], static_cast<int>(l), false);
  if (!r.exact) row(r.reference, -1, true);
  write_file_atomic(path, s);
}

// --- Solver agreement --------------------------------------------------------

std::vector<SolverComparisonLevel> compare_solvers(const Mesh& base_mesh, const ProblemFactory& factory, int levels,
                                                   int n_steps, const SolverChoice& base,
                                                   const std::function<void(const std::string&)>& log) {
  require(levels >= 1, "solver comparison: at least 1 level (got {})", levels);
  const MeshHierarchy meshes(base_mesh, levels - 1);
  SolverChoice as = base, pd = base;
  as.contact = as.damage = "active-set";
  pd.contact = pd.damage = "penalty-duality";
  std::vector<SolverComparisonLevel> out;
  for (int l = 0; l < levels; ++l) {
    const auto problem = factory(meshes.mesh(l), n_steps);
    LevelRun ra, rp;
    ra.level = rp.level = l;
    ra.problem = rp.problem = problem;
    ra.stepper = std::make_unique<TimeStepper>(problem, as);
    rp.stepper = std::make_unique<TimeStepper>(problem, pd);
    const DiscreteNorms norms(problem->mesh, problem->elasticity);
    SolverComparisonLevel c;
    c.level = l;
    c.h = problem->mesh.size_range().second;
    c.k = problem->largest_step();
    c.n_free_dofs = ra.stepper->dofs().n_free();
    c.n_contact_nodes = ra.stepper->part().n_contact;
    c.n_nodes = problem->mesh.n_nodes();
    c.n_steps = n_steps;
    // Differences relative to the largest size of each field over the run.
    double scale_u = 0, scale_beta = 0, scale_lambda = 0;
    while (!ra.stepper->done()) {
      advance(ra, false);
      advance(rp, false);
      const State& a = ra.state();
      const State& p = rp.state();
      scale_u = std::max(scale_u, norms.energy(a.u));
      scale_beta = std::max(scale_beta, norms.l2(a.beta));
      scale_lambda = std::max(scale_lambda, a.lambda.cwiseAbs().maxCoeff());
      c.diff_u = std::max(c.diff_u, norms.energy(a.u - p.u));
      c.diff_beta = std::max(c.diff_beta, norms.l2(a.beta - p.beta));
      c.diff_lambda = std::max(c.diff_lambda, (a.lambda - p.lambda).cwiseAbs().maxCoeff());
    }
    c.diff_u /= std::max(scale_u, 1e-300);
    c.diff_beta /= std::max(scale_beta, 1e-300);
    c.diff_lambda = scale_lambda > 0 ? c.diff_lambda / scale_lambda : 0.0;
    finish(ra);
    finish(rp);
    c.contact_as = ra.result.contact_iterations;
    c.damage_as = ra.result.damage_iterations;
    c.contact_pd = rp.result.contact_iterations;
    c.damage_pd = rp.result.damage_iterations;
    c.max_active_contact = ra.result.max_active_contact;
    c.failed_as = ra.result.n_failed_steps;
    c.failed_pd = rp.result.n_failed_steps;
    c.seconds_as = ra.result.seconds;
    c.seconds_pd = rp.result.seconds;
    log_line(log, fmt::format("  solvers level {}: {} free dofs, active-set {:.2f} s, penalty-duality {:.2f} s", l,
                              c.n_free_dofs, c.seconds_as, c.seconds_pd));
    out.push_back(c);
  }
  return out;
}

std::string format_solver_table(const std::vector<SolverComparisonLevel>& r) {
  std::string s =
      "active-set (AS) versus penalty-duality (PD), both inequalities; differences relative, max over the steps;\n"
      "iterations per step, mean/max\n";
  s += fmt::format("{:>3} {:>9} {:>8} {:>6} | {:>9} {:>9} {:>9} | {:>11} {:>11} | {:>11} {:>13} | {:>7} {:>7} | {}\n",
                   "lvl", "h", "dofs", "m", "du_E", "dbeta_L2", "dlambda", "contact AS", "contact PD", "damage AS",
                   "damage PD", "AS s", "PD s", "failed AS/PD");
  for (const auto& c : r)
    s += fmt::format(
        "{:>3} {:>9.3e} {:>8} {:>6} | {:>9} {:>9} {:>9} | {:>11} {:>11} | {:>11} {:>13} | {:>7.2f} {:>7.2f} | {}/{}\n",
        c.level, c.h, c.n_free_dofs, c.n_contact_nodes, g(c.diff_u), g(c.diff_beta), g(c.diff_lambda),
        fmt::format("{:.2f}/{}", c.contact_as.mean, c.contact_as.max),
        fmt::format("{:.1f}/{}", c.contact_pd.mean, c.contact_pd.max),
        fmt::format("{:.2f}/{}", c.damage_as.mean, c.damage_as.max),
        fmt::format("{:.1f}/{}", c.damage_pd.mean, c.damage_pd.max), c.seconds_as, c.seconds_pd, c.failed_as,
        c.failed_pd);
  s += "(m: contact nodes; failed: steps whose solver did not converge or whose KKT residual exceeded the tolerance)\n";
  return s;
}

void write_solver_csv(const std::vector<SolverComparisonLevel>& r, const std::string& path) {
  std::string s =
      "level,h,k,n_steps,n_nodes,n_free_dofs,n_contact_nodes,diff_u_energy,diff_beta_l2,diff_lambda,"
      "contact_as_mean,contact_as_max,contact_pd_mean,contact_pd_max,damage_as_mean,damage_as_max,damage_pd_mean,"
      "damage_pd_max,max_active_contact,failed_as,failed_pd,seconds_as,seconds_pd\n";
  for (const auto& c : r)
    s += fmt::format("{},{:.17g},{:.17g},{},{},{},{},{:.6e},{:.6e},{:.6e},{:.4f},{},{:.4f},{},{:.4f},{},{:.4f},{},{},{},{},"
                     "{:.3f},{:.3f}\n",
                     c.level, c.h, c.k, c.n_steps, c.n_nodes, c.n_free_dofs, c.n_contact_nodes, c.diff_u, c.diff_beta,
                     c.diff_lambda, c.contact_as.mean, c.contact_as.max, c.contact_pd.mean, c.contact_pd.max,
                     c.damage_as.mean, c.damage_as.max, c.damage_pd.mean, c.damage_pd.max, c.max_active_contact,
                     c.failed_as, c.failed_pd, c.seconds_as, c.seconds_pd);
  write_file_atomic(path, s);
}

}  // namespace vpc
