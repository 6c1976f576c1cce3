#include "scheme/surface_fields.hpp"

#include "core/error.hpp"
#include "scheme/contact_gap.hpp"
#include "scheme/friction_data.hpp"
#include "scheme/step_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <iterator>

namespace vpc {

namespace {

bool valid_name(const std::string& s) {
  return !s.empty() && std::islower(static_cast<unsigned char>(s[0])) &&
         std::ranges::all_of(s, [](char c) { return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'; });
}

}  // namespace

std::vector<SurfaceVariable> declared_surface_state(const ContactSpec& contact) {
  std::vector<SurfaceVariable> all;
  for (std::size_t e = 0; e < contact.laws().size(); ++e)
    for (const SurfaceHistory* law : contact.surface_laws(e))
      for (SurfaceVariable& v : law->surface_state()) {
        require(valid_name(v.name) && v.width >= 1 && std::isfinite(v.initial) && (v.history.empty() || v.width == 1),
                "a contact law declares the per-node state '{}' (width {}, initial {}): expected a name of lower-case "
                "letters, digits and '_', a width >= 1, a finite initial value and a history column only for width 1",
                v.name, v.width, v.initial);
        const auto same = std::ranges::find(all, v.name, &SurfaceVariable::name);
        if (same == all.end()) {
          all.push_back(std::move(v));
          continue;
        }
        require(same->width == v.width && same->initial == v.initial && same->history == v.history,
                "two contact laws declare the per-node state '{}' differently (width {} and {}, initial {} and {}); a "
                "name is one variable on all of Γ3",
                v.name, same->width, v.width, same->initial, v.initial);
      }
  return all;
}

std::vector<SurfaceField> initial_surface_state(const ContactSpec& contact, int n_contact) {
  std::vector<SurfaceField> fields;
  for (const SurfaceVariable& v : declared_surface_state(contact))
    fields.push_back({v.name, v.width, Vector::Constant(static_cast<Eigen::Index>(n_contact) * v.width, v.initial)});
  return fields;
}

namespace {

/// A law that keeps state and where its variables are in State::surface (in its declared order).
struct LawFields {
  const SurfaceHistory* law;
  std::size_t index;  // its place in ContactSpec::surface_laws of its entry
  std::vector<std::size_t> fields;
};

/// Per laws() entry, its laws that declare variables: built once per call, then indexed by each
/// node's law (no lists of laws made per node).
std::vector<std::vector<LawFields>> laws_with_fields(const ContactSpec& contact, const State& s) {
  std::vector<std::vector<LawFields>> table(contact.laws().size());
  for (std::size_t e = 0; e < table.size(); ++e)
    for (std::size_t l = 0; const SurfaceHistory* law : contact.surface_laws(e)) {
      LawFields lf{law, l++, {}};
      for (const SurfaceVariable& v : law->surface_state())
        lf.fields.push_back(static_cast<std::size_t>(s.surface_field(v.name) - s.surface.data()));
      if (!lf.fields.empty()) table[e].push_back(std::move(lf));
    }
  return table;
}

/// Pointers to node `row`'s numbers of `lf`'s variables, field f's numbers starting at data(f)
/// (State::surface's values or a copy of them), `width` per node.
template <typename T, typename Data>
std::vector<T*> node_values(const LawFields& lf, const std::vector<SurfaceField>& surface, int row, Data data) {
  std::vector<T*> out;
  for (std::size_t f : lf.fields) out.push_back(data(f) + static_cast<Eigen::Index>(row) * surface[f].width);
  return out;
}

/// State::surface updated by each row's owner: a copy that holds this rank's rows only (zero elsewhere),
/// summed over the ranks into the state (one owner per row: exact).
class OwnedRows {
 public:
  explicit OwnedRows(const State& s) {
    for (const SurfaceField& f : s.surface) mine_.push_back(Vector::Zero(f.values.size()));
  }
  /// Copies the state's values of `row` into the copy (before its laws update them there).
  void take(const State& s, int row) {
    const auto i = static_cast<Eigen::Index>(row);
    for (std::size_t f = 0; f < s.surface.size(); ++f) {
      const int w = s.surface[f].width;
      mine_[f].segment(i * w, w) = s.surface[f].values.segment(i * w, w);
    }
  }
  /// Pointers to `row`'s numbers of `lf`'s variables in the copy.
  std::vector<double*> values(const LawFields& lf, const State& s, int row) {
    return node_values<double>(lf, s.surface, row, [&](std::size_t f) { return mine_[f].data(); });
  }
  /// Sums the copies over the ranks into the state, in place (Python's views stay valid). Collective.
  void publish(const la::Comm& comm, State& s) {
    for (std::size_t f = 0; f < s.surface.size(); ++f) {
      comm.sum(mine_[f].data(), mine_[f].size());
      s.surface[f].values.noalias() = mine_[f];
    }
  }

 private:
  std::vector<Vector> mine_;
};

}  // namespace

void set_initial_surface_state(const DiscreteSystem& sys, const Vector& gap, State& s) {
  if (s.surface.empty()) return;
  const ContactSpec& contact = sys.problem->contact;
  const auto table = laws_with_fields(contact, s);
  const MeshPart& part = sys.part;
  OwnedRows mine(s);
  la::collective(part.comm, [&] {
    Eigen::Index owned = 0;
    for (const PartContactNode& node : sys.contact->nodes) {
      if (!node.owned) continue;
      mine.take(s, node.row);
      const auto e = static_cast<std::size_t>(node.law);
      const Point& x = part.mesh().node(node.local_node);
      for (const LawFields& lf : table[e])
        if (const LawText why = lf.law->initial_at(x, gap[owned], mine.values(lf, s, node.row)); !why.text.empty())
          fail("{}: {}", sys.problem->where_in(contact.entry_table(e), why.key), why.text);
      ++owned;
    }
  });
  mine.publish(part.comm, s);
}

namespace {

/// visit(law, values, node, row) for each owned row (row: its index among them, in row order) and each of
/// its node's laws that keep state, `values` the node's numbers of the law's variables in s.
template <class Visit>
void visit_laws(const DiscreteSystem& sys, const State& s, Visit visit) {
  const auto table = laws_with_fields(sys.problem->contact, s);
  const auto values = [&](std::size_t f) { return s.surface[f].values.data(); };
  Eigen::Index row = 0;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    for (const LawFields& lf : table[static_cast<std::size_t>(node.law)])
      visit(*lf.law, node_values<const double>(lf, s.surface, node.row, values), node, row);
    ++row;
  }
}

/// Per owned row in row order, the sum over its node's laws that keep state of term(law, values, node).
template <class Term>
Vector sum_over_laws(const DiscreteSystem& sys, const State& s, Term term) {
  Vector out = Vector::Zero(static_cast<Eigen::Index>(sys.contact->owned_row_numbers().size()));
  visit_laws(sys, s, [&](const SurfaceHistory& law, std::span<const double* const> v, const PartContactNode& node,
                         Eigen::Index row) { out[row] += term(law, v, node); });
  return out;
}

}  // namespace

StepBonds surface_bond(const DiscreteSystem& sys, const State& s, double k) {
  StepBonds bonds;
  const ContactSpec& spec = sys.problem->contact;
  if (!spec.adhesive()) return bonds;
  const Mesh& mesh = sys.part.mesh();
  bonds.normal = sum_over_laws(sys, s, [&](const SurfaceHistory& law, std::span<const double* const> v, const PartContactNode& node) {
    return law.bond(v, mesh.node(node.local_node), k) * node.measure;
  });
  if (!spec.shear_bonded()) return bonds;
  bonds.shear = sum_over_laws(sys, s, [&](const SurfaceHistory& law, std::span<const double* const> v, const PartContactNode& node) {
    return law.shear_bond(v, mesh.node(node.local_node), k) * node.measure;
  });
  const Eigen::Index t = spec.block_size(mesh.dim()) - 1;
  bonds.stretch = Vector::Zero(bonds.shear.size() * t);
  visit_laws(sys, s, [&](const SurfaceHistory& law, std::span<const double* const> v, const PartContactNode&,
                         Eigen::Index row) {
    law.bond_stretch(v, std::span<double>(bonds.stretch.data() + row * t, static_cast<std::size_t>(t)));
  });
  return bonds;
}

Vector surface_gap_shift(const DiscreteSystem& sys, const State& s) {
  if (s.surface.empty()) return {};
  return sum_over_laws(sys, s, [](const SurfaceHistory& law, std::span<const double* const> v, const PartContactNode&) {
    return law.gap_shift(v);
  });
}

void record_gap_left(const DiscreteSystem& sys, const Vector& g, State& s) {
  if (!records_gap(sys)) return;
  const Vector shift = surface_gap_shift(sys, s);
  record_gap(sys, shift.size() > 0 ? Vector(g + shift) : g, s);
}

namespace {

/// k_ν,i of each owned row (SurfaceNode::normal_stiffness): Σ_j N_ij² K_jj / Σ_j N_ij² over the
/// row's own node's free dofs (a pair row's slave entries are ν; its masters' are left out), from
/// K's assembled diagonal (DiscreteSystem::K_diagonal): the same on every rank count. 0 where the node
/// has no free dof.
std::vector<double> normal_stiffness(const DiscreteSystem& sys) {
  const Vector& K_diagonal = sys.K_diagonal;
  const ContactSet& set = *sys.contact;
  std::vector<double> k(set.dofs.size(), 0.0);
  for (std::size_t i = 0; i < set.dofs.size(); ++i) {
    double weighted = 0, weights = 0;
    for (int j : set.dofs[i]) {
      const double n = set.N.coeff(static_cast<Eigen::Index>(i), j);
      weighted += n * n * K_diagonal[j];
      weights += n * n;
    }
    k[i] = weights > 0 ? weighted / weights : 0.0;
  }
  return k;
}

/// The largest share of one kind over every process and where it is (least original node among ties),
/// with the law's text and the node's place where it passes 1. Collective.
struct LargestShare {
  double share = 0;
  int node = -1;  // original node number (−1: none)
  std::size_t entry = 0, law = 0;
  Point x{0, 0, 0};
  void offer(double v, int n, std::size_t e, std::size_t l, const Point& at) {
    if (v > share || (v == share && v > 0 && n < node)) *this = {v, n, e, l, at};
  }
  /// On every process: the largest and the text of its law (`text` of the law) where it passes 1.
  std::string reduce(const DiscreteSystem& sys, double& out, LawText (SurfaceHistory::*text)() const) {
    const la::Comm& comm = sys.part.comm;
    const double mine = -share;
    const int index = node;
    const MinimumAt best = global_minimum_at(comm, std::span<const double>(&mine, 1), std::span<const int>(&index, 1));
    out = -best.value;
    if (!(out > 1)) return {};
    // Its owner's entry, law and position, 0 elsewhere: one sum gives them everywhere.
    const bool owner = node == best.index && share == out;
    double where[5] = {static_cast<double>(entry), static_cast<double>(law), x[0], x[1], x[2]};
    if (!owner) std::fill(std::begin(where), std::end(where), 0.0);
    comm.sum(where, 5);
    const auto e = static_cast<std::size_t>(where[0]);
    const ContactSpec& c = sys.problem->contact;
    const SurfaceHistory* l = c.surface_laws(e)[static_cast<std::size_t>(where[1])];
    const LawText said = (l->*text)();
    return fmt::format("{}: at contact node {} ({}, {}, {}), {:.3g} times: {}",
                       sys.problem->where_in(c.entry_table(e), said.key), best.index, where[2], where[3], where[4], out,
                       said.text);
  }
};

}  // namespace

SurfaceLimits update_surface_state(const DiscreteSystem& sys, const Vector& gap, double k, const Vector& u_before,
                                   double t_end, State& s) {
  SurfaceLimits limits;
  if (s.surface.empty()) return limits;
  const MeshPart& part = sys.part;
  const int b = s.contact_block, t = b - 1;
  const int dim = part.mesh().dim();
  const Vector left = rows_gap_left(sys, gap, s);  // g − N u per owned row
  const std::vector<double> stiffness = normal_stiffness(sys);
  const Vector fixed = prescribed_slip(sys, u_before, s.u, s.t, t_end);  // along prescribed directions
  const auto table = laws_with_fields(sys.problem->contact, s);
  OwnedRows mine(s);
  LargestShare step, warn;
  double rates[2] = {0, 0};  // ∫ rate_change² and ∫ 1 over the owned rows
  Eigen::Index owned = 0;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    const auto i = static_cast<Eigen::Index>(node.row);
    mine.take(s, node.row);
    SurfaceNode view;
    view.lambda_nu = s.lambda[i * b];
    if (t > 0) {
      view.lambda_tau = {s.lambda.data() + i * b + 1, static_cast<std::size_t>(t)};
      if (s.slip_step.size() == static_cast<Eigen::Index>(part.n_contact) * t)
        view.slip_step = {s.slip_step.data() + i * t, static_cast<std::size_t>(t)};
    }
    view.slip = std::hypot(fixed[owned], view.slip_step.empty() ? 0.0
                                                                : Eigen::Map<const Vector>(view.slip_step.data(), t).norm());
    view.gap_left = left[owned];
    view.measure = node.measure;
    view.k = k;
    view.x = part.mesh().node(node.local_node);
    view.normal_stiffness = stiffness[static_cast<std::size_t>(owned)];
    view.size = dim == 3 ? std::sqrt(node.measure) : node.measure;
    ++owned;
    const auto e = static_cast<std::size_t>(node.law);
    const int number = part.original_node[static_cast<std::size_t>(node.local_node)];
    for (const LawFields& lf : table[e]) {
      const SurfaceUpdate u = lf.law->update_surface(view, mine.values(lf, s, node.row));
      step.offer(u.step_share, number, e, lf.index, view.x);
      warn.offer(u.warn_share, number, e, lf.index, view.x);
      rates[0] += u.rate_change * u.rate_change * node.measure;
    }
    rates[1] += node.measure;
  }
  mine.publish(part.comm, s);
  part.comm.sum(rates, 2);
  limits.rate_change = rates[1] > 0 ? std::sqrt(rates[0] / rates[1]) : 0.0;
  limits.step_text = step.reduce(sys, limits.step_share, &SurfaceHistory::step_limit);
  limits.warn_text = warn.reduce(sys, limits.warn_share, &SurfaceHistory::warning);
  return limits;
}

}  // namespace vpc
