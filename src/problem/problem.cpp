#include "problem/problem.hpp"

#include "core/error.hpp"
#include "core/expression.hpp"
#include "problem/contact_rows.hpp"
#include "problem/rigid_motions.hpp"
#include "problem/stability.hpp"

#include <Eigen/Dense>
#include <fmt/ranges.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <cmath>
#include <set>

namespace vpc {

void check_kappa(double kappa) {
  require(std::isfinite(kappa) && kappa >= 0, "kappa must be >= 0 (got {})", kappa);
}

void check_final_time(double final_time) {
  require(std::isfinite(final_time) && final_time > 0, "the final time T must be > 0 (got {})", final_time);
}

void check_n_steps(int n_steps) {
  require(n_steps >= 1, "the number of time steps must be >= 1 (got {})", n_steps);
}

int steps_of_time_step(double final_time, double k) {
  require(std::isfinite(k) && k > 0, "the time step must be > 0 (got {})", k);
  const double n = final_time / k;
  require(n <= 1e8, "the time step {} gives {:.3g} steps over T = {}; at most 1e8", k, n, final_time);
  require(std::abs(n - std::round(n)) <= 1e-9 * n,
          "the time step {} does not divide the final time T = {} into whole steps", k, final_time);
  return static_cast<int>(std::round(n));
}

std::string Problem::where(const std::string& key) const {
  const auto it = key_locations.find(key);
  return it != key_locations.end() ? it->second : fmt::format("{}: {}", name.empty() ? "problem" : name, key);
}

std::string Problem::where_in(const std::string& table, const std::string& key) const {
  const std::string path = table + "." + key;
  return key_locations.contains(path) ? where(path) : where(table);
}

double Problem::time_at(int n) const {
  if (!step_times.empty()) return n == 0 ? 0.0 : step_times[static_cast<std::size_t>(n) - 1];
  return n == n_steps ? final_time : n * step();  // exactly (sums of k would accumulate round-off)
}

double Problem::step_at(int n) const {
  if (step_times.empty()) return step();
  return step_sizes.empty() ? time_at(n) - time_at(n - 1) : step_sizes[static_cast<std::size_t>(n) - 1];
}

void Problem::set_fixed_grid(FixedGrid grid) {
  n_steps = static_cast<int>(grid.times.size());
  step_times = std::move(grid.times);
  step_sizes = std::move(grid.sizes);
  step_control.reset();
}

int Problem::step_nearest(double t) const {
  if (step_times.empty()) return std::clamp(static_cast<int>(std::lround(t / step() - 1e-9)), 0, n_steps);
  const auto after = std::lower_bound(step_times.begin(), step_times.end(), t);
  const int n = static_cast<int>(after - step_times.begin()) + 1;  // t_{n−1} < t ≤ t_n
  if (n > n_steps) return n_steps;
  return t - time_at(n - 1) <= time_at(n) - t ? n - 1 : n;
}

int Problem::expected_steps() const {
  if (!step_control) return n_steps;
  return std::max(1, static_cast<int>(std::lround(final_time / stable_step_control(*this).dt_initial)));
}

double Problem::first_step() const { return step_control ? stable_step_control(*this).dt_initial : step_at(1); }

double Problem::largest_step() const {
  if (step_control) return stable_step_control(*this).dt_max;
  double k = 0;
  for (int n = 1; n <= n_steps && !step_times.empty(); ++n) k = std::max(k, step_at(n));
  return step_times.empty() ? step() : k;
}

std::string Problem::describe_steps() const {
  if (step_control) return stable_step_control(*this).describe();
  // 6 significant digits, as below: T / N is often not the decimal it looks like (1.3 / 100 prints
  // as 0.013000000000000001 in its shortest round-trip form).
  if (step_times.empty()) return fmt::format("k = {:.6g}, N = {}", step(), n_steps);
  double lo = INFINITY;
  for (int n = 1; n <= n_steps; ++n) lo = std::min(lo, step_at(n));
  return fmt::format("k in [{:.6g}, {:.6g}], N = {}", lo, largest_step(), n_steps);
}

void check_formulas(const Problem& p) {
  for (const auto& f : p.formulas) f->check_finite();
}

void check_beta0(const Mesh& mesh, const ScalarField& beta0, int body, const MeshBlock* block) {
  if (!beta0) return;  // β0 = 1
  const std::vector<int> of_node = body < 0 ? std::vector<int>() : node_bodies(mesh, cell_bodies(mesh));
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    if (body >= 0 && of_node[static_cast<std::size_t>(i)] != body) continue;
    const Point& x = mesh.node(i);
    const double b = beta0(x, 0.0);
    require(std::isfinite(b) && b >= 0 && b <= 1, "initial damage beta0 must lie in [0, 1]; it is {} at node {} ({}, {}, {})",
            b, node_number(block, i), x[0], x[1], x[2]);
  }
}

namespace {

/// Where the prescribed components (`condition`: DirichletDofs::condition) leave a
/// rigid motion of the body free, the elastic stiffness K is singular and contact cannot
/// hold the body (every contact solver factors or inverts K without it): refused before
/// K's factorization fails, located at [boundary] and naming the free motion. With
/// `[contact] held_by_bond` (SPEC §9) the directions of the body's bonded contact nodes on Γ3 (`rows`:
/// those of its nodes, bonded where α_0 γ_ν > 0) hold it as well: the primal solver then factors K
/// with its bonds' springs, and a step whose load the remaining bonds cannot hold is a pull-off.
/// Throws unless the prescribed dofs among `nodes` (one body's) stop every rigid motion of them.
/// `body`: how the message names the body.
/// The body's box is [lo, hi]; with `sum`, `nodes` are this rank's share of a body on several
/// (Problem::block), whose matrices `sum` adds up over the ranks. Returns whether its bonds hold it.
bool check_body_held(const Problem& p, const std::vector<int>& condition, const std::vector<int>& nodes,
                     const std::vector<ContactRow>& rows, const std::string& body, Point lo, Point hi,
                     const std::function<void(double*, int)>& sum = {}) {
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim();
  const RigidMotions motions(d, lo, hi);
  RigidHold held(motions);
  for (int node : nodes)
    for (int c = 0; c < d; ++c)
      if (condition[static_cast<std::size_t>(node) * d + c] >= 0) held.add_axis(mesh.node(node), c);
  const Eigen::MatrixXd unheld = held.free_motions(sum);
  if (unheld.cols() == 0) return false;
  if (p.contact.held_by_bond) {
    std::vector<char> mine(static_cast<std::size_t>(mesh.n_nodes()), 0);
    for (int node : nodes) mine[static_cast<std::size_t>(node)] = 1;
    const auto adhesions = p.contact.adhesions();
    for (const ContactRow& r : rows) {
      const FremondAdhesion* bond = r.pair < 0 ? adhesions[static_cast<std::size_t>(r.law)].get() : nullptr;
      const Point& x = mesh.node(r.node);
      if (mine[static_cast<std::size_t>(r.node)] && bond && bond->bonding(x) * bond->stiffness(x) > 0)
        held.add(x, r.direction);
    }
    const Eigen::MatrixXd free = held.free_motions(sum);
    if (free.cols() == 0) return true;
    fail("{}: {} is not held: the prescribed displacements (clamped, displacement and symmetry parts) leave {} "
         "free, and its bonded contact nodes (held_by_bond) do not stop it either (a bond pulls along the contact "
         "direction only): prescribe components that stop this motion (a symmetry part, a displacement)",
         p.where("boundary"), body, motions.describe(free.col(0)));
  }
  fail("{}: {} is not held: the prescribed displacements (clamped, displacement and symmetry parts) leave {} "
       "free, so the elastic stiffness K is singular; contact cannot hold the body (K must be positive definite "
       "without it){}: clamp a part, or prescribe components that stop this motion",
       p.where("boundary"), body, motions.describe(unheld.col(0)),
       // SPEC §9: a bond's pull holds a body only while it lasts; a body it alone held flies off at pull-off.
       p.contact.adhesive() ? "; adhesion holds it only where the case says so ([contact] held_by_bond = true: the "
                              "run then ends at pull-off, where the remaining bond can no longer hold the load)"
                            : "");
}

/// The body whose facets form `part` (-1: the part spans several bodies).
int body_of_part(const Mesh& mesh, const std::string& part) {
  int body = -2;
  for (int f : mesh.facets_of_parts({part})) {
    const int b = mesh.cell_body(mesh.facet_cell(f));
    body = body == -2 || body == b ? b : -1;
  }
  return body;
}

/// Contact pairs (SPEC §8): a slave and a master part, each of one body, of two bodies, off Γ3;
/// any normal law and friction.
void check_pairs(const Problem& p) {
  for (std::size_t q = 0; q < p.contact.pairs.size(); ++q) {
    const ContactPair& pair = p.contact.pairs[q];
    const std::string at = p.where(fmt::format("contact.pair[{}]", q));
    int bodies[2];
    for (int s = 0; s < 2; ++s) {
      const std::string& part = s == 0 ? pair.slave : pair.master;
      require(p.mesh.part_size(part) > 0, "{}: part '{}' has no boundary facets in the mesh", at, part);
      bodies[s] = body_of_part(p.mesh, part);
      require(bodies[s] >= 0, "{}: part '{}' has facets of several bodies; a pair's part lies on one body", at, part);
      require(std::find(p.contact.parts.begin(), p.contact.parts.end(), part) == p.contact.parts.end(),
              "{}: part '{}' is on Γ3 ([boundary] contact) too; a pair's parts meet each other, not the foundation",
              at, part);
    }
    require(bodies[0] != bodies[1], "{}: slave '{}' and master '{}' are parts of one body; a pair joins two bodies "
            "([[body]])", at, pair.slave, pair.master);
  }
}

/// `held_by_bond` where no body needs its bonds is refused: the key would change the solver's choice and
/// the checks for nothing (a body clamped in the case the user meant to float, say).
void check_bonds_hold(const Problem& p, bool bonds_hold) {
  require(!p.contact.held_by_bond || bonds_hold,
          "{}: held_by_bond = true, but the prescribed displacements hold every body already (no body needs its bonds): "
          "remove the key, or the supports that hold the body you meant the bond to hold",
          p.where("contact.held_by_bond"));
}

/// Each body held by its prescribed displacements (a contact pair does not hold one either), or with
/// `held_by_bond` by its bonds on Γ3 as well (then some body must need them: the key is not a no-op).
void check_held(const Problem& p, const std::vector<int>& condition, const std::vector<ContactRow>& rows) {
  const Mesh& mesh = p.mesh;
  bool bonds_hold = false;
  const std::vector<int> body_of = node_bodies(mesh, cell_bodies(mesh));
  for (int b = 0; b < mesh.n_bodies(); ++b) {
    std::vector<int> nodes;
    for (int i = 0; i < mesh.n_nodes(); ++i)
      if (body_of[static_cast<std::size_t>(i)] == b) nodes.push_back(i);
    if (nodes.empty()) continue;
    Point lo = mesh.node(nodes[0]), hi = lo;
    for (int node : nodes)
      for (int j = 0; j < 3; ++j) {
        lo[j] = std::min(lo[j], mesh.node(node)[j]);
        hi[j] = std::max(hi[j], mesh.node(node)[j]);
      }
    bonds_hold |= check_body_held(p, condition, nodes, rows,
                                  mesh.n_bodies() == 1 ? std::string("the body")
                                  : b == 0 ? std::string("the body of [mesh]")
                                           : fmt::format("body '{}'", p.bodies[static_cast<std::size_t>(b) - 1].name),
                                  lo, hi);
  }
  check_bonds_hold(p, bonds_hold);
}

}  // namespace

void check_block_held(const Problem& p, const std::vector<int>& condition, const std::vector<int>& nodes,
                      const std::vector<ContactRow>& rows, const std::function<void(double*, int)>& sum) {
  require(p.block != nullptr && p.mesh.n_bodies() == 1, "internal: check_block_held on a mesh that is not one body's block");
  check_bonds_hold(p, check_body_held(p, condition, nodes, rows, "the body", p.block->lo, p.block->hi, sum));
}

ContactRows Problem::validate() const {
  const std::string where = name.empty() ? "problem" : name;
  require(mesh.n_cells() > 0, "{}: the mesh has no cells", where);
  require(elasticity.dim() == mesh.dim(),
          "{}: elasticity '{}' is for d = {} but the mesh has d = {}", where, elasticity.name(),
          elasticity.dim(), mesh.dim());
  located(where, [&] { check_kappa(kappa); });
  located(where, [&] { check_final_time(final_time); });
  if (step_control) {
    require(n_steps == 0 && step_times.empty() && step_sizes.empty(), "{}: error-controlled steps have no fixed grid",
            where);
    located(where, [&] { (void)step_control->completed(final_time); });
  } else {
    located(where, [&] { check_n_steps(n_steps); });
    require(step_times.empty() || static_cast<int>(step_times.size()) == n_steps,
            "{}: {} step times for N = {} steps", where, step_times.size(), n_steps);
    require(step_sizes.empty() || !step_times.empty(), "{}: step sizes without step times", where);
    if (!step_times.empty()) located(where, [&] { check_fixed_grid(final_time, step_times, step_sizes); });
  }
  require(law != nullptr, "{}: no viscoplastic law G", where);
  require(source != nullptr, "{}: no damage source phi", where);
  require(!clamped.empty() || !displacement.empty() || !symmetry.empty() || contact.held_by_bond,
          "{}: no clamped part Γ1 and no prescribed displacement given (the body must be held)", where);
  // On a block of the mesh (Problem::block) a part may lie elsewhere, and the body's supports too:
  // validate_blocks (parallel/block_part.hpp) checks those on all the blocks together.
  const bool whole = !block;
  for (const auto& p : clamped)
    require(!whole || mesh.part_size(p) > 0, "{}: clamped part '{}' has no boundary facets in the mesh", where, p);
  for (std::size_t k = 0; k < displacement.size(); ++k) {
    const PrescribedDisplacement& bc = displacement[k];
    require(!bc.parts.empty(), "{}: prescribed displacement {} has no parts", where, k + 1);
    for (const auto& p : bc.parts)
      require(!whole || mesh.part_size(p) > 0, "{}: displacement part '{}' has no boundary facets in the mesh", where, p);
    require(std::any_of(bc.value.begin(), bc.value.end(), [](const ScalarField& f) { return static_cast<bool>(f); }),
            "{}: prescribed displacement {} (parts {}) prescribes no component", where, k + 1, fmt::join(bc.parts, ", "));
    for (int c = mesh.dim(); c < 3; ++c)
      require(!bc.value[c], "{}: prescribed displacement {} gives component {} of {}, but the mesh has d = {}", where,
              k + 1, c + 1, 3, mesh.dim());
  }
  const std::vector<int> cell_material = cell_materials(*this);  // checks the materials' regions and kinds
  const DirichletDofs dirichlet = dirichlet_dofs(*this);  // checks the symmetry parts, values and conflicts
  require(!contact.parts.empty() || !contact.pairs.empty(), "{}: no contact part Γ3 and no contact pair given", where);
  check_pairs(*this);
  for (const auto& p : contact.parts)
    require(!whole || mesh.part_size(p) > 0, "{}: contact part '{}' has no boundary facets in the mesh", where, p);
  for (const auto& p : traction)
    require(!whole || mesh.part_size(p) > 0, "{}: traction part '{}' has no boundary facets in the mesh", where, p);
  for (std::size_t k = 0; k < pressure.size(); ++k) {
    const std::string at = this->where(fmt::format("loads.pressure[{}]", k));  // its [[loads.pressure]] table
    for (const auto& p : pressure[k].parts) {
      require(!whole || mesh.part_size(p) > 0, "{}: pressure part '{}' has no boundary facets in the mesh", at, p);
      const bool on_gamma1 = std::find(clamped.begin(), clamped.end(), p) != clamped.end();
      const bool on_gamma3 = std::find(contact.parts.begin(), contact.parts.end(), p) != contact.parts.end();
      require(!on_gamma1 && !on_gamma3, "{}: pressure part '{}' is a {} part; a pressure acts on Γ2 only", at, p,
              on_gamma1 ? "clamped" : "contact");
    }
  }
  require(static_cast<bool>(contact.gap) || !contact.obstacles.empty(), "{}: no gap function g", where);
  require(contact.obstacles.size() <= 64, "{}: {} obstacles; at most 64 are supported", where, contact.obstacles.size());
  auto on_gamma3 = [&](const std::string& part) {
    return std::find(contact.parts.begin(), contact.parts.end(), part) != contact.parts.end();
  };
  for (const Obstacle& o : contact.obstacles)
    for (const auto& part : o.parts)
      require(on_gamma3(part), "{}: obstacle '{}' acts on part '{}', which is not a contact part (Γ3: {})", where,
              o.name, part, fmt::join(contact.parts, ", "));
  // A law checks its own parameters when it is made (contact/registry.cpp).
  require(contact.law != nullptr, "{}: no contact law", where);
  for (const PartContactLaw& pl : contact.part_laws) {
    require(pl.law != nullptr, "{}: no contact law on {}", where, fmt::join(pl.parts, ", "));
    for (const auto& part : pl.parts)
      require(on_gamma3(part), "{}: a contact law is given on part '{}', which is not a contact part (Γ3: {})", where,
              part, fmt::join(contact.parts, ", "));
  }
  located(where, [&] { check_gap(mesh, contact, block.get()); });
  // Directions against prescribed components, obstacles' gaps, the pairs' coverage and overlap.
  auto rows = std::make_shared<const std::vector<ContactRow>>(contact_rows(*this, dirichlet.condition));
  if (whole) check_held(*this, dirichlet.condition, *rows);
  located(where, [&] { check_beta0(mesh, beta0, bodies.empty() ? -1 : 0, block.get()); });
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const std::string at = fmt::format("{}: body '{}'", where, bodies[b].name);
    located(at, [&] { check_kappa(bodies[b].kappa); });
    located(at, [&] { check_beta0(mesh, bodies[b].beta0, static_cast<int>(b) + 1); });
  }
  if (contact.direction) {
    const Point& v = *contact.direction;
    require(std::hypot(v[0], v[1], v[2]) > 0, "{}: the contact direction must be a non-zero vector", where);
  }
  check_step_stability(*this, cell_material);  // the explicit G of (3.6): k L <= 2
  return rows;
}

std::vector<std::vector<int>> pressure_facets(const Problem& p) {
  std::vector<std::vector<int>> facets;
  for (const PressureLoad& load : p.pressure) facets.push_back(p.mesh.facets_of_parts(load.parts));
  return facets;
}

std::vector<int> traction_facets(const Problem& p) {
  const Mesh& mesh = p.mesh;
  if (!p.traction.empty()) return mesh.facets_of_parts(p.traction);
  std::vector<int> excluded, facets;
  for (const auto& n : dirichlet_parts(p)) excluded.push_back(mesh.find_part(n));
  for (const auto& n : p.contact.parts) excluded.push_back(mesh.find_part(n));
  for (int f = 0; f < mesh.n_facets(); ++f)
    if (std::find(excluded.begin(), excluded.end(), mesh.facet_part(f)) == excluded.end()) facets.push_back(f);
  return facets;
}

}  // namespace vpc
