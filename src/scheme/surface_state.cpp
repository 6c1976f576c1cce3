#include "scheme/surface_state.hpp"

#include "core/error.hpp"

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

/// Per laws() entry and per law of it (laws_of), the indices in s.surface of the variables it declared.
std::vector<std::vector<std::vector<std::size_t>>> fields_of(const ContactSpec& contact, const State& s) {
  std::vector<std::vector<std::vector<std::size_t>>> field_of(contact.laws().size());
  for (std::size_t e = 0; e < field_of.size(); ++e)
    for (const SurfaceHistory* law : laws_of(contact, e)) {
      std::vector<std::size_t> f;
      for (const SurfaceVariable& v : law->surface_state())
        f.push_back(static_cast<std::size_t>(std::ranges::find(s.surface, v.name, &SurfaceField::name) - s.surface.begin()));
      field_of[e].push_back(std::move(f));
    }
  return field_of;
}

}  // namespace

Vector surface_gap_shift(const DiscreteSystem& sys, const State& s) {
  if (s.surface.empty()) return {};
  const ContactSpec& contact = sys.problem->contact;
  const auto field_of = fields_of(contact, s);
  std::vector<double> shift;
  for (const PartContactNode& node : sys.part.contact) {
    if (!node.owned) continue;
    const auto e = static_cast<std::size_t>(node.law);
    const auto laws = laws_of(contact, e);
    double sum = 0;
    for (std::size_t l = 0; l < laws.size(); ++l) {
      std::vector<const double*> values;
      for (std::size_t f : field_of[e][l]) values.push_back(s.surface[f].values.data() + node.row * s.surface[f].width);
      if (!values.empty()) sum += laws[l]->gap_shift(values);
    }
    shift.push_back(sum);
  }
  return Eigen::Map<Vector>(shift.data(), static_cast<Eigen::Index>(shift.size()));
}

void update_surface_state(const DiscreteSystem& sys, const Vector& gap, const Vector& u_free, double k, State& s) {
  if (s.surface.empty()) return;
  const MeshPart& part = sys.part;
  const ContactSpec& contact = sys.problem->contact;
  const int b = s.contact_block, t = b - 1;
  const Vector left = gap - sys.N * u_free;  // g − N u per owned row
  const auto field_of = fields_of(contact, s);
  // This rank's rows updated in a copy that holds only them (zero elsewhere), then summed: one owner per row.
  std::vector<Vector> mine;
  for (const SurfaceField& f : s.surface) mine.push_back(Vector::Zero(f.values.size()));
  Eigen::Index owned = 0;
  for (const PartContactNode& node : part.contact) {
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
    const auto e = static_cast<std::size_t>(node.law);
    const std::vector<const SurfaceHistory*> laws = laws_of(contact, e);
    for (std::size_t l = 0; l < laws.size(); ++l) {
      std::vector<double*> values;
      for (std::size_t f : field_of[e][l]) values.push_back(mine[f].data() + i * s.surface[f].width);
      if (!values.empty()) laws[l]->update_surface(view, values);
    }
  }
  for (std::size_t f = 0; f < s.surface.size(); ++f) {
    part.comm.sum(mine[f].data(), mine[f].size());
    s.surface[f].values.noalias() = mine[f];  // in place: Python's views stay valid
  }
}

}  // namespace vpc
