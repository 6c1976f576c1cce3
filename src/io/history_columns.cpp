#include "io/history_columns.hpp"

#include "scheme/surface_fields.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace vpc {

namespace {

using F = ColumnFormat;

// The contact residuals are relative (docs/verification.md, "contact checks").
constexpr HistoryColumn kColumns[] = {
    {"step", F::integer, [](const StepReport& r) { return double(r.n); }, "the step n"},
    {"t", F::exact, [](const StepReport& r) { return r.t; }, "its time t_n"},
    {"n_active", F::integer, [](const StepReport& r) { return double(r.contact.n_active); },
     "active contact nodes, as the contact solver counts them"},
    {"total_contact_force", F::exact, [](const StepReport& r) { return r.contact.total_force; },
     "Σ λ_i, the normal contact forces summed over the contact nodes"},
    {"contact_iterations", F::integer, [](const StepReport& r) { return double(r.contact.iterations); },
     "the contact solver's iterations"},
    {"contact_equilibrium", F::residual, [](const StepReport& r) { return r.contact.residuals.equilibrium; },
     "‖Ku − F + Nᵀλ‖∞, relative"},
    {"contact_penetration", F::residual, [](const StepReport& r) { return r.contact.residuals.penetration; },
     "max(0, Nu − g), relative"},
    {"contact_negative_force", F::residual, [](const StepReport& r) { return r.contact.residuals.negative_force; },
     "max(0, −λ), relative"},
    {"contact_complementarity", F::residual, [](const StepReport& r) { return r.contact.residuals.complementarity; },
     "max over the nodes of λ_i (g − Nu)_i in absolute value, relative"},
    {"damage_iterations", F::integer, [](const StepReport& r) { return double(r.damage.iterations); },
     "the damage solver's iterations"},
    {"damage_kkt_residual", F::residual, [](const StepReport& r) { return r.damage.kkt_residual; },
     "the damage inequality's KKT residual, relative"},
    {"beta_min", F::exact, [](const StepReport& r) { return r.beta_min; }, "min β_n over the nodes"},
    {"beta_max", F::exact, [](const StepReport& r) { return r.beta_max; }, "max β_n over the nodes"},
    {"n_beta_zero", F::integer, [](const StepReport& r) { return double(r.damage.n_lower); },
     "nodes at β = 0 (fully damaged)"},
    {"n_beta_one", F::integer, [](const StepReport& r) { return double(r.damage.n_upper); },
     "nodes at β = 1 (undamaged)"},
    {"max_von_mises", F::exact, [](const StepReport& r) { return r.max_von_mises; }, "the largest von Mises norm of σ_n over the cells"},
    {"ok", F::integer, [](const StepReport& r) { return r.ok ? 1.0 : 0.0; },
     "1: both solvers converged within the tolerance"},
    {"contact_area", F::exact, [](const StepReport& r) { return r.contact_area; },
     "the tributary measures of the active contact nodes, summed"},
    {"dt", F::exact, [](const StepReport& r) { return r.k; }, "the step's size t_n − t_{n−1}"},
    {"error_estimate", F::exact, [](const StepReport& r) { return r.error_estimate; },
     "the estimate of the relative error the step adds"},
    {"rejected", F::integer, [](const StepReport& r) { return double(r.rejected); },
     "attempts of the step rejected and redone smaller"},
};

// A run with mesh adaptivity's ([adapt]), last.
constexpr HistoryColumn kAdaptColumns[] = {
    {"cells", F::integer, [](const StepReport& r) { return double(r.mesh_cells); }, "the cells of the mesh the step ends on"},
    {"unknowns", F::integer, [](const StepReport& r) { return double(r.mesh_unknowns); },
     "its free displacement unknowns"},
    {"adaptations", F::integer, [](const StepReport& r) { return double(r.adaptations); },
     "the mesh adaptations so far"},
};

// Friction's (SPEC §7): the residuals are relative, as the contact residuals.
constexpr HistoryColumn kFrictionColumns[] = {
    {"n_stick", F::integer, [](const StepReport& r) { return double(r.contact.n_stick); },
     "contact nodes that stick: in contact, the tangential force below its bound"},
    {"n_slip", F::integer, [](const StepReport& r) { return double(r.contact.n_slip); },
     "contact nodes that slip: in contact, the tangential force at its bound (to 1e-8 of the force scale)"},
    {"dissipation", F::exact, [](const StepReport& r) { return r.contact.dissipation; },
     "the step's frictional dissipation Σ λ_τ,i·Δ_i (≥ 0)"},
    {"friction_bound", F::residual, [](const StepReport& r) { return r.contact.residuals.friction_bound; },
     "max(0, ‖λ_τ‖ − s) over the nodes (s = min(tresca + μ λ_ν, shear limit)), relative"},
    {"friction_stick_slip", F::residual, [](const StepReport& r) { return r.contact.residuals.stick_slip; },
     "max min((s − ‖λ_τ‖)₊, force scale) ‖Δ‖ over the nodes: no slip below the bound, relative"},
    {"friction_slip_direction", F::residual, [](const StepReport& r) { return r.contact.residuals.slip_direction; },
     "max ‖λ_τ‖ ‖Δ‖ − λ_τ·Δ over the nodes: slip along λ_τ, relative"},
};

// A run with a friction law whose bound acts out of contact (Tresca), after the friction columns.
constexpr HistoryColumn kOpenColumns[] = {
    {"n_tresca_open", F::integer, [](const StepReport& r) { return double(r.contact.n_open); },
     "contact nodes not in contact (λ_ν = 0) that carry a tangential force: Tresca's bound acts on all of Γ3"},
};

bool has_open_column(const Problem& p) {
  return std::ranges::any_of(p.contact.frictions(), [](const auto& f) { return f && f->acts_out_of_contact(); });
}

}  // namespace

std::span<const HistoryColumn> history_columns() { return kColumns; }
std::span<const HistoryColumn> friction_columns() { return kFrictionColumns; }
std::span<const HistoryColumn> open_friction_columns() { return kOpenColumns; }
std::span<const HistoryColumn> adapt_columns() { return kAdaptColumns; }

namespace {

std::vector<std::string> case_column_names(const Problem& p, const MeshPart& part) {
  std::vector<std::string> names;
  for (const HistoryColumn& c : kColumns) names.emplace_back(c.name);
  for (const Obstacle& o : p.contact.obstacles) names.push_back("force_" + o.name);
  for (const ContactPair& pair : p.contact.pairs) names.push_back("force_pair_" + pair.slave);
  const std::vector<std::string> parts = dirichlet_parts(p);
  for (std::size_t j = 0; j < parts.size(); ++j)
    for (int i = 0; i < part.dofs.dim(); ++i)
      if (part.dirichlet_components[j] >> i & 1) names.push_back(fmt::format("reaction_{}_{}", parts[j], "xyz"[i]));
  for (const SurfaceVariable& v : declared_surface_state(p.contact))  // the laws' per-node state, ∫_Γ3
    if (!v.history.empty()) names.push_back(v.history);
  const int d = part.dofs.dim();
  if (p.contact.block_size(d) == 1) return names;
  for (const HistoryColumn& c : kFrictionColumns) names.emplace_back(c.name);
  if (has_open_column(p))
    for (const HistoryColumn& c : kOpenColumns) names.emplace_back(c.name);
  for (int i = 0; i < d; ++i) names.push_back(fmt::format("tangential_force_{}", "xyz"[i]));
  for (const Obstacle& o : p.contact.obstacles)
    for (int i = 0; i < d; ++i) names.push_back(fmt::format("tangential_force_{}_{}", o.name, "xyz"[i]));
  for (const ContactPair& pair : p.contact.pairs)
    for (int i = 0; i < d; ++i) names.push_back(fmt::format("tangential_force_pair_{}_{}", pair.slave, "xyz"[i]));
  if (p.contact.part_laws.empty()) return names;
  for (const std::string& entry : contact_law_entry_names(p.contact)) {
    names.push_back(fmt::format("force_part_{}", entry));
    for (int i = 0; i < d; ++i) names.push_back(fmt::format("tangential_force_part_{}_{}", entry, "xyz"[i]));
  }
  return names;
}

}  // namespace

std::vector<std::string> contact_law_entry_names(const ContactSpec& c) {
  std::vector<std::string> names;
  std::vector<std::string> rest;  // [contact]'s law: the parts no [[contact.part]] names
  for (const std::string& part : c.parts)
    if (std::none_of(c.part_laws.begin(), c.part_laws.end(), [&](const PartContactLaw& l) {
          return std::find(l.parts.begin(), l.parts.end(), part) != l.parts.end();
        }))
      rest.push_back(part);
  names.push_back(rest.empty() ? "none" : fmt::format("{}", fmt::join(rest, "+")));
  for (const PartContactLaw& l : c.part_laws) names.push_back(fmt::format("{}", fmt::join(l.parts, "+")));
  return names;
}

namespace {

std::vector<HistoryValue> case_values(const StepReport& r) {
  std::vector<HistoryValue> row;
  for (const HistoryColumn& c : kColumns) row.push_back({c.value(r), c.format});
  for (double f : r.obstacle_force) row.push_back({f, F::exact});
  for (double f : r.pair_force) row.push_back({f, F::exact});
  for (double f : r.reaction) row.push_back({f, F::exact});
  for (double f : r.surface_integral) row.push_back({f, F::exact});
  if (r.tangential_force.empty()) return row;  // no friction
  for (const HistoryColumn& c : kFrictionColumns) row.push_back({c.value(r), c.format});
  if (r.contact.n_open >= 0)  // a run with Tresca's bound (contact_totals)
    for (const HistoryColumn& c : kOpenColumns) row.push_back({c.value(r), c.format});
  for (double f : r.tangential_force) row.push_back({f, F::exact});
  for (double f : r.obstacle_tangential_force) row.push_back({f, F::exact});
  for (double f : r.pair_tangential_force) row.push_back({f, F::exact});
  const std::size_t d = r.tangential_force.size();
  for (std::size_t j = 0; j < r.part_force.size(); ++j) {
    row.push_back({r.part_force[j], F::exact});
    for (std::size_t i = 0; i < d; ++i) row.push_back({r.part_tangential_force[j * d + i], F::exact});
  }
  return row;
}

}  // namespace

std::vector<std::string> history_column_names(const Problem& p, const MeshPart& part, bool adaptive) {
  std::vector<std::string> names = case_column_names(p, part);
  if (adaptive)
    for (const HistoryColumn& c : kAdaptColumns) names.emplace_back(c.name);
  return names;
}

std::vector<HistoryValue> history_values(const StepReport& r) {
  std::vector<HistoryValue> row = case_values(r);
  if (r.mesh_cells >= 0)
    for (const HistoryColumn& c : kAdaptColumns) row.push_back({c.value(r), c.format});
  return row;
}

std::string HistoryValue::text() const {
  switch (format) {
    case F::integer: return fmt::format("{}", static_cast<long long>(value));
    case F::residual: return fmt::format("{:.3e}", value);
    case F::exact: break;
  }
  return fmt::format("{:.17g}", value);
}

}  // namespace vpc
