// The rows of the contact matrix N of (3.9): one per node of Γ3 with a free component,
// its direction, its gap at t = 0, its contact law lumped at the node, its obstacles.
#include "problem/contact_rows.hpp"

#include "core/error.hpp"
#include "problem/contact_pairs.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <iterator>
#include <cmath>
#include <set>

namespace vpc {

namespace {

double length(const Point& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/// A fixed contact direction must point out of the body: at a node where it makes
/// an angle of 90° or more with the outward normal of Γ3, a displacement along it
/// moves the node into the body, u_ν ≤ g never binds and the body falls through
/// the foundation. (cos ≤ 1e-9 also refuses 90° up to round-off.)
void check_direction(const Problem& p, int node, const Point& direction, const Point& normal) {
  const double ld = length(direction), ln = length(normal);
  double cos = 0;
  for (int j = 0; j < 3; ++j) cos += direction[j] * normal[j];
  cos /= ld * ln;
  if (cos > 1e-9) return;
  const double angle = std::acos(std::clamp(cos, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
  const Point& x = p.mesh.node(node);
  Point n = normal;
  for (double& c : n) c /= ln;
  fail("{}: the contact direction ({}, {}, {}) points into the body at contact node {} ({}, {}, {}): its angle "
       "with the outward normal ({:.6g}, {:.6g}, {:.6g}) of the contact part is {:.6g} degrees; a fixed direction "
       "must make an angle below 90 degrees with the outward normal at every contact node (e.g. its opposite)",
       p.name, direction[0], direction[1], direction[2], p.node_number(node), x[0], x[1], x[2], n[0], n[1], n[2], angle);
}

/// The key that prescribes component c at a node (condition: DirichletDofs::condition),
/// located for a message; `clamped`: the nodes of Γ1 (Mesh::nodes_of_parts, sorted).
std::string prescribed_by(const Problem& p, int node, int c, const std::vector<int>& condition,
                          const std::vector<int>& clamped) {
  const int k = condition[static_cast<std::size_t>(node) * p.mesh.dim() + c];
  if (k > 0) return p.where(fmt::format("boundary.displacement[{}]", k - 1));
  const bool on_clamped = std::binary_search(clamped.begin(), clamped.end(), node);
  return p.where(on_clamped ? "boundary.clamped" : "boundary.symmetry");
}

/// Obstacle k located for a message: "case.toml:27:1: obstacle[0] ('punch')".
std::string obstacle_where(const Problem& p, int k) {
  return fmt::format("{} ('{}')", p.where(fmt::format("obstacle[{}]", k)), p.contact.obstacles[k].name);
}

/// At t = 0 the body, u0 = 0, must lie outside every obstacle (docs/cases.md, [[obstacle]]):
/// a contact node inside one is refused, whichever way its ray along ν goes (a ray
/// pointing away from a plane, or along a cylinder's axis, misses the obstacle, which
/// the gap alone would then ignore).
void check_outside_obstacles(const Problem& p, int node, ObstacleMask mask) {
  const Point& x = p.mesh.node(node);
  for (std::size_t k = 0; k < p.contact.obstacles.size(); ++k) {
    if (!(mask >> k & 1)) continue;
    const Obstacle& o = p.contact.obstacles[k];
    const double depth_0 = depth(o, x, 0.0);
    if (!(depth_0 > 0)) continue;  // outside, on the surface (or NaN: reported with the gap)
    const std::string where = obstacle_where(p, static_cast<int>(k));
    if (o.shape == Obstacle::Shape::Plane)
      fail("{}: contact node {} ({}, {}, {}) lies inside the obstacle at t = 0: {:.6g} behind the plane, on the side "
           "its normal ({:.6g}, {:.6g}, {:.6g}) points away from; the normal must point from the obstacle towards the "
           "body, and at t = 0 every contact node must lie outside every obstacle",
           where, p.node_number(node), x[0], x[1], x[2], depth_0, o.normal[0], o.normal[1], o.normal[2]);
    fail("{}: contact node {} ({}, {}, {}) lies inside the {} at t = 0, {:.6g} from its {} (radius {}); at t = 0 "
         "every contact node must lie outside every obstacle",
         where, p.node_number(node), x[0], x[1], x[2], o.shape == Obstacle::Shape::Sphere ? "sphere" : "cylinder",
         o.radius - depth_0, o.shape == Obstacle::Shape::Sphere ? "centre" : "axis", o.radius);
  }
}

/// The obstacles acting on the facets of contact part `part` (Obstacle::parts; none named: all).
ObstacleMask acting_on(const Problem& p, const std::string& part) {
  ObstacleMask acting = 0;
  for (std::size_t o = 0; o < p.contact.obstacles.size(); ++o) {
    const auto& on = p.contact.obstacles[o].parts;
    if (on.empty() || std::find(on.begin(), on.end(), part) != on.end()) acting |= ObstacleMask{1} << o;
  }
  return acting;
}

/// At t = 0 the body must lie outside every obstacle, not only its contact nodes: a node on an
/// obstacle's surface (gap 0) passes check_outside_obstacles whichever side of it the body is on, so a
/// plane put on the contact face with its normal pointing away from the body would hold the whole body
/// and never meet it (its rays along ν all miss). The cell behind each contact facet is tested at its
/// centroid, a point strictly inside the body: inside an obstacle acting on the facet, the body
/// overlaps the obstacle. Run after the node's check, whose message names a node inside, and
/// before its gap's (a node touching a sphere or cylinder from inside has a negative gap, which
/// says less).
void check_body_outside_obstacles(const Problem& p, int node, int f, ObstacleMask acting) {
  const Mesh& mesh = p.mesh;
  const Point c = mesh.cell_centroid(mesh.facet_cell(f));
  const Point& x = mesh.node(node);
  const double reach = std::hypot(c[0] - x[0], c[1] - x[1], c[2] - x[2]);  // the cell's size there
  for (std::size_t k = 0; k < p.contact.obstacles.size(); ++k) {
    if (!(acting >> k & 1)) continue;
    const Obstacle& o = p.contact.obstacles[k];
    const double inside = depth(o, c, 0.0);
    if (!(inside > 1e-6 * reach)) continue;  // outside (or round-off of a face meshed on a curved obstacle)
    if (o.shape == Obstacle::Shape::Plane) {
      const std::string key = fmt::format("obstacle[{}].normal", k);
      fail("{} ('{}'): the body lies inside the obstacle at t = 0: next to contact node {} ({}, {}, {}), {:.6g} from "
           "the plane, the centroid ({:.6g}, {:.6g}, {:.6g}) of its cell is {:.6g} behind the plane, on the side its "
           "normal ({:.6g}, {:.6g}, {:.6g}) points away from (the side the obstacle occupies); the normal must point "
           "from the obstacle towards the body: flip it to ({:.6g}, {:.6g}, {:.6g})",
           p.key_locations.count(key) ? p.where(key) : obstacle_where(p, static_cast<int>(k)), o.name,
           p.node_number(node), x[0], x[1], x[2], 0.0 - depth(o, x, 0.0), c[0], c[1], c[2], inside, o.normal[0],
           o.normal[1], o.normal[2], -o.normal[0] + 0.0, -o.normal[1] + 0.0, -o.normal[2] + 0.0);
    }
    const bool sphere = o.shape == Obstacle::Shape::Sphere;
    fail("{}: the body lies inside the {} at t = 0: next to contact node {} ({}, {}, {}), the centroid ({:.6g}, "
         "{:.6g}, {:.6g}) of its cell is {:.6g} inside it (radius {}); a {} occupies its inside, and at t = 0 the body "
         "must lie outside every obstacle: move them apart",
         obstacle_where(p, static_cast<int>(k)), sphere ? "sphere" : "cylinder", p.node_number(node), x[0], x[1], x[2],
         c[0], c[1], c[2], inside, o.radius, sphere ? "sphere" : "cylinder");
  }
}

}  // namespace

void fail_no_free_contact_node(const Problem& p, const std::vector<int>& condition) {
  const Mesh& mesh = p.mesh;
  std::set<std::string> by;  // the keys that prescribe them
  const std::vector<int> clamped = mesh.nodes_of_parts(p.clamped);
  for (int node : mesh.nodes_of_parts(p.contact.parts))
    for (int c = 0; c < mesh.dim(); ++c) by.insert(prescribed_by(p, node, c, condition, clamped));
  fail("{}: the contact part has no free node: every displacement component of each of its nodes is prescribed, by "
       "{}; a contact node must be free to move (take the contact part's nodes out of those parts, or give another "
       "contact part)",
       p.where("boundary.contact"), fmt::join(by, " and "));
}

namespace {

std::atomic<long long> builds{0};

}  // namespace

long long contact_rows_builds() { return builds.load(); }

std::vector<ContactRow> contact_rows(const Problem& p, const std::vector<int>& condition) {
  ++builds;
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim();
  std::vector<Point> normal(mesh.n_nodes(), Point{0, 0, 0});
  for (int f : mesh.facets_of_parts(p.contact.parts)) {
    const Point nf = mesh.facet_normal(f);
    const double w = mesh.facet_measure(f);
    for (int a = 0; a < mesh.nodes_per_facet(); ++a)
      for (int j = 0; j < 3; ++j) normal[mesh.facet(f)[a]][j] += w * nf[j];
  }
  const auto [lo, hi] = p.block ? std::pair{p.block->lo, p.block->hi} : mesh.bounding_box();  // the whole mesh's
  const double miss = contact_miss_gap(lo, hi);
  // Per node: its law (a rigid one where any of its Γ3 facets has one; else the compliant law
  // of its facets; the laws of one kind must agree: ContactLaw::conflict), its datum (the shares
  // of that kind's facets, lumped by the law: k_i for a compliance) and the obstacles acting on its parts.
  const std::vector<std::shared_ptr<const ContactLaw>> laws = p.contact.laws();
  std::vector<double> rigid_datum(mesh.n_nodes(), 0.0), compliant_datum(mesh.n_nodes(), 0.0);
  std::vector<int> compliant_law(mesh.n_nodes(), -1), rigid_law(mesh.n_nodes(), -1);
  std::vector<ObstacleMask> obstacles(mesh.n_nodes(), 0);
  // Per node with obstacles: its Γ3 facets and the obstacles acting on each (check_body_outside_obstacles).
  std::vector<std::vector<std::pair<int, ObstacleMask>>> facets_at(p.contact.obstacles.empty() ? 0 : mesh.n_nodes());
  for (int f : mesh.facets_of_parts(p.contact.parts)) {  // each facet once, with its part's law and obstacles
    const std::string& part = mesh.part_names()[static_cast<std::size_t>(mesh.facet_part(f))];
    const int k = p.contact.law_index(part);
    const ContactLaw& law = *laws[static_cast<std::size_t>(k)];
    const ObstacleMask acting = acting_on(p, part);
    for (int a = 0; a < mesh.nodes_per_facet(); ++a) {
      const int i = mesh.facet(f)[a];
      obstacles[i] |= acting;
      if (!facets_at.empty()) facets_at[static_cast<std::size_t>(i)].emplace_back(f, acting);
      int& first = law.rigid() ? rigid_law[i] : compliant_law[i];
      if (first < 0) first = k;
      const ContactLaw& node_law = *laws[static_cast<std::size_t>(first)];
      std::string why = node_law.conflict(law);
      if (why.empty()) why = law.conflict(node_law);
      const Point& x = mesh.node(i);
      require(why.empty(), "{}: contact node {} ({}, {}, {}) lies on contact parts whose {}", p.name, p.node_number(i), x[0], x[1], x[2],
              why);
      (law.rigid() ? rigid_datum : compliant_datum)[i] += law.lumped(mesh.facet_measure(f), mesh.nodes_per_facet());
    }
  }
  const std::vector<double> measure = tributary_measures(mesh, p.contact.parts);
  std::vector<ContactRow> rows;
  for (int node : mesh.nodes_of_parts(p.contact.parts)) {
    const int* fixed = condition.data() + static_cast<std::size_t>(node) * d;
    if (std::all_of(fixed, fixed + d, [](int k) { return k >= 0; })) continue;  // u prescribed there
    const Point& x = mesh.node(node);
    require(length(normal[node]) > 0,
            "{}: the outward normal of the contact part vanishes at node {} ({}, {}, {}) (its facets face opposite "
            "ways); split the contact part there",
            p.name, p.node_number(node), x[0], x[1], x[2]);
    if (p.contact.direction) check_direction(p, node, *p.contact.direction, normal[node]);
    Point v = p.contact.direction ? *p.contact.direction : normal[node];
    double l = length(v);
    for (double& c : v) c /= l;
    // On a symmetry plane the mirrored half's facets would cancel the normal's
    // component across the plane: drop it. Any other component along a prescribed
    // one would make N act on a dof that is not an unknown.
    for (int c = 0; c < d; ++c) {
      if (fixed[c] < 0 || v[c] == 0) continue;
      if (!(fixed[c] == 0 && !p.contact.direction && std::abs(v[c]) < 0.5))
        fail("{}: contact node {} ({}, {}, {}) has u{} prescribed (by {}), but its contact direction ({:.6g}, {:.6g}, "
             "{:.6g}) has a component along it; a node cannot be in contact along a prescribed component (remove the "
             "node from one of the parts, or use a symmetry part for a symmetry plane)",
             p.where("boundary.contact"), p.node_number(node), x[0], x[1], x[2], c == 0 ? "x" : c == 1 ? "y" : "z",
             prescribed_by(p, node, c, condition, mesh.nodes_of_parts(p.clamped)), v[0], v[1], v[2]);
      v[c] = 0;
      l = length(v);
      for (double& vc : v) vc /= l;
    }
    check_outside_obstacles(p, node, obstacles[node]);
    if (!facets_at.empty())
      for (const auto& [f, acting] : facets_at[static_cast<std::size_t>(node)]) check_body_outside_obstacles(p, node, f, acting);
    const double g = contact_gap_at(p.contact, x, v, 0.0, miss, obstacles[node]);
    if (!(std::isfinite(g) && g >= 0)) {
      const int k = p.contact.obstacles.empty() ? -1 : nearest_obstacle(p.contact.obstacles, x, v, 0.0, obstacles[node]);
      fail("{}: the gap g must be a number >= 0 at t = 0; it is {} at contact node {} ({}, {}, {})",
           k < 0 ? p.where("contact.gap") : obstacle_where(p, k), g, p.node_number(node), x[0], x[1], x[2]);
    }
    const bool rigid = rigid_law[node] >= 0;
    ContactRow& row = rows.emplace_back();  // Γ3's row: no masters, no pair
    row.node = node;
    row.direction = v;
    row.gap = g;
    row.measure = measure[static_cast<std::size_t>(node)];
    row.law = rigid ? rigid_law[node] : compliant_law[node];
    row.datum = rigid ? rigid_datum[node] : compliant_datum[node];
    row.obstacles = obstacles[node];
  }
  // Every contact node has every component prescribed (a block may have no contact node: the
  // ranks check the whole mesh's together, validate_blocks).
  if (rows.empty() && !p.contact.parts.empty() && !p.block) fail_no_free_contact_node(p, condition);
  // Pairs between bodies (SPEC §8): their slave nodes' rows, among Γ3's in node order (a pair with
  // none is refused: add_pair_rows).
  std::vector<ContactRow> pairs = pair_rows(p, condition);
  for (std::size_t a = 0, b = 0; a < rows.size() && b < pairs.size();) {
    if (rows[a].node == pairs[b].node) {
      const Point& x = mesh.node(rows[a].node);
      fail("{}: node {} ({}, {}, {}) is on Γ3 and a slave of a contact pair; a node has one contact constraint",
           p.where("contact.pair"), rows[a].node, x[0], x[1], x[2]);
    }
    rows[a].node < pairs[b].node ? ++a : ++b;
  }
  for (std::size_t a = 1; a < pairs.size(); ++a)
    require(pairs[a - 1].node != pairs[a].node, "{}: node {} is a slave of two contact pairs", p.where("contact.pair"),
            pairs[a].node);
  std::vector<ContactRow> merged;
  std::merge(std::make_move_iterator(rows.begin()), std::make_move_iterator(rows.end()),
             std::make_move_iterator(pairs.begin()), std::make_move_iterator(pairs.end()), std::back_inserter(merged),
             [](const ContactRow& a, const ContactRow& b) { return a.node < b.node; });
  return merged;
}


ContactRows contact_rows_of(const Problem& p, const std::vector<int>& condition, const ContactRows& built) {
  return built ? built : std::make_shared<const std::vector<ContactRow>>(contact_rows(p, condition));
}

std::vector<double> tributary_measures(const Mesh& mesh, const std::vector<std::string>& parts) {
  std::vector<double> m(static_cast<std::size_t>(mesh.n_nodes()), 0.0);
  const int nv = mesh.nodes_per_facet();
  for (int f : mesh.facets_of_parts(parts)) {
    const double share = mesh.facet_measure(f) / nv;
    for (int a = 0; a < nv; ++a) m[mesh.facet(f)[a]] += share;
  }
  return m;
}

}  // namespace vpc
