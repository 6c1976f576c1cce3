#include "part/contact_set.hpp"

#include "core/error.hpp"
#include "problem/rigid_motions.hpp"
#include "solvers/contact_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace vpc {

namespace {

/// The box of the part's local nodes i < n that `take` accepts, over every process. Collective.
template <class Take>
std::pair<Point, Point> box_over_ranks(const MeshPart& part, int n, Take take) {
  const Mesh& mesh = part.mesh();
  Point lo{0, 0, 0}, hi{0, 0, 0};
  for (int j = 0; j < 3; ++j) {
    double l = INFINITY, h = -INFINITY;
    for (int i = 0; i < n; ++i)
      if (take(i)) l = std::min(l, mesh.node(i)[j]), h = std::max(h, mesh.node(i)[j]);
    lo[j] = part.comm.min(l);
    hi[j] = part.comm.max(h);
  }
  return {lo, hi};
}

/// The diagonal of the bodies' bounding box, over every process's nodes (contact_miss_gap). Collective.
double miss_gap_of(const MeshPart& part) {
  const auto [lo, hi] = box_over_ranks(part, part.mesh().n_nodes(), [](int) { return true; });
  return contact_miss_gap(lo, hi);
}

/// The rigid motions of the part's bodies that their prescribed dofs leave free (`held_by_bond`: K is
/// singular on them), as columns over the owned free dofs: each body's (RigidHold) from its prescribed
/// components over every rank. Collective.
Eigen::MatrixXd free_motions(const MeshPart& part) {
  const Mesh& mesh = part.mesh();
  const la::Comm& comm = part.comm;
  const int d = mesh.dim(), owned = part.n_owned_nodes;
  const std::vector<int> body_of = node_bodies(mesh, part.cell_body);
  int bodies = 0;
  for (int b : part.cell_body) bodies = std::max(bodies, b + 1);
  bodies = static_cast<int>(comm.max(static_cast<double>(bodies)));
  std::vector<Eigen::MatrixXd> columns;
  int total = 0;
  std::vector<RigidMotions> motions;
  motions.reserve(static_cast<std::size_t>(bodies));  // (each RigidHold refers to its body's)
  for (int b = 0; b < bodies; ++b) {
    const auto [lo, hi] = box_over_ranks(part, owned, [&](int i) { return body_of[static_cast<std::size_t>(i)] == b; });
    motions.emplace_back(d, lo, hi);
    RigidHold held(motions.back());
    for (int i = 0; i < owned; ++i)
      for (int c = 0; c < d && body_of[static_cast<std::size_t>(i)] == b; ++c)
        if (part.dirichlet[static_cast<std::size_t>(i) * d + c] >= 0) held.add_axis(mesh.node(i), c);
    columns.push_back(held.free_motions([&](double* v, int n) { comm.sum(v, n); }));
    total += static_cast<int>(columns.back().cols());
  }
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(part.n_owned_dofs, total);
  int col = 0;
  for (int b = 0; b < bodies; ++b) {
    const Eigen::MatrixXd& V = columns[static_cast<std::size_t>(b)];
    for (int i = 0; i < owned && V.cols() > 0; ++i)
      for (int c = 0; c < d && body_of[static_cast<std::size_t>(i)] == b; ++c)
        if (const int dof = part.dofs.free_index(part.dofs.full_index(i, c)); dof >= 0) {
          Point axis{0, 0, 0};  // the motions' values along dof's axis
          axis[c] = 1;
          R.row(dof).segment(col, V.cols()) = motions[static_cast<std::size_t>(b)].along(mesh.node(i), axis).transpose() * V;
        }
    col += static_cast<int>(V.cols());
  }
  return R;
}

}  // namespace

ContactSet::ContactSet(const Problem& p, const MeshPart& part, std::vector<PartContactNode> nodes_in)
    : ContactSet(p, part, std::move(nodes_in), miss_gap_of(part)) {
  check_surface_laws(p, part);  // at set-up: a slid set has the same nodes and laws
}

ContactSet::ContactSet(const Problem& p, const MeshPart& part, std::vector<PartContactNode> nodes_in, double miss)
    : nodes(std::move(nodes_in)), miss_gap(miss) {
  set_rows(p, part);
}

ContactSet ContactSet::moved(const Problem& p, const MeshPart& part, std::vector<PartContactNode> moved) const {
  return ContactSet(p, part, std::move(moved), miss_gap);
}

std::vector<int> ContactSet::owned_row_numbers() const {
  std::vector<int> rows;
  for (const PartContactNode& node : nodes)
    if (node.owned) rows.push_back(node.row);
  return rows;
}

std::vector<int> ContactSet::owned_row_laws() const {
  std::vector<int> laws;
  for (const PartContactNode& node : nodes)
    if (node.owned) laws.push_back(node.law);
  return laws;
}

void ContactSet::set_rows(const Problem& p, const MeshPart& part) {
  local = contact_matrix(part.dofs, nodes, ContactColumns::local);
  ContactMatrix owned = owned_rows(local, part, nodes);
  N_local = std::move(owned.N);
  N = owned_columns(N_local, part);
  dofs = std::move(owned.node_dofs);
  if (p.contact.tangential()) set_friction_frame(p, part);  // SPEC §7 (and the slip that wear needs, §9)
}

void ContactSet::check_surface_laws(const Problem& p, const MeshPart& part) const {
  const ContactSpec& c = p.contact;
  std::vector<std::vector<const SurfaceHistory*>> laws;  // per entry, made once
  for (std::size_t e = 0; e < c.laws().size(); ++e) laws.push_back(c.surface_laws(e));
  for (const PartContactNode& node : nodes) {
    if (!node.owned) continue;
    const auto e = static_cast<std::size_t>(node.law);
    for (const SurfaceHistory* law : laws[e])
      if (const LawText bad = law->check_at(part.mesh().node(node.local_node)); !bad.text.empty())
        fail("{}: {}", p.where_in(c.entry_table(e), bad.key), bad.text);
  }
}

void ContactSet::set_friction_frame(const Problem& p, const MeshPart& part) {
  const Mesh& mesh = part.mesh();
  const int d = mesh.dim();
  FrictionFrame& f = friction;
  ContactConstraints c;  // over the local free dofs: T's rows whole, relative to every master's mean
  c.N = N_local;
  c.block = p.contact.block_size(d);
  c.rows = owned_row_numbers();
  f.laws = p.contact.frictions();
  f.row_friction.clear();
  std::vector<double> mus, limits;
  for (const PartContactNode& node : nodes) {
    if (!node.owned) continue;
    const FrictionLaw* law = f.laws[static_cast<std::size_t>(node.law)].get();
    f.row_friction.push_back(law);
    const Point& x = mesh.node(node.local_node);
    const double mu_i = law ? law->coefficient(x) : 0.0;
    if (!(std::isfinite(mu_i) && mu_i >= 0))
      fail("{}: the friction coefficient mu is {} at contact node ({}, {}, {}) ({}); expected a number >= 0",
           p.where("contact.mu"), mu_i, x[0], x[1], x[2], law->describe());
    mus.push_back(mu_i);
    const double tau = law ? law->limit(x) : std::numeric_limits<double>::infinity();
    if (!(tau > 0))  // +∞ (none) passes; NaN and ≤ 0 do not
      fail("{}: the shear limit is {} at contact node ({}, {}, {}) ({}); expected a traction > 0",
           p.where("contact.shear_limit"), tau, x[0], x[1], x[2], law->describe());
    limits.push_back(std::isfinite(tau) ? tau * node.measure : tau);
  }
  c.mu = Eigen::Map<Vector>(mus.data(), static_cast<Eigen::Index>(mus.size()));
  f.limit = Eigen::Map<Vector>(limits.data(), static_cast<Eigen::Index>(limits.size()));
  f.local_master_mean = std::move(local.master_mean);
  const int n = part.n_owned_dofs;
  f.master_mean = f.local_master_mean.size() > 0 ? SparseMatrix(f.local_master_mean.topLeftCorner(n, n)) : SparseMatrix();
  c.master_mean = f.local_master_mean;
  set_tangents(c, dofs);
  f.T_local = std::move(c.T);
  f.T = owned_columns(f.T_local, part);
  f.tangent_dof = std::move(c.tangent_dof);
  f.mu = std::move(c.mu);
}

ContactConstraints ContactSet::constraints(const Problem& p, const MeshPart& part, Vector gap) const {
  ContactConstraints c;
  c.m = part.n_contact;
  c.rows = owned_row_numbers();
  c.N = N;
  c.gap = std::move(gap);
  // Each row's law (contact/contact_law.hpp) and its per-node datum, lumped at the node (ContactNode).
  c.laws = p.contact.laws();
  c.block = p.contact.block_size(part.mesh().dim());
  c.law = owned_row_laws();
  std::vector<double> datum;
  for (const PartContactNode& node : nodes)
    if (node.owned) datum.push_back(node.datum);
  c.datum = Eigen::Map<Vector>(datum.data(), static_cast<Eigen::Index>(datum.size()));
  c.node_dofs = dofs;
  if (p.contact.adhesive()) {  // adhesion (SPEC §9): each row's bond length, its bond the steps' (set_bond)
    std::vector<std::vector<const SurfaceHistory*>> laws;  // per entry, made once
    for (std::size_t e = 0; e < p.contact.laws().size(); ++e) laws.push_back(p.contact.surface_laws(e));
    std::vector<double> length;
    for (const PartContactNode& node : nodes) {
      if (!node.owned) continue;
      double L = 0;
      for (const SurfaceHistory* law : laws[static_cast<std::size_t>(node.law)]) L = std::max(L, law->bond_length());
      length.push_back(L);
    }
    c.bond_length = Eigen::Map<Vector>(length.data(), static_cast<Eigen::Index>(length.size()));
    c.bond = Vector::Zero(c.bond_length.size());
    c.shear_bonded = p.contact.shear_bonded();
  }
  // Friction's frame (empty without): the bounds and the shift are the steps' (set_friction).
  c.frictions = friction.laws;
  c.master_mean = friction.master_mean;
  c.T = friction.T;
  c.tangent_dof = friction.tangent_dof;
  c.mu = friction.mu;
  c.limit = friction.limit;
  c.tresca = Vector::Zero(friction.mu.size());
  c.shift = Vector::Zero(friction.T.rows());
  if (p.contact.held_by_bond) c.free_motions = free_motions(part);
  // Spread pairs: the other ranks' rows' entries at this rank's dofs; the products then sum over the
  // ranks (the same answer on every rank: the part's).
  c.remote = remote_pieces(part, c.rows, N_local, friction.T_local, c.block - 1);
  c.remote.spread = part.pairs_spread;
  return c;
}

}  // namespace vpc
