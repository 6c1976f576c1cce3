#include "scheme/step_control.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

bool snapshot_fits(const Snapshot& s, const State& now, Eigen::Index n_u_free, const Problem& problem) {
  return s.state.u.size() == now.u.size() && s.state.beta.size() == now.beta.size() &&
         s.state.sigma.size() == now.sigma.size() && s.state.eps.size() == now.eps.size() &&
         s.state.z.size() == now.z.size() && s.state.lambda.size() == now.lambda.size() &&
         s.state.slip.size() == now.slip.size() && s.state.slip_step.size() == now.slip_step.size() &&
         s.state.contact_status.size() == now.contact_status.size() &&
         same_fields(s.state.surface, now.surface) &&
         s.u_free.size() == n_u_free && s.state.n >= 0 &&
         (problem.step_control ? s.state.t <= problem.final_time : s.state.n <= problem.n_steps);
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

void StepControlState::accept(const StepReport& rep) {
  sigma_scale = std::max(sigma_scale, rep.sigma_norm);
  n_active = rep.contact.n_active;
  n_beta_zero = rep.damage.n_lower;
  n_beta_one = rep.damage.n_upper;
}

std::vector<double> error_damping(const DiscreteSystem& sys, const State& s, const std::vector<SymTensor>& G_now,
                                  const std::vector<SymTensor>& G_before) {
  const Mesh& mesh = sys.part.mesh();
  const int n_cells = mesh.n_cells();
  std::vector<double> jd(n_cells, 0.0);
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) {
    const SymTensor dG = G_now[c] - G_before[c];
    const double size = dG.norm(), sigma = s.sigma[c].norm();
    if (size == 0 || sigma == 0) continue;
    // A difference quotient along ΔG (the laws' rates are Lipschitz in σ, not all differentiable),
    // with σ moved by a relative 1e-6.
    const double h = 1e-6 * sigma / size;
    const Material& m = sys.material(c);
    const PointState moved{s.sigma[c] + h * dG, s.eps[c], cell_mean(mesh, s.beta, c), m.elasticity.stress_dim(),
                           mesh.cell_centroid(c), s.t};
    SymTensor rate = m.law->rate(moved);
    m.elasticity.restrict_stress(rate);
    jd[c] = dG.dot(rate - G_now[c]) / h;
  }
  return jd;
}

ErrorEstimate estimate_error(const DiscreteSystem& sys, const State& s, const StepTaken& taken, const LaggedRates& now,
                             double k, const std::vector<SymTensor>& dG_last, double sigma_scale_before) {
  // The local error (k/2)|x'(t_n) − x'(t_{n−1})| of the explicit rate of z, G (3.6), and of β's
  // rate in (3.8), M β' = F_φ − κAβ, whose change over the step is F_φ(n) − F_φ(n−1) −
  // κA(β_n − β_{n−1}) (M lumped; nodes at a bound have no rate). The sums run in cell and node
  // order on each process (an OpenMP reduction's order varies, and the estimate chooses steps).
  const MeshPart& part = sys.part;
  const Mesh& mesh = part.mesh();
  const int n_cells = mesh.n_cells();
  const std::vector<SymTensor>& G = taken.lagged.G;
  const std::vector<double> damping = error_damping(sys, s, now.G, G);
  ErrorEstimate e;
  // |ΔG|², |Δβ'|², |σ_n|² (L2), ⟨ΔG, J ΔG⟩, (ΔG, ΔG of the last accepted step)
  double sums[5] = {0, 0, 0, 0, 0};
  std::vector<double> dphi(n_cells);
  e.dG.resize(n_cells);
  const bool have_last = dG_last.size() == static_cast<std::size_t>(n_cells);
  for (int c = 0; c < n_cells; ++c) {
    const double w = sys.geo[c].volume;
    const SymTensor dG = now.G[c] - G[c];
    sums[0] += w * dG.dot(dG);
    if (have_last) sums[4] += w * dG.dot(dG_last[c]);
    e.dG[c] = dG;
    sums[2] += w * s.sigma[c].dot(s.sigma[c]);
    sums[3] += w * damping[c];
    dphi[c] = now.phi[c] - taken.lagged.phi[c];
  }
  la::Vector dF(part.node_layout);
  dF.local() = assemble_p0_source(mesh, sys.geo, dphi) - sys.kappa * (sys.A_local * (s.beta - taken.beta_before));
  dF.add_ghosts_to_owners();
  for (int i = 0; i < part.n_owned_nodes; ++i)
    if (s.beta[i] > 0 && s.beta[i] < 1) sums[1] += dF.owned()[i] * dF.owned()[i] / sys.lumped_mass[i];
  part.comm.sum(sums, 5);
  e.dG2 = sums[0];
  e.dG_dot_last = sums[4];
  e.sigma_norm = std::sqrt(sums[2]);
  const double sigma_scale = std::max(sigma_scale_before, e.sigma_norm);
  // The law damps an error in z along ΔG at the rate μ = −⟨ΔG, J ΔG⟩ / |ΔG|² (J = ∂G/∂σ); the
  // explicit step keeps a factor |1 − kμ| of it per step, a rate −ln|1 − kμ| / k (none from
  // kμ ≥ 2 on: the step is unstable). Such an error lasts about 1/μ, not until T, so the step's
  // share of the error at any time up to T is its local error times 1/(μT) (at most 1).
  const double T = sys.problem->final_time;
  const double mu = sums[0] > 0 ? -sums[3] / sums[0] : 0.0;
  const double mu_step = k * mu >= 2 ? 0.0 : std::min(mu, -std::log(std::abs(1 - k * mu)) / k);
  const double lasting = mu_step * T > 1 ? 1 / (mu_step * T) : 1.0;
  const double e_sigma = sigma_scale > 0 ? k / 2 * std::sqrt(sums[0]) / sigma_scale * lasting : 0.0;
  const double e_beta = k / 2 * std::sqrt(sums[1] / sys.volume);
  // The surface laws' lagged rates (adhesion's bonding: SurfaceUpdate::rate_change), as β's.
  const double e_surface = k / 2 * taken.report.surface.rate_change;
  e.error = std::max({e_sigma, e_beta, e_surface});
  return e;
}

StepReport advance_or_halve(const StepAttempts& a, int level, int max_halvings, double k, double t_end) {
  if (level >= max_halvings) return a.advance(k, t_end);
  const Snapshot before = a.snapshot();
  StepReport rep = a.advance(k, t_end);
  if (rep.ok) return rep;  // the same on every process: rep is
  a.restore(before);
  const double t_mid = before.state.t + k / 2;
  const StepReport first = advance_or_halve(a, level + 1, max_halvings, k / 2, t_mid);
  if (!first.ok) return first;
  rep = advance_or_halve(a, level + 1, max_halvings, k / 2, t_end);
  rep.k = t_end - before.state.t;
  rep.error_estimate = std::max(rep.error_estimate, first.error_estimate);
  rep.substeps += first.substeps;
  add_seconds(rep, first);
  return rep;
}

bool is_event(const StepControl& c, const StepControlState& last, const StepReport& rep) {
  return (c.contact_events && rep.contact.n_active != last.n_active) ||
         (c.damage_events && (rep.damage.n_lower > last.n_beta_zero || rep.damage.n_upper > last.n_beta_one));
}

StepReport controlled_step(const StepAttempts& a, const StepControl& c, StepControlState& cs, double T) {
  const Snapshot before = a.snapshot();
  const double t0 = before.state.t;
  double k = cs.k_next > 0 ? cs.k_next : c.dt_initial;
  int rejected = 0;
  StepReport spent;  // the rejected attempts' times: part of the step's cost
  for (;;) {
    k = step_on_ladder(k, c.dt_min, c.dt_max);
    const double t_end = step_end(t0, k, T, c.landings);
    const double k_used = t_end == t0 + k ? k : t_end - t0;  // a ladder size, or shortened to land
    StepReport rep = a.advance(k_used, t_end);
    // r: the estimate over what the tolerance allows this step (an error per unit of time).
    const double r = rep.error_estimate / (c.tolerance * k_used);
    // share: of a surface law's step limit (SPEC §9's wear cap), which grows with the step like the slip
    // in it: a step above it is redone at the size that meets it, and the next one proposed within it.
    const double share = rep.surface.step_share;
    double retry = 0;  // the smaller step to redo it with (0: accept)
    if (!rep.ok)
      retry = k_used * (share > 1 ? std::min(c.cut, c.safety / share) : c.cut);
    else if (k_used > c.event_dt * (1 + 1e-9) && is_event(c, cs, rep))
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
      if (is_event(c, cs, rep)) next = std::min(next, c.event_dt);  // events come in runs: no rejection for each
      if (share > 0) next = std::min(next, k_used * c.safety / share);
      if (rep.ok) {
        cs.k_next = std::clamp(next, c.dt_min, c.dt_max);
        cs.rejected += rejected;
      }
      return rep;
    }
    add_seconds(spent, rep);
    a.restore(before);
    ++rejected;
    k = std::max(retry, c.dt_min);
  }
}

}  // namespace vpc
