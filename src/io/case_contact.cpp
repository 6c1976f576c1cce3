// [contact] (gap, direction, the normal and friction laws, wear), [[contact.part]], [[contact.pair]] and
// [[obstacle]]: the case's ContactSpec. The laws read their own keys (contact/registry.hpp,
// contact/friction_law.hpp) through a Section (SectionKeys, SectionFrictionKeys).
#include "io/case_readers.hpp"

#include "contact/registry.hpp"
#include "core/error.hpp"
#include "core/quote.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace vpc::case_file {

namespace {

/// `direction`: "normal" (unset) or a fixed non-zero vector.
std::optional<Point> read_contact_direction(Section& ct, int d) {
  if (!ct.has("direction")) return std::nullopt;
  if (ct.get("direction")->is_string()) {
    ct.choice("direction", {"normal"});
    return std::nullopt;
  }
  const auto v = ct.numbers("direction", d);
  Point dir{0, 0, 0};
  for (int i = 0; i < d; ++i) dir[i] = v[i];
  if (std::hypot(dir[0], dir[1], dir[2]) == 0) fail("{}: expected a non-zero vector", ct.where("direction"));
  return dir;
}

/// A unit vector from `key` (d numbers, not all zero).
Point unit_vector(Section& s, const std::string& key, int d) {
  const auto v = s.numbers(key, static_cast<size_t>(d));
  Point u{0, 0, 0};
  for (int i = 0; i < d; ++i) u[i] = v[i];
  const double l = std::hypot(u[0], u[1], u[2]);
  if (l == 0) fail("{}: expected a non-zero vector", s.where(key));
  for (double& c : u) c /= l;
  return u;
}

/// One [[obstacle]]: its shape, its position (formulas in t) and size.
Obstacle read_obstacle(Section& s, int k, int d) {
  Obstacle o;
  o.name = s.string("name", fmt::format("obstacle{}", k + 1));
  const std::string shape = s.choice("shape", {"plane", "sphere", "cylinder"});
  o.shape = shape == "plane" ? Obstacle::Shape::Plane : shape == "sphere" ? Obstacle::Shape::Sphere : Obstacle::Shape::Cylinder;
  const std::string at = o.shape == Obstacle::Shape::Plane ? "point" : "center";
  auto position = s.state_expressions(at, d, Expression::Kind::SpaceTime);
  for (const auto& e : position)
    if (e->uses_position())
      fail("{}: the position of an obstacle is a formula in t only (got {})", s.where(at), quote_formula(e->text()));
  o.position = vector_field(std::move(position));
  if (o.shape == Obstacle::Shape::Plane) {
    o.normal = unit_vector(s, "normal", d);
  } else {
    o.radius = s.number("radius");
    if (!(o.radius > 0)) fail("{}: expected a radius > 0, got {}", s.where("radius"), o.radius);
  }
  if (o.shape == Obstacle::Shape::Cylinder && d == 3) o.axis = unit_vector(s, "axis", d);
  return o;
}

/// `key`: parts of Γ3 (a subset of [boundary] contact), or none when the key is absent.
std::vector<std::string> contact_parts(Section& s, const std::string& key, const Problem& p) {
  if (!s.has(key)) return {};
  const auto parts = s.strings(key);
  if (parts.empty()) fail("{}: expected at least one contact part name", s.where(key));
  for (const auto& part : parts)
    if (std::find(p.contact.parts.begin(), p.contact.parts.end(), part) == p.contact.parts.end())
      fail("{}: {} is not a contact part; [boundary] contact has: {}", s.where(key), quote(part), fmt::join(p.contact.parts, ", "));
  return parts;
}

/// A law's keys as a Section's (located errors; each key read is a known one for finish()).
class SectionKeys final : public LawKeys {
 public:
  explicit SectionKeys(Section& s) : s_(s) {}
  bool has(const std::string& key) override { return s_.has(key); }
  double number(const std::string& key) override { return s_.number(key); }
  double number(const std::string& key, double fallback) override { return s_.number(key, fallback); }
  std::string where(const std::string& key) override { return s_.where(key); }

 private:
  Section& s_;
};

/// A friction law's keys: a number or a formula (mu in x, y, z; friction_bound also in t),
/// registered for the per-step finiteness check.
class SectionFrictionKeys final : public FrictionKeys {
 public:
  explicit SectionFrictionKeys(Section& s) : s_(s) {}
  bool has(const std::string& key) override { return s_.has(key); }
  double number(const std::string& key) override { return s_.number(key); }
  double number(const std::string& key, double fallback) override { return s_.number(key, fallback); }
  std::string where(const std::string& key) override { return s_.has(key) ? s_.where(key) : s_.where_section(); }
  LawField field(const std::string& key, bool time) override {
    std::shared_ptr<const Expression> e =
        s_.state_expression(key, time ? Expression::Kind::SpaceTime : Expression::Kind::Space);
    return [e](const Point& x, double t) { return (*e)(x, t); };
  }
  bool is_number(const std::string& key) override { return s_.get(key) && s_.get(key)->is_number(); }
  bool uses_time(const std::string& key) override {
    return s_.get(key) && s_.get(key)->is_string() && s_.expression(key, Expression::Kind::SpaceTime)->uses_time();
  }

 private:
  Section& s_;
};

/// The friction law of a [contact], [[contact.part]] or [[contact.pair]] table (SPEC §7): friction = "none",
/// "coulomb" (mu) or "tresca" (friction_bound); `inherited` where the table has no friction key.
std::shared_ptr<const FrictionLaw> read_friction_law(Section& s, std::shared_ptr<const FrictionLaw> inherited, int dim) {
  if (!s.has("friction")) {
    for (const std::string& k : friction_keys())
      if (s.has(k))
        fail("{}: {} needs friction = \"{}\" in the same table", s.where(k), k, k == "friction_bound" ? "tresca" : "coulomb");
    return inherited;
  }
  const std::string name = s.choice("friction", friction_law_names(), "none");
  if (name != "none" && dim < 2)
    fail("{}: friction needs a body of dimension 2 or 3 (a 1D bar has no tangential direction)", s.where("friction"));
  SectionFrictionKeys keys(s);
  return make_friction_law(name, keys);
}

/// What `key` of a table names, "none" or `law` (a surface law of SPEC §9: wear, adhesion); nothing where the
/// table has no `key`, which then takes [contact]'s: a key of the law (`law_keys`) without it is a located error.
std::optional<std::string> surface_law_choice(Section& s, const std::string& key, const std::string& law,
                                              const std::vector<std::string>& law_keys) {
  if (!s.has(key)) {
    for (const std::string& k : law_keys)
      if (s.has(k)) fail("{}: {} needs {} = \"{}\" in the same table", s.where(k), k, key, law);
    return std::nullopt;
  }
  return s.choice(key, {"none", law}, "none");
}

/// The wear of a [contact], [[contact.part]] or [[contact.pair]] table (SPEC §9): wear = "none" or
/// "archard" (wear_coefficient, wear_cap, wear_warning); `inherited` where the table has no wear key.
std::shared_ptr<const ArchardWear> read_wear_law(Section& s, std::shared_ptr<const ArchardWear> inherited, int dim) {
  const std::optional<std::string> name = surface_law_choice(s, "wear", "archard", wear_keys());
  if (!name) return inherited;
  if (*name != "none" && dim < 2)
    fail("{}: wear needs a body of dimension 2 or 3 (Archard's wear follows the tangential slip, which a 1D bar "
         "does not have)",
         s.where("wear"));
  SectionFrictionKeys keys(s);
  return make_wear_law(*name, keys);
}

/// SPEC §9's tangential bond (bond_shear_stiffness) on a table whose friction and wear are `friction`, `wear`:
/// refused with either (the bond's spring and the friction or the slip that wears would act on one tangential
/// force in parallel, which no solver here takes apart) and in 1D (no tangents).
void check_shear_bond(Section& s, const FremondAdhesion* adhesion, const FrictionLaw* friction, const ArchardWear* wear,
                      int dim) {
  if (!adhesion || !adhesion->shears()) return;
  const std::string key = s.has("bond_shear_stiffness") ? "bond_shear_stiffness" : "adhesion";
  if (dim < 2) fail("{}: a tangential bond (bond_shear_stiffness) needs a body of dimension 2 or 3", s.where(key));
  if (friction || wear)
    fail("{}: a tangential bond (bond_shear_stiffness) is solved on frictionless contact without wear; this table "
         "also has {}: the bond's spring and {} would share one tangential force (remove one of them here)",
         s.where(key), friction ? "friction" : "wear", friction ? "the friction" : "the wearing slip");
}

/// The adhesion of a [contact], [[contact.part]] or [[contact.pair]] table (SPEC §9): adhesion = "none"
/// or "fremond" (bond_stiffness, bond_length, bond_viscosity, adhesion_energy, bonding); `inherited`
/// where the table has no adhesion key.
std::shared_ptr<const FremondAdhesion> read_adhesion_law(Section& s, std::shared_ptr<const FremondAdhesion> inherited) {
  const std::optional<std::string> name = surface_law_choice(s, "adhesion", "fremond", adhesion_keys());
  if (!name) return inherited;
  SectionFrictionKeys keys(s);
  return make_adhesion_law(*name, keys);
}

/// A contact law: `law`, a name in the registry (contact/registry.cpp; default "signorini"),
/// which reads its own keys (normal-compliance: stiffness c > 0, exponent e ≥ 1).
std::shared_ptr<const ContactLaw> read_contact_law(Section& s) {
  const std::string name = s.choice("law", contact_law_names(), "signorini");
  SectionKeys keys(s);
  return make_contact_law(name, keys);
}

}  // namespace

/// [[obstacle]] sections (instead of [contact] gap).
void read_obstacles(Section& top, Problem& p, const Origins& origins, bool gap_given) {
  if (!top.has("obstacle")) return;
  const toml::node* list = top.get("obstacle");
  if (!list->is_array_of_tables()) top.expected("obstacle", "an array of tables [[obstacle]] with shape and position");
  if (gap_given) fail("{}: a case has either [contact] gap or [[obstacle]] sections, not both", top.where("obstacle"));
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("obstacle[{}]", k), origins);
    p.contact.obstacles.push_back(read_obstacle(s, k++, p.mesh.dim()));
    p.contact.obstacles.back().parts = contact_parts(s, "parts", p);
    s.finish();
  }
}

namespace {

/// [[contact.pair]] (SPEC §8): slave and master, boundary parts of two bodies; `search`; a normal
/// law and a friction law, each [contact]'s where the pair gives none; `sliding`.
void read_contact_pairs(Section& ct, Problem& p, const Origins& origins) {
  if (!ct.has("pair")) return;
  const toml::node* list = ct.get("pair");
  if (!list->is_array_of_tables()) ct.expected("pair", "an array of tables [[contact.pair]] with slave and master");
  const bool check = p.mesh.n_cells() > 0 && !p.block;  // the rank that built the whole mesh
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("contact.pair[{}]", k++), origins);
    ContactPair pair;
    for (auto [key, part] : {std::pair{"slave", &pair.slave}, std::pair{"master", &pair.master}}) {
      *part = s.string(key);
      if (check && p.mesh.part_size(*part) == 0)
        fail("{}: boundary part {} does not exist in the mesh (or has no facets); the mesh has: {}", s.where(key),
             quote(*part), printable(fmt::format("{}", fmt::join(p.mesh.part_names(), ", ")), 300));
    }
    pair.search = s.number("search", 0.0);
    if (s.has("law")) {
      pair.law = read_contact_law(s);
    } else {  // [contact]'s law; a compliance parameter alone is a forgotten law
      for (const std::string& k : compliance_keys())
        if (s.has(k)) fail("{}: {} needs law = \"normal-compliance\" in the same table", s.where(k), k);
    }
    pair.friction = read_friction_law(s, p.contact.friction, p.mesh.dim());
    pair.wear = read_wear_law(s, p.contact.wear, p.mesh.dim());
    pair.adhesion = read_adhesion_law(s, p.contact.adhesion);
    check_shear_bond(s, pair.adhesion.get(), pair.friction.get(), pair.wear.get(), p.mesh.dim());
    pair.large_sliding = s.choice("sliding", {"small", "large"}, "small") == "large";
    // A bond ties a slave node to the master material it touched at bonding; large sliding rebuilds
    // the rows against whatever master the node faces at each step, which would carry the bond along.
    if (pair.large_sliding && pair.adhesion)
      fail("{}: adhesion on a pair with sliding = \"large\" is refused: the bond ties a slave node to the master "
           "material it was bonded to, while large sliding pairs it with the master it faces at each step; use "
           "sliding = \"small\" (or adhesion = \"none\" on this pair)",
           s.where("sliding"));
    if (!(pair.search >= 0) || !std::isfinite(pair.search))
      fail("{}: expected a distance >= 0 (0: the slave part's longest facet edge)", s.where("search"));
    s.finish();
    p.contact.pairs.push_back(std::move(pair));
  }
}

}  // namespace

/// Returns whether a gap was given.
bool read_contact(Section ct, Problem& p, const Origins& origins) {
  const auto gap = ct.has("gap") ? ct.state_expression("gap", Expression::Kind::SpaceTime) : nullptr;
  p.contact.gap = [gap](const Point& x, double t) { return gap ? (*gap)(x, t) : 0.0; };
  p.contact.gap_moves = gap && gap->uses_time();
  located(ct.where("gap"), [&] { check_gap(p.mesh, p.contact, p.block.get()); });
  p.contact.direction = read_contact_direction(ct, p.mesh.dim());
  p.contact.law = read_contact_law(ct);
  p.contact.friction = read_friction_law(ct, nullptr, p.mesh.dim());
  p.contact.wear = read_wear_law(ct, nullptr, p.mesh.dim());
  p.contact.adhesion = read_adhesion_law(ct, nullptr);
  check_shear_bond(ct, p.contact.adhesion.get(), p.contact.friction.get(), p.contact.wear.get(), p.mesh.dim());
  p.contact.held_by_bond = ct.boolean("held_by_bond", false);
  if (p.contact.held_by_bond && !p.contact.adhesion && !ct.has("part"))
    fail("{}: held_by_bond = true, but [contact] has no adhesion: a bond holds a body only where adhesion = "
         "\"fremond\" bonds it", ct.where("held_by_bond"));
  if (ct.has("part")) {  // [[contact.part]]: another law on some parts
    const toml::node* list = ct.get("part");
    if (!list->is_array_of_tables())
      ct.expected("part", "an array of tables [[contact.part]] with parts and law (stiffness, exponent)");
    int k = 0;
    for (const auto& node : *list->as_array()) {
      Section s(node.as_table(), fmt::format("contact.part[{}]", k++), origins);
      PartContactLaw pl;
      pl.parts = contact_parts(s, "parts", p);
      if (pl.parts.empty()) s.expected("parts", "the contact parts this law acts on");
      for (const auto& part : pl.parts)
        for (const PartContactLaw& other : p.contact.part_laws)
          if (std::find(other.parts.begin(), other.parts.end(), part) != other.parts.end())
            fail("{}: contact part {} has a law already (an earlier [[contact.part]])", s.where("parts"), quote(part));
      pl.law = read_contact_law(s);
      pl.friction = read_friction_law(s, p.contact.friction, p.mesh.dim());
      pl.wear = read_wear_law(s, p.contact.wear, p.mesh.dim());
      pl.adhesion = read_adhesion_law(s, p.contact.adhesion);
      check_shear_bond(s, pl.adhesion.get(), pl.friction.get(), pl.wear.get(), p.mesh.dim());
      s.finish();
      p.contact.part_laws.push_back(std::move(pl));
    }
  }
  read_contact_pairs(ct, p, origins);
  ct.finish();
  return gap != nullptr;
}

}  // namespace vpc::case_file
