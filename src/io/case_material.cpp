// The material of the body and its parts: [elasticity], [viscoplasticity] (G by name, with its
// parameters), [damage] (κ, β0, φ), [[material]] and the materials of [[body]]; and the warning
// for ν near 1/2 (locking).
#include "io/case_readers.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"
#include "material/sources/expression_source.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <set>

namespace vpc::case_file {

Elasticity read_elasticity(Section e, int d, const std::string& file) {
  if (!e.exists()) fail("{}: missing section [elasticity] (kind, E, nu)", file);
  const std::string default_kind = d == 1 ? "1d" : (d == 3 ? "isotropic" : "");
  const std::string kind = e.choice("kind", {"1d", "plane-stress", "plane-strain", "isotropic"}, default_kind);
  const double young = e.number("E");
  const double nu = d == 1 ? e.number("nu", 0.0) : e.number("nu");
  const Elasticity elasticity = located(e.where_section(), [&] { return Elasticity::from_name(kind, young, nu); });
  if (elasticity.dim() != d)
    fail("{}: elasticity '{}' is for d = {} but the mesh has d = {}", e.where("kind"), kind, elasticity.dim(), d);
  e.finish();
  return elasticity;
}

namespace {

/// [material.elasticity]: E and nu of another material; the kind is the body's, and
/// a key left out keeps the body's value.
Elasticity read_material_elasticity(Section e, const Elasticity& body) {
  if (e.has("kind") && e.string("kind") != body.name())
    fail("{}: every material of a body has the body's kind '{}' (the stresses have the same components); "
         "leave kind out", e.where("kind"), body.name());
  const double young = e.number("E", body.young()), nu = e.number("nu", body.poisson());
  const Elasticity elasticity = located(e.where_section(), [&] { return Elasticity(body.kind(), young, nu); });
  e.finish();
  return elasticity;
}

Parameters law_parameters(Section& s) {
  Parameters p;
  for (const auto& k : s.remaining()) p.set(k, s.number(k));
  return p;
}

/// If a law rejected a parameter it does not know, say where it is and what the
/// law's parameters are.
void unknown_parameter(Section& s, const Parameters& params, const std::string& law,
                       const std::vector<std::string>& names) {
  const auto unused = params.unused();
  if (unused.empty()) return;
  std::set<std::string> candidates(names.begin(), names.end());
  candidates.insert(s.known().begin(), s.known().end());  // a misspelt key of the section itself
  for (const auto& u : unused) candidates.erase(u);
  fail("{}: unknown key or parameter of the {}{}; its parameters are: {}", s.where(unused.front()), law,
       did_you_mean(unused.front(), candidates), names.empty() ? "(none)" : fmt::format("{}", fmt::join(names, ", ")));
}

}  // namespace

/// [viscoplasticity]: G, named, with its parameters (Perzyna's E defaults to ℰ's).
std::shared_ptr<const ViscoplasticLaw> read_viscoplasticity(Section v, double young) {
  const std::string law = v.choice("law", viscoplastic_law_names(), "elastic");
  Parameters params = law_parameters(v);
  if (law.rfind("perzyna", 0) == 0 && !params.has("E")) params.set("E", young);
  try {
    return make_viscoplastic_law(law, params);
  } catch (const Error& err) {
    unknown_parameter(v, params, "viscoplastic law '" + law + "'", viscoplastic_law_parameters(law));
    fail("{}: [viscoplasticity]: {}", v.where_section(), err.what());
  }
}

namespace {

/// φ: a formula (`phi`), or a named source with its parameters.
std::shared_ptr<const DamageSource> read_damage_source(Section& dm) {
  if (dm.has("phi")) {
    if (dm.has("source") && dm.string("source") != "expression")
      fail("{}: give either source = \"<name>\" or phi = \"<formula>\", not both", dm.where("phi"));
    return std::make_shared<ExpressionSource>(dm.state_expression("phi", Expression::Kind::PointState));
  }
  const std::string src = dm.choice("source", damage_source_names(), "zero");
  Parameters params = law_parameters(dm);
  try {
    return make_damage_source(src, params);
  } catch (const Error& err) {
    unknown_parameter(dm, params, "damage source '" + src + "'", damage_source_parameters(src));
    fail("{}: [damage]: {}", dm.where_section(), err.what());
  }
}

}  // namespace

void read_damage(Section dm, Problem& p) {
  p.kappa = dm.number("kappa", 1.0);
  located(dm.where("kappa"), [&] { check_kappa(p.kappa); });
  const auto b0 = dm.has("beta0") ? dm.expression("beta0", Expression::Kind::Space) : nullptr;
  if (b0) {
    p.beta0 = [b0](const Point& x, double) { return (*b0)(x); };
    located(dm.where("beta0"), [&] { check_beta0(p.mesh, p.beta0, p.mesh.n_bodies() > 1 ? 0 : -1, p.block.get()); });
  } else {
    p.beta0 = [](const Point&, double) { return 1.0; };
  }
  p.source = read_damage_source(dm);
  dm.finish();
}

/// [[material]]: further materials, each on Gmsh regions (`regions`: physical groups of
/// the mesh's dimension) or on the cells whose centroid satisfies `where`; a later one
/// takes the cells it selects from an earlier one. [material.elasticity],
/// [material.viscoplasticity] and [material.damage] left out are the body's.
/// `build`: this process has the mesh (the regions can be checked and tagged).
void read_materials(Section& top, Problem& p, const Origins& origins, bool build) {
  if (!top.has("material")) return;
  const toml::node* list = top.get("material");
  if (!list->is_array_of_tables())
    top.expected("material", "an array of tables [[material]] with name and regions or where");
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("material[{}]", k++), origins);
    Material m;
    m.name = s.string("name");
    const bool taken = m.name == "body" || std::any_of(p.materials.begin(), p.materials.end(),
                                                       [&](const Material& o) { return o.name == m.name; });
    if (m.name.empty() || taken)
      fail("{}: expected a new material name (\"body\" is the body's material{})", s.where("name"),
           m.name.empty() ? "" : fmt::format("; {} is taken", quote(m.name)));
    if (s.has("regions") == s.has("where"))
      fail("{}: expected either regions (Gmsh physical groups of dimension {}) or where (a predicate on the cell "
           "centroid), not {}", s.where_section(), p.mesh.dim(), s.has("where") ? "both" : "neither");
    if (s.has("regions")) {
      m.regions = s.strings("regions");
      if (m.regions.empty()) fail("{}: expected at least one region name", s.where("regions"));
      for (const auto& r : m.regions) {
        const std::string none = fmt::format(
            "{}: the mesh has no cell in region {}; its regions: {}", s.where("regions"), quote(r),
            p.mesh.region_names().empty() ? "(none: give the cells Gmsh physical groups of dimension d)"
                                           : printable(fmt::format("{}", fmt::join(p.mesh.region_names(), ", ")), 300));
        if (build && p.mesh.region_size(r) == 0) fail("{}", none);
        if (p.block) p.block->checks.push_back({MeshBlock::Check::Of::region, r, none});
      }
    } else {
      const auto where = s.expression("where", Expression::Kind::Space);
      if (build && p.mesh.find_region(m.name) >= 0)
        fail("{}: the mesh has a region named {} already; name the material otherwise, or give regions = [{}]",
             s.where("name"), quote(m.name), quote_formula(m.name));
      p.mesh.tag_cells(m.name, [&](const Point& x) { return (*where)(x) != 0.0; });
      const std::string none = fmt::format("{}: the predicate {} selects no cell (it is evaluated at cell centroids)",
                                           s.where("where"), quote_formula(where->text()));
      if (build && p.mesh.region_size(m.name) == 0) fail("{}", none);
      if (p.block) p.block->checks.push_back({MeshBlock::Check::Of::region, m.name, none});
      m.regions = {m.name};
    }
    Section e = s.table("elasticity");
    m.elasticity = e.exists() ? read_material_elasticity(e, p.elasticity) : p.elasticity;
    Section v = s.table("viscoplasticity");
    m.law = v.exists() ? read_viscoplasticity(v, m.elasticity.young()) : p.law;
    Section dm = s.table("damage");
    m.source = p.source;
    if (dm.exists()) {
      for (const char* global : {"kappa", "beta0"})
        if (dm.has(global))
          fail("{}: {} belongs to [damage]: the damage equation is one field over the whole body", dm.where(global),
               global);
      m.source = read_damage_source(dm);
      dm.finish();
    }
    s.finish();
    p.materials.push_back(std::move(m));
  }
}

/// The [[body]] tables' [body.elasticity] (E, nu; the case's kind), [body.viscoplasticity]
/// and [body.damage] (kappa, beta0, the source): each left out, or each key of
/// [body.elasticity] and [body.damage] left out, is the case's.
void read_body_data(std::vector<Section>& sections, Problem& p) {
  for (Section& s : sections) {
    Body b;
    b.name = s.string("name");
    Section e = s.table("elasticity");
    b.material.name = b.name;
    b.material.elasticity = e.exists() ? read_material_elasticity(e, p.elasticity) : p.elasticity;
    Section v = s.table("viscoplasticity");
    b.material.law = v.exists() ? read_viscoplasticity(v, b.material.elasticity.young()) : p.law;
    Section dm = s.table("damage");
    b.kappa = dm.number("kappa", p.kappa);
    located(dm.where("kappa"), [&] { check_kappa(b.kappa); });
    if (dm.has("beta0")) {
      const auto b0 = dm.expression("beta0", Expression::Kind::Space);
      b.beta0 = [b0](const Point& x, double) { return (*b0)(x); };
      const int index = static_cast<int>(p.bodies.size()) + 1;
      located(dm.where("beta0"), [&] { check_beta0(p.mesh, b.beta0, index); });
    } else {
      b.beta0 = p.beta0;
    }
    b.material.source = dm.has("source") || dm.has("phi") ? read_damage_source(dm) : p.source;
    dm.finish();
    s.finish();
    p.bodies.push_back(std::move(b));
  }
}

/// ν near 1/2 locks P1 elements in plane strain and 3D: λ/μ = 2ν/(1 − 2ν) grows without
/// bound, and linear simplices cannot represent a divergence-free displacement field
/// well (volumetric locking): the body is too stiff, its forces too large. Plane stress
/// does not lock (its λ* = 2λμ/(λ + 2μ) stays below 2μ). Above ν = 0.475 (λ/μ = 19), the
/// threshold above which Abaqus recommends its hybrid elements, a coarse mesh's contact
/// force is measured 11 % above a 4× finer one's (24 % at 0.49, 180 % at 0.499; 0.8 % at
/// ν = 0.3): warn, naming the key.
std::vector<std::string> locking_warnings(Section& top, const Problem& p) {
  constexpr double kNuLocking = 0.475;
  std::vector<std::string> warnings;
  auto check = [&](Section e, const Elasticity& elasticity, const std::string& what) {
    const auto kind = elasticity.kind();
    const double nu = elasticity.poisson();
    if ((kind != Elasticity::Kind::PlaneStrain && kind != Elasticity::Kind::Isotropic) || !(nu > kNuLocking)) return;
    warnings.push_back(fmt::format(
        "{}: nu = {} {}is near 1/2 (lambda/mu = {:.3g}): linear (P1) elements lock in {} (volumetric locking: the body "
        "is too stiff and its forces too large, the more so the closer nu is to 1/2); above nu = {} compare with a finer "
        "mesh, or use a smaller nu",
        e.has("nu") ? e.where("nu") : e.where_section(), nu, what, 2 * nu / (1 - 2 * nu),
        kind == Elasticity::Kind::PlaneStrain ? "plane strain" : "3D", kNuLocking));
  };
  check(top.table("elasticity"), p.elasticity, "");
  if (top.has("material") && top.get("material")->is_array_of_tables()) {
    const auto& list = *top.get("material")->as_array();
    for (std::size_t k = 0; k < p.materials.size() && k < list.size(); ++k) {
      Section m(list[k].as_table(), fmt::format("material[{}]", k), top.origins());
      if (m.table("elasticity").has("nu"))
        check(m.table("elasticity"), p.materials[k].elasticity, fmt::format("of material '{}' ", p.materials[k].name));
    }
  }
  if (top.has("body") && top.get("body")->is_array_of_tables()) {
    const auto& list = *top.get("body")->as_array();
    for (std::size_t k = 0; k < p.bodies.size() && k < list.size(); ++k) {
      Section b(list[k].as_table(), fmt::format("body[{}]", k), top.origins());
      if (b.table("elasticity").has("nu"))
        check(b.table("elasticity"), p.bodies[k].material.elasticity, fmt::format("of body '{}' ", p.bodies[k].name));
    }
  }
  return warnings;
}

}  // namespace vpc::case_file
