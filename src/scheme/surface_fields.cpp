#include "scheme/surface_fields.hpp"

#include "core/error.hpp"
#include "scheme/contact_gap.hpp"

#include <algorithm>
#include <cctype>

namespace vpc {

namespace {

/// The laws of laws() entry e that keep state: its normal law and its friction law.
std::vector<const SurfaceHistory*> laws_of(const ContactSpec& contact, std::size_t e) {
  const auto normal = contact.laws();
  const auto friction = contact.frictions();
  std::vector<const SurfaceHistory*> out;
  if (normal[e]) out.push_back(normal[e].get());
  if (friction[e]) out.push_back(friction[e].get());
  return out;
}

bool valid_name(const std::string& s) {
  return !s.empty() && std::islower(static_cast<unsigned char>(s[0])) &&
         std::ranges::all_of(s, [](char c) { return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'; });
}

}  // namespace

std::vector<SurfaceVariable> declared_surface_state(const ContactSpec& contact) {
  std::vector<SurfaceVariable> all;
  for (std::size_t e = 0; e < contact.laws().size(); ++e)
    for (const SurfaceHistory* law : laws_of(contact, e))
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
  std::vector<std::size_t> fields;
};

/// Per laws() entry, its laws that declare variables: built once per call, then indexed by each
/// node's law (no lists of laws made per node).
std::vector<std::vector<LawFields>> laws_with_fields(const ContactSpec& contact, const State& s) {
  std::vector<std::vector<LawFields>> table(contact.laws().size());
  for (std::size_t e = 0; e < table.size(); ++e)
    for (const SurfaceHistory* law : laws_of(contact, e)) {
      LawFields lf{law, {}};
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

}  // namespace

Vector surface_gap_shift(const DiscreteSystem& sys, const State& s) {
  if (s.surface.empty()) return {};
  const auto table = laws_with_fields(sys.problem->contact, s);
  const auto values = [&](std::size_t f) { return s.surface[f].values.data(); };
  std::vector<double> shift;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    double sum = 0;
    for (const LawFields& lf : table[static_cast<std::size_t>(node.law)])
      sum += lf.law->gap_shift(node_values<const double>(lf, s.surface, node.row, values));
    shift.push_back(sum);
  }
  return Eigen::Map<Vector>(shift.data(), static_cast<Eigen::Index>(shift.size()));
}

void record_gap_left(const DiscreteSystem& sys, const Vector& g, State& s) {
  if (!records_gap(sys)) return;
  const Vector shift = surface_gap_shift(sys, s);
  record_gap(sys, shift.size() > 0 ? Vector(g + shift) : g, s);
}

void update_surface_state(const DiscreteSystem& sys, const Vector& gap, double k, State& s) {
  if (s.surface.empty()) return;
  const MeshPart& part = sys.part;
  const int b = s.contact_block, t = b - 1;
  const Vector left = rows_gap_left(sys, gap, s);  // g − N u per owned row
  const auto table = laws_with_fields(sys.problem->contact, s);
  // This rank's rows updated in a copy that holds only them (zero elsewhere), then summed: one owner per row.
  std::vector<Vector> mine;
  for (const SurfaceField& f : s.surface) mine.push_back(Vector::Zero(f.values.size()));
  Eigen::Index owned = 0;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    const auto i = static_cast<Eigen::Index>(node.row);
    for (std::size_t f = 0; f < s.surface.size(); ++f) {
      const int w = s.surface[f].width;
      mine[f].segment(i * w, w) = s.surface[f].values.segment(i * w, w);
    }
    SurfaceNode view;
    view.lambda_nu = s.lambda[i * b];
    if (t > 0) {
      view.lambda_tau = {s.lambda.data() + i * b + 1, static_cast<std::size_t>(t)};
      if (s.slip_step.size() == static_cast<Eigen::Index>(part.n_contact) * t)
        view.slip_step = {s.slip_step.data() + i * t, static_cast<std::size_t>(t)};
    }
    view.gap_left = left[owned++];
    view.measure = node.measure;
    view.k = k;
    for (const LawFields& lf : table[static_cast<std::size_t>(node.law)])
      lf.law->update_surface(view, node_values<double>(lf, s.surface, node.row, [&](std::size_t f) { return mine[f].data(); }));
  }
  for (std::size_t f = 0; f < s.surface.size(); ++f) {
    part.comm.sum(mine[f].data(), mine[f].size());
    s.surface[f].values.noalias() = mine[f];  // in place: Python's views stay valid
  }
}

}  // namespace vpc
