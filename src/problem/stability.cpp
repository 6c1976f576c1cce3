#include "problem/stability.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

namespace {

/// "L = E/(2 lambda) = 500" (with "at beta = …" where L depends on β).
std::string describe_lipschitz(const ViscoplasticLaw& law, double beta) {
  const Lipschitz L = law.lipschitz(beta);
  const bool on_beta = L.value != law.lipschitz(1.0).value;
  return fmt::format("L = {} = {:.6g}{}", L.formula, L.value, on_beta ? fmt::format(" at beta = {:.6g}", beta) : "");
}

/// The number of uniform steps over T with k L ≤ c.
long long steps_for(double T, double L, double c) { return static_cast<long long>(std::ceil(T * L / c * (1 - 1e-12))); }

/// "--steps 250 or more (--steps 500 for k L <= 1, without overshoot)", for L at β = 0: the worst
/// state, so that a law whose L grows as β falls stays stable too.
std::string stable_steps(double T, const ViscoplasticLaw& law) {
  const double L = law.lipschitz(0.0).value;
  if (L <= 0) return "smaller steps";
  return fmt::format("--steps {} or more (--steps {} for k L <= 1, without overshoot){}", steps_for(T, L, 2),
                     steps_for(T, L, 1), L != law.lipschitz(1.0).value ? " (stable at every beta)" : "");
}

}  // namespace

double stable_step(const ViscoplasticLaw& law, double beta) {
  const double L = law.lipschitz(beta).value;
  return L > 0 ? 2 / L : INFINITY;
}

double stable_step_limit(const Problem& p) {
  double k = INFINITY;
  for (const Material& m : p.material_list())
    if (m.law) k = std::min(k, stable_step(*m.law, 0.0));
  return k;
}

StepControl stable_step_control(const Problem& p) {
  StepControl c = p.step_control->completed(p.final_time);
  c.dt_max = std::min(c.dt_max, stable_step_limit(p));
  c.dt_initial = std::min(c.dt_initial, c.dt_max);
  c.event_dt = std::min(c.event_dt, c.dt_max);  // no step is longer: events are located to it
  return c;
}

void check_step_stability(const Problem& p, const std::vector<int>& cell_material) {
  // The key that sets the step (Problem::where: its file, line and column, or the option).
  std::string key = "time";
  for (const char* k : {"time.dt_min", "time.tolerance", "time.steps", "time.dt"})
    if (p.key_locations.count(k)) {
      key = k;
      break;
    }
  const std::string where = p.where(key);
  const std::vector<Material> materials = p.material_list();
  if (p.step_control) {
    const StepControl c = p.step_control->completed(p.final_time);
    for (const Material& m : materials) {
      if (!m.law || c.dt_min <= stable_step(*m.law, 0.0)) continue;
      const Lipschitz L = m.law->lipschitz(0.0);
      fail("{}: error-controlled steps: dt_min = {:.6g} exceeds the largest stable step {:.6g} of material '{}', {}: "
           "G enters the step explicitly (z_n = z_(n-1) + k G_(n-1), the paper's (3.6)), stable only for k <= 2/L, {}; "
           "give time.dt_min below it",
           where, c.dt_min, 2 / L.value, m.name, m.law->describe(), describe_lipschitz(*m.law, 0.0));
    }
    return;
  }
  // The least initial β at a cell centroid, per material (the β a law sees: SPEC §2 step 1).
  std::vector<double> beta(materials.size(), 1.0);
  if (p.beta0 || !p.bodies.empty()) {
    const Mesh& mesh = p.mesh;
    const Vector nodal = p.initial_damage(mesh, cell_bodies(mesh));
    for (int c = 0; c < mesh.n_cells(); ++c) {
      double& b = beta[static_cast<std::size_t>(cell_material[c])];
      b = std::min(b, cell_mean(mesh, nodal, c));
    }
  }
  const double k = p.largest_step();
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const Material& m = materials[i];
    if (!m.law || k <= stable_step(*m.law, beta[i])) continue;
    const double L = m.law->lipschitz(beta[i]).value;
    fail("{}: the time step k = {:.6g} is unstable for material '{}', {}: G enters the step explicitly "
         "(z_n = z_(n-1) + k G_(n-1), the paper's (3.6)), stable only for k <= 2/L = {:.6g}, {}; the run would "
         "blow up as soon as the material flows. Use {}",
         where, k, m.name, m.law->describe(), 2 / L, describe_lipschitz(*m.law, beta[i]), stable_steps(p.final_time, *m.law));
  }
}

std::string unstable_step_message(const Problem& p, const Material& material, double beta, int n, double t, double k,
                                  double growth, int steps) {
  const ViscoplasticLaw& law = *material.law;
  return fmt::format(
      "{}: step {} (t = {:.6g}): the explicit viscoplastic step is unstable and the run is stopped: G_n - G_(n-1) "
      "changed sign in each of the last {} steps and grew {:.3g} times over them, which a stable step cannot do. "
      "Material '{}', {}: {}, stable only for k <= 2/L = {:.6g} (z_n = z_(n-1) + k G_(n-1) is explicit in G, the "
      "paper's (3.6)), and k = {:.6g}. Use {}",
      p.name.empty() ? "problem" : p.name, n, t, steps, growth, material.name, law.describe(),
      describe_lipschitz(law, beta), stable_step(law, beta), k, stable_steps(p.final_time, law));
}

}  // namespace vpc
