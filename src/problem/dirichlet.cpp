// The Dirichlet data of SPEC §6: which displacement components are prescribed,
// by which condition, and the parts whose reactions are reported.
#include "core/error.hpp"
#include "problem/problem.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace vpc {

namespace {

constexpr const char* kAxis[] = {"x", "y", "z"};

/// The extent of the mesh (the largest side of its bounding box), for relative tolerances.
double mesh_extent(const Mesh& mesh) {
  double extent = 0;
  for (int j = 0; j < mesh.dim(); ++j) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Point& x : mesh.nodes()) {
      lo = std::min(lo, x[j]);
      hi = std::max(hi, x[j]);
    }
    extent = std::max(extent, hi - lo);
  }
  return extent;
}

}  // namespace

std::vector<std::string> dirichlet_parts(const Problem& p) {
  std::vector<std::string> parts;
  auto add = [&](const std::string& name) {
    if (std::find(parts.begin(), parts.end(), name) == parts.end()) parts.push_back(name);
  };
  for (const auto& name : p.clamped) add(name);
  for (const PrescribedDisplacement& d : p.displacement)
    for (const auto& name : d.parts) add(name);
  for (const auto& name : p.symmetry) add(name);
  return parts;
}

int symmetry_axis(const Mesh& mesh, const std::string& part, const MeshBlock* block) {
  const std::vector<int> nodes = mesh.nodes_of_parts({part});
  require(!nodes.empty(), "symmetry part '{}' has no boundary facets in the mesh", part);
  const double tol = 1e-9 * std::max(mesh_extent(mesh), 1e-300);
  for (int i = 0; i < mesh.dim(); ++i) {
    const double x0 = mesh.node(nodes.front())[i];
    if (std::all_of(nodes.begin(), nodes.end(), [&](int n) { return std::abs(mesh.node(n)[i] - x0) <= tol; }))
      return i;
  }
  const Point& x = mesh.node(nodes.front());
  fail("symmetry part '{}' does not lie in a plane x = const, y = const{}: a symmetry plane (roller) prescribes "
       "the displacement component normal to an axis-aligned plane (its node {} is at ({}, {}, {}))",
       part, mesh.dim() == 3 ? " or z = const" : "", node_number(block, nodes.front()), x[0], x[1], x[2]);
}

DirichletDofs dirichlet_dofs(const Problem& p) {
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim(), n = mesh.n_nodes();
  DirichletDofs out;
  out.condition.assign(static_cast<std::size_t>(n) * d, -1);
  out.parts = dirichlet_parts(p);
  require(out.parts.size() <= 64, "{}: at most 64 clamped, displacement and symmetry parts (got {})", p.name,
          out.parts.size());
  out.on_parts.assign(static_cast<std::size_t>(n), 0);
  for (std::size_t j = 0; j < out.parts.size(); ++j)
    for (int node : mesh.nodes_of_parts({out.parts[j]})) out.on_parts[node] |= std::uint64_t{1} << j;

  out.components.assign(out.parts.size(), 0);
  auto part_prescribes = [&](const std::string& part, unsigned mask) {
    out.components[std::find(out.parts.begin(), out.parts.end(), part) - out.parts.begin()] |= mask;
  };
  // A condition that prescribes a dof: what it is and where the case gives it (Problem::where:
  // "case.toml:12:1: boundary.displacement[0]"), for the messages.
  struct Condition {
    std::string what, at;
  };
  // What set each prescribed dof, for the message of a conflict.
  std::vector<Condition> by(out.condition.size());
  auto value = [&](int k, int c, const Point& x, double t) { return k == 0 ? 0.0 : p.displacement[k - 1].value[c](x, t); };
  auto prescribe = [&](int node, int c, int k, const Condition& cond) {
    const Point& x = mesh.node(node);
    const std::size_t i = static_cast<std::size_t>(node) * d + c;
    for (double t : {0.0, p.final_time}) {
      const double v = value(k, c, x, t);
      require(std::isfinite(v), "{}: {} gives u{} = {} (not finite) at t = {} at node {} ({}, {}, {})", cond.at,
              cond.what, kAxis[c], v, t, p.node_number(node), x[0], x[1], x[2]);
      if (out.condition[i] < 0) continue;
      const double before = value(out.condition[i], c, x, t);
      // Located at the later condition; the message names both, each with its place in the file.
      require(std::abs(v - before) <= 1e-12 * std::max({1.0, std::abs(v), std::abs(before)}),
              "{}: u{} at node {} ({}, {}, {}) is prescribed twice with different values at t = {}: {} by {} at {}, "
              "and {} by {} at {}; restrict one of the parts",
              cond.at, kAxis[c], p.node_number(node), x[0], x[1], x[2], t, before, by[i].what, by[i].at, v, cond.what,
              cond.at);
    }
    if (out.condition[i] >= 0) return;
    out.condition[i] = k;
    by[i] = cond;
  };
  for (const auto& part : p.clamped) part_prescribes(part, (1u << d) - 1);
  const Condition clamped{"the clamped part Γ1", p.where("boundary.clamped")};
  for (int node : mesh.nodes_of_parts(p.clamped))
    for (int c = 0; c < d; ++c) prescribe(node, c, 0, clamped);
  for (const auto& part : p.symmetry) {
    // A block of the mesh (Problem::block) may not meet the part: its axis is then found by the
    // ranks whose blocks do (block_part_pieces).
    if (p.block && mesh.part_size(part) == 0) continue;
    const int c = located(p.where("boundary.symmetry"), [&] { return symmetry_axis(mesh, part, p.block.get()); });
    part_prescribes(part, 1u << c);
    const Condition symmetry{fmt::format("symmetry part '{}'", part), p.where("boundary.symmetry")};
    for (int node : mesh.nodes_of_parts({part})) prescribe(node, c, 0, symmetry);
  }
  for (std::size_t k = 0; k < p.displacement.size(); ++k) {
    const PrescribedDisplacement& bc = p.displacement[k];
    const Condition what{fmt::format("[[boundary.displacement]] {} (parts {})", k + 1, fmt::join(bc.parts, ", ")),
                         p.where(fmt::format("boundary.displacement[{}]", k))};
    for (const auto& part : bc.parts)
      for (int c = 0; c < d; ++c)
        if (bc.value[c]) part_prescribes(part, 1u << c);
    for (int node : mesh.nodes_of_parts(bc.parts))
      for (int c = 0; c < d; ++c)
        if (bc.value[c]) prescribe(node, c, static_cast<int>(k) + 1, what);
  }
  return out;
}

}  // namespace vpc
