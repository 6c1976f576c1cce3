#include "scheme/step_checks.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "part/contact_tangents.hpp"
#include "problem/stability.hpp"
#include "scheme/surface_fields.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace vpc {

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

MinimumAt global_minimum_at(const la::Comm& comm, std::span<const double> values, std::span<const int> index) {
  const MinimumAt mine = minimum_at(values, index);
  // minimum_at's rule over the processes: the least value, then the least node holding it.
  const double lo = comm.min(mine.index < 0 ? INFINITY : mine.value);
  const double at = comm.min(mine.index >= 0 && mine.value == lo ? mine.index : INFINITY);
  return {lo, std::isfinite(at) ? static_cast<int>(at) : mine.index};
}

namespace {

bool acts_out_of_contact(const FrictionLaw* f) { return f && f->acts_out_of_contact(); }

}  // namespace

std::string open_friction_warning(const Problem& p, const StepReport& rep) {
  if (rep.contact.n_open <= 0) return {};
  const ContactSpec& c = p.contact;
  // The first entry whose bound acts out of contact (laws() order): a pair's key, else
  // [contact]'s friction (or a [[contact.part]]'s, which p.where finds there).
  const auto frictions = c.frictions();
  const auto first = std::ranges::find_if(frictions, [](const auto& f) { return acts_out_of_contact(f.get()); });
  const auto entry = static_cast<std::size_t>(first - frictions.begin()), first_pair = 1 + c.part_laws.size();
  const std::string where = entry >= first_pair && entry < frictions.size() ? p.where(c.entry_table(entry))
                                                                            : p.where("contact.friction");
  return fmt::format(
      "{}: Tresca friction acts through {} contact node(s) not in contact at step {} (t = {:.6g}): its given bound "
      "acts on all of Γ3, in contact or not (history.csv n_tresca_open; contact_status 3). For friction only where "
      "the surfaces touch, with a largest shear traction, use friction = \"coulomb\" with shear_limit",
      where, rep.contact.n_open, rep.n, rep.t);
}

void contact_totals(const DiscreteSystem& sys, const State& s, StepReport& rep) {
  // n_tresca_open only where some bound acts out of contact (history.csv's column is there only then).
  if (std::ranges::none_of(sys.problem->contact.frictions(), [](const auto& f) { return acts_out_of_contact(f.get()); }))
    rep.contact.n_open = -1;
  const auto& c = sys.problem->contact;
  const int b = s.contact_block;
  // The tangential force's components: the dimension with friction, none without (every tangential
  // slot below is then empty, and so are the report's tangential totals: history.csv has no columns).
  const std::size_t dt = b > 1 ? static_cast<std::size_t>(sys.part.mesh().dim()) : 0;
  // Each law entry's normal and tangential forces (ContactSpec::laws() order: [contact]'s, the
  // [[contact.part]]s', then each pair's); history.csv has the pairs' always and, with friction and
  // several laws on Γ3, Γ3's entries'.
  const std::size_t n_obstacles = c.obstacles.size(), n_entries = 1 + c.part_laws.size() + c.pairs.size();
  const std::size_t first_pair = 1 + c.part_laws.size();
  // area, the obstacles' forces, the tangential force (dt), its share on each obstacle (obstacles ×
  // dt), then the entries' forces (entries × (1 + dt))
  const std::size_t on_total = n_obstacles + 1, on_obstacles = on_total + dt, on_entries = on_obstacles + dt * n_obstacles;
  std::vector<double> sums(on_entries + n_entries * (1 + dt), 0.0);
  const std::vector<Point> tangents = contact_tangents(sys.part.dofs, sys.contact->nodes, b);
  for (std::size_t k = 0; k < sys.contact->nodes.size(); ++k) {
    const PartContactNode& node = sys.contact->nodes[k];
    if (!node.owned) continue;
    const double lambda = s.lambda[node.row * b];
    if (lambda > rep.contact.active_threshold) sums[0] += node.measure;
    const Point tangential = along_tangents(tangents, k, b, s.lambda.data() + node.row * b + 1);
    for (std::size_t i = 0; i < dt; ++i) sums[on_total + i] += tangential[i];
    const std::size_t entry = on_entries + static_cast<std::size_t>(node.law) * (1 + dt);
    sums[entry] += lambda;
    for (std::size_t i = 0; i < dt; ++i) sums[entry + 1 + i] += tangential[i];
    if (c.obstacles.empty() || (lambda == 0 && tangential == Point{0, 0, 0})) continue;
    const int nearest = nearest_obstacle(c.obstacles, sys.part.mesh().node(node.local_node), node.direction, rep.t,
                                         node.obstacles);
    if (nearest < 0) continue;
    sums[static_cast<std::size_t>(nearest) + 1] += lambda;
    for (std::size_t i = 0; i < dt; ++i) sums[on_obstacles + dt * static_cast<std::size_t>(nearest) + i] += tangential[i];
  }
  sys.part.comm.sum(sums.data(), static_cast<int>(sums.size()));
  rep.contact_area = sums[0];
  auto at = [&](std::size_t i) { return sums.begin() + static_cast<std::ptrdiff_t>(i); };
  rep.obstacle_force.assign(at(1), at(on_total));
  rep.tangential_force.assign(at(on_total), at(on_obstacles));
  rep.obstacle_tangential_force.assign(at(on_obstacles), at(on_entries));
  rep.part_force.clear();
  rep.part_tangential_force.clear();
  rep.pair_force.clear();
  rep.pair_tangential_force.clear();
  const std::size_t n_parts = dt > 0 && !c.part_laws.empty() ? first_pair : 0;
  for (std::size_t e = 0; e < n_entries; ++e) {
    const auto entry = on_entries + e * (1 + dt);
    if (e >= first_pair) {
      rep.pair_force.push_back(sums[entry]);
      rep.pair_tangential_force.insert(rep.pair_tangential_force.end(), at(entry + 1), at(entry + 1 + dt));
    } else if (e < n_parts) {
      rep.part_force.push_back(sums[entry]);
      rep.part_tangential_force.insert(rep.part_tangential_force.end(), at(entry + 1), at(entry + 1 + dt));
    }
  }
}

void reactions(const DiscreteSystem& sys, const State& s, const Vector& F, StepReport& rep) {
  const MeshPart& part = sys.part;
  const Mesh& mesh = part.mesh();
  const int d = mesh.dim();
  // r = (σ_n, ε(φ)) − F_n at the prescribed dofs; each cell and loaded facet lives on
  // one process, so the part's sums over its nodes (owned and ghost) add up to the whole.
  Vector r = Vector::Zero(part.dofs.n_full());
  for (int c : sys.dirichlet_cells)
    for (int a = 0; a <= d; ++a)
      for (int i = 0; i < d; ++i) r[mesh.cell(c)[a] * d + i] += stress_divergence_entry(sys.geo[c], s.sigma[c], d, a, i);
  // A part's reaction has the components it prescribes (a roller's: its normal one); each
  // prescribed dof counts once, for the first part that prescribes it there, so that the
  // reactions of all parts add up to the supports' total force.
  const auto& prescribes = part.dirichlet_components;
  std::vector<double> sums(prescribes.size() * d, 0.0);
  for (const auto& [node, bits] : part.dirichlet_nodes)
    for (int i = 0; i < d; ++i)
      for (std::size_t j = 0; j < prescribes.size(); ++j)
        if ((bits >> j & 1) && (prescribes[j] >> i & 1)) {
          sums[j * d + i] += r[node * d + i] - F[node * d + i];
          break;
        }
  part.comm.sum(sums.data(), static_cast<int>(sums.size()));
  rep.reaction.clear();
  for (std::size_t j = 0; j < prescribes.size(); ++j)
    for (int i = 0; i < d; ++i)
      if (prescribes[j] >> i & 1) rep.reaction.push_back(sums[j * d + i]);
}

void beta_range(const DiscreteSystem& sys, const State& s, StepReport& rep) {
  const auto n = static_cast<std::size_t>(sys.part.n_owned_nodes);
  const MinimumAt lo = global_minimum_at(sys.part.comm, {s.beta.data(), n}, {sys.part.original_node.data(), n});
  rep.beta_min = lo.value;
  rep.beta_min_node = lo.index;
  rep.beta_max = sys.part.comm.max(n ? s.beta.head(static_cast<Eigen::Index>(n)).maxCoeff() : -INFINITY);
}

/// ∫_Γ3 v of each per-node state variable with a history column (its owned nodes', summed).
/// A mean (SurfaceVariable::history_mean) over the nodes whose laws declare v: ∫ v / ∫ 1 there.
void surface_integrals(const DiscreteSystem& sys, const State& s, StepReport& rep) {
  rep.surface_integral.clear();
  const ContactSpec& contact = sys.problem->contact;
  for (const SurfaceVariable& v : declared_surface_state(contact)) {
    if (v.history.empty()) continue;
    const SurfaceField& f = *s.surface_field(v.name);
    std::vector<char> declares;  // per laws() entry, for a mean
    if (v.history_mean)
      for (std::size_t e = 0; e < contact.laws().size(); ++e)
        declares.push_back(std::ranges::any_of(contact.surface_laws(e), [&](const SurfaceHistory* law) {
          return std::ranges::any_of(law->surface_state(), [&](const SurfaceVariable& w) { return w.name == v.name; });
        }));
    double sums[2] = {0, 0};
    for (const PartContactNode& node : sys.contact->nodes) {
      if (!node.owned || (v.history_mean && !declares[static_cast<std::size_t>(node.law)])) continue;
      sums[0] += f.values[node.row] * node.measure;
      sums[1] += node.measure;
    }
    sys.part.comm.sum(sums, 2);
    rep.surface_integral.push_back(v.history_mean ? (sums[1] > 0 ? sums[0] / sums[1] : 0.0) : sums[0]);
  }
}

void report_step(const DiscreteSystem& sys, const State& s, const Vector& F, StepReport& rep) {
  contact_totals(sys, s, rep);
  surface_integrals(sys, s, rep);
  reactions(sys, s, F, rep);
  beta_range(sys, s, rep);
}

bool step_accepted(const la::Comm& comm, const StepReport& rep, double tolerance, const Vector& u_free,
                   const Vector& beta_owned) {
  // allFinite, not a sum of squares: that overflows for a finite |u| > 1e154 (issue 26).
  const bool finite = comm.all(u_free.allFinite() && beta_owned.allFinite());
  return rep.contact.converged && rep.damage.converged && rep.contact.residuals.max() <= tolerance &&
         rep.damage.kkt_residual <= tolerance && !(rep.surface.step_share > 1) && finite;
}

void LaggedStepBackstop::attempted(std::vector<SymTensor> dG, double dG2, double dot_last) {
  dG_attempt_ = std::move(dG);
  dG2_attempt_ = dG2;
  dG_dot_attempt_ = dot_last;
}

void LaggedStepBackstop::check_accepted(const DiscreteSystem& sys, const State& s, const StepReport& rep) {
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
  const MeshPart& part = sys.part;
  const Mesh& mesh = part.mesh();
  std::vector<double> largest(sys.materials.size(), 0.0), beta(sys.materials.size(), INFINITY);
  for (int c = 0; c < mesh.n_cells(); ++c) {
    double& l = largest[static_cast<std::size_t>(part.cell_material[c])];
    l = std::max(l, dG_last_[c].dot(dG_last_[c]));
  }
  for (double& l : largest) l = part.comm.max(l);
  const auto m = static_cast<std::size_t>(std::max_element(largest.begin(), largest.end()) - largest.begin());
  for (int c = 0; c < mesh.n_cells(); ++c)
    if (static_cast<std::size_t>(part.cell_material[c]) == m && dG_last_[c].dot(dG_last_[c]) >= 0.25 * largest[m])
      beta[m] = std::min(beta[m], cell_mean(mesh, s.beta, c));
  const double b = part.comm.min(beta[m]);
  la::collective(part.comm, [&] {
    fail("{}", unstable_step_message(*sys.problem, sys.materials[m], std::isfinite(b) ? b : 1.0, rep.n, rep.t, rep.k,
                                     growth_product_, growing_steps_));
  });
}

}  // namespace vpc
