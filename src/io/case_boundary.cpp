// [boundary] (Γ1 clamped, prescribed displacements, symmetry planes, Γ3 contact, Γ2 traction) and
// [loads] (f0, f2, [[loads.pressure]]): the data on the boundary parts, checked against the mesh.
#include "io/case_readers.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"
#include "mesh/gmsh_reader.hpp"

#include <algorithm>

namespace vpc::case_file {

VectorField vector_field(std::vector<std::shared_ptr<const Expression>> e) {
  return [e = std::move(e)](const Point& x, double t) {
    Point v{0, 0, 0};
    for (size_t i = 0; i < e.size(); ++i) v[i] = (*e[i])(x, t);
    return v;
  };
}

namespace {

/// `check`: whether the parts must exist in the problem's mesh (not on a rank that did not build
/// it; on a block, MeshBlock::required_parts keeps the check for all ranks together).
std::vector<std::string> read_parts(Section& b, const std::string& key, Problem& problem, bool required, bool check) {
  if (!required && !b.has(key)) return {};
  const auto parts = b.strings(key);
  if (parts.empty()) fail("{}: expected at least one boundary part name", b.where(key));
  for (const auto& p : parts) {
    const std::string missing =
        fmt::format("{}: boundary part {} does not exist in the mesh (or has no facets); the mesh has: ", b.where(key), quote(p));
    if (check && problem.mesh.part_size(p) == 0) fail("{}{}", missing, describe_parts(problem.mesh));
    if (problem.block) problem.block->checks.push_back({MeshBlock::Check::Of::part, p, missing, true});
  }
  return parts;
}

/// [[boundary.displacement]]: prescribed components ux, uy, uz (formulas in x, y, z, t) on named parts.
void read_displacements(Section& b, Problem& p, const Origins& origins, bool check) {
  if (!b.has("displacement")) return;
  const toml::node* list = b.get("displacement");
  if (!list->is_array_of_tables())
    b.expected("displacement", "an array of tables [[boundary.displacement]] with parts and ux, uy or uz");
  const int d = p.mesh.dim();
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("boundary.displacement[{}]", k++), origins);
    PrescribedDisplacement bc;
    bc.parts = read_parts(s, "parts", p, true, check);
    for (int c = 0; c < 3; ++c) {
      const std::string key = std::string("u") + "xyz"[c];
      if (!s.has(key)) continue;
      if (c >= d) fail("{}: the mesh has d = {}: its components are {}", s.where(key), d, d == 1 ? "ux" : "ux, uy");
      const auto e = s.state_expression(key, Expression::Kind::SpaceTime);
      bc.value[c] = [e](const Point& x, double t) { return (*e)(x, t); };
    }
    if (std::none_of(bc.value.begin(), bc.value.end(), [](const ScalarField& f) { return static_cast<bool>(f); }))
      fail("{}: expected at least one of {} (a formula in x, y, z, t)", s.where_section(),
           d == 1 ? "ux" : d == 2 ? "ux, uy" : "ux, uy, uz");
    s.finish();
    p.displacement.push_back(std::move(bc));
  }
}

}  // namespace

/// `pairs`: the case has [[contact.pair]]s, and Γ3 (`contact`) may then be left out; `held_by_bond`:
/// [contact] says its bonds hold a body, and Γ1 may be left out (Problem::validate checks what holds it).
void read_boundary(Section b, Problem& p, const Origins& origins, bool check, bool pairs, bool held_by_bond) {
  if (!b.exists()) fail("{}: missing section [boundary] (clamped and contact parts)", origins.file);
  read_displacements(b, p, origins, check);
  p.symmetry = read_parts(b, "symmetry", p, false, check);
  if (check)
    for (const auto& part : p.symmetry) located(b.where("symmetry"), [&] { symmetry_axis(p.mesh, part); });
  // Γ1 may be left out when prescribed displacements or symmetry planes hold the body.
  const bool unheld = p.displacement.empty() && p.symmetry.empty() && !held_by_bond;
  if (unheld && !b.has("clamped"))
    fail("{}: missing key 'boundary.clamped': nothing holds the body: give the clamped parts Γ1 (a string or an array "
         "of strings), prescribed displacements ([[boundary.displacement]]) or symmetry parts; or, where adhesion "
         "alone holds it, [contact] held_by_bond = true",
         b.where_section());
  p.clamped = read_parts(b, "clamped", p, unheld, check);
  p.contact.parts = read_parts(b, "contact", p, !pairs, check);
  p.traction = read_parts(b, "traction", p, false, check);
  b.finish();
}

namespace {

/// [[loads.pressure]]: a normal pressure p(x, t) on named parts.
void read_pressure(Section& l, Problem& p, const Origins& origins, bool check) {
  if (!l.has("pressure")) return;
  const toml::node* loads = l.get("pressure");
  if (!loads->is_array_of_tables()) l.expected("pressure", "an array of tables [[loads.pressure]] with parts and p");
  int i = 0;
  for (const auto& node : *loads->as_array()) {
    Section s(node.as_table(), fmt::format("loads.pressure[{}]", i++), origins);
    PressureLoad load;
    load.parts = read_parts(s, "parts", p, true, check);
    const auto pressure = s.state_expression("p", Expression::Kind::SpaceTime);
    load.p = [pressure](const Point& x, double t) { return (*pressure)(x, t); };
    s.finish();
    p.pressure.push_back(std::move(load));
  }
}

}  // namespace

void read_loads(Section l, Problem& p, const Origins& origins, bool check) {
  auto load = [&](const char* key, bool& uniform) {
    if (!l.has(key)) return VectorField{};
    auto e = l.state_expressions(key, p.mesh.dim(), Expression::Kind::SpaceTime);
    uniform = std::none_of(e.begin(), e.end(), [](const auto& f) { return f->uses_position(); });
    return vector_field(std::move(e));
  };
  p.f0 = load("f0", p.f0_uniform);
  p.f2 = load("f2", p.f2_uniform);
  read_pressure(l, p, origins, check);
  l.finish();
}

}  // namespace vpc::case_file
