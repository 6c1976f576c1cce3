#include "contact/contact_spec.hpp"

#include "core/error.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace vpc {

double contact_gap_at(const ContactSpec& contact, const Point& x, const Point& nu, double t, double miss,
                      ObstacleMask obstacles) {
  return contact.obstacles.empty() ? contact.gap(x, t) : obstacle_gap(contact.obstacles, x, nu, t, miss, obstacles);
}

std::vector<std::shared_ptr<const ContactLaw>> ContactSpec::laws() const {
  std::vector<std::shared_ptr<const ContactLaw>> all = {law};
  for (const PartContactLaw& p : part_laws) all.push_back(p.law);
  for (const ContactPair& p : pairs) all.push_back(p.law ? p.law : law);
  return all;
}

int ContactSpec::law_index(const std::string& part) const {
  for (std::size_t k = 0; k < part_laws.size(); ++k)
    if (std::ranges::find(part_laws[k].parts, part) != part_laws[k].parts.end()) return static_cast<int>(k) + 1;
  return 0;
}

namespace {

/// One law of each entry, in the order of laws(): [contact]'s, each [[contact.part]]'s, each pair's.
template <class Law>
std::vector<std::shared_ptr<const Law>> per_entry(const ContactSpec& c, const std::shared_ptr<const Law>& on_gamma3,
                                                  std::shared_ptr<const Law> PartContactLaw::*of_part,
                                                  std::shared_ptr<const Law> ContactPair::*of_pair) {
  std::vector<std::shared_ptr<const Law>> all = {on_gamma3};
  for (const PartContactLaw& p : c.part_laws) all.push_back(p.*of_part);
  for (const ContactPair& p : c.pairs) all.push_back(p.*of_pair);
  return all;
}

}  // namespace

std::vector<std::shared_ptr<const FrictionLaw>> ContactSpec::frictions() const {
  return per_entry(*this, friction, &PartContactLaw::friction, &ContactPair::friction);
}

bool ContactSpec::frictional() const {
  return std::ranges::any_of(frictions(), [](const auto& f) { return f != nullptr; });
}

std::vector<std::shared_ptr<const ArchardWear>> ContactSpec::wears() const {
  return per_entry(*this, wear, &PartContactLaw::wear, &ContactPair::wear);
}

std::vector<std::shared_ptr<const FremondAdhesion>> ContactSpec::adhesions() const {
  return per_entry(*this, adhesion, &PartContactLaw::adhesion, &ContactPair::adhesion);
}

bool ContactSpec::adhesive() const {
  for (std::size_t e = 0; e < laws().size(); ++e)
    for (const SurfaceHistory* law : surface_laws(e))
      if (law->bond_length() > 0) return true;
  return false;
}

bool ContactSpec::tangential() const {
  return frictional() || std::ranges::any_of(wears(), [](const auto& w) { return w != nullptr; }) || shear_bonded();
}

bool ContactSpec::shear_bonded() const {
  return std::ranges::any_of(adhesions(), [](const auto& a) { return a && a->shears(); });
}

std::vector<const SurfaceHistory*> ContactSpec::surface_laws(std::size_t e) const {
  std::vector<const SurfaceHistory*> out;
  for (const SurfaceHistory* law : {static_cast<const SurfaceHistory*>(laws()[e].get()),
                                    static_cast<const SurfaceHistory*>(frictions()[e].get()),
                                    static_cast<const SurfaceHistory*>(wears()[e].get()),
                                    static_cast<const SurfaceHistory*>(adhesions()[e].get())})
    if (law) out.push_back(law);
  return out;
}

std::string ContactSpec::entry_table(std::size_t e) const {
  if (e == 0) return "contact";
  if (e <= part_laws.size()) return fmt::format("contact.part[{}]", e - 1);
  return fmt::format("contact.pair[{}]", e - 1 - part_laws.size());
}

std::vector<std::size_t> ContactSpec::sliding_pairs(bool large) const {
  std::vector<std::size_t> out;
  for (std::size_t q = 0; q < pairs.size(); ++q)
    if (pairs[q].large_sliding == large) out.push_back(q);
  return out;
}

int ContactSpec::block_size(int dim) const {
  int block = tangential() ? dim : 1;
  for (const auto& l : laws()) block = std::max(block, l->block_size(dim));
  return block;
}

namespace {

/// A law entry's normal law, friction and wear ("Signorini, Coulomb friction mu = 0.3, Archard wear k_w = 1e-09");
/// `none` for no friction.
std::string entry_laws(const ContactLaw& law, const FrictionLaw* friction, const ArchardWear* wear,
                       const FremondAdhesion* adhesion, std::string_view none) {
  return law.describe() + (friction ? ", " + friction->describe() : std::string(none)) +
         (wear ? ", " + wear->describe() : std::string()) + (adhesion ? ", " + adhesion->describe() : std::string());
}

}  // namespace

std::vector<std::string> ContactSpec::describe() const {
  std::string on_gamma3 = entry_laws(*law, friction.get(), wear.get(), adhesion.get(), "");
  for (const PartContactLaw& pl : part_laws)
    on_gamma3 +=
        fmt::format("; on {}: {}", fmt::join(pl.parts, ", "), entry_laws(*pl.law, pl.friction.get(), pl.wear.get(), pl.adhesion.get(), ""));
  std::vector<std::string> all;
  if (!parts.empty()) all.push_back(fmt::format("Γ3 (contact): {} ({})", fmt::join(parts, ", "), on_gamma3));
  const auto entries = laws();  // a pair's own law or [contact]'s
  for (std::size_t q = 0; q < pairs.size(); ++q)
    all.push_back(fmt::format("pair: slave {}, master {} ({}, {} sliding)", pairs[q].slave, pairs[q].master,
                              entry_laws(*entries[static_cast<std::size_t>(pair_law_index(q))], pairs[q].friction.get(),
                                         pairs[q].wear.get(), pairs[q].adhesion.get(), ", frictionless"),
                              pairs[q].large_sliding ? "large" : "small"));
  return all;
}

double contact_miss_gap(const Point& lo, const Point& hi) { return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]); }

void check_gap(const Mesh& mesh, const ContactSpec& contact, const MeshBlock* block) {
  if (!contact.obstacles.empty()) return;  // needs the directions: checked by contact_rows
  for (int i : mesh.nodes_of_parts(contact.parts)) {
    const Point& x = mesh.node(i);
    const double g = contact.gap(x, 0.0);
    // NaN compares false with everything: test finiteness first so that it is not called negative.
    require(std::isfinite(g), "the gap g is not finite ({}) at contact node {} ({}, {}, {})", g, node_number(block, i), x[0],
            x[1], x[2]);
    require(g >= 0, "the gap g must be >= 0; it is {} at contact node {} ({}, {}, {})", g, node_number(block, i), x[0], x[1],
            x[2]);
  }
}

}  // namespace vpc
