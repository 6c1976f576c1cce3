#include "scheme/friction_data.hpp"

#include "fem/assembly.hpp"
#include "solvers/stick_slip.hpp"

#include <cmath>

namespace vpc {

Vector friction_bounds(const DiscreteSystem& sys, double t, std::string& bad) {
  const MeshPart& part = sys.part;
  std::vector<double> bounds;
  std::size_t row = 0;
  for (const PartContactNode& node : part.contact) {
    if (!node.owned) continue;
    const FrictionLaw* law = sys.row_friction[row++];
    const Point& x = part.mesh().node(node.local_node);
    const double g = law ? law->bound(x, t) : 0.0;
    if (!(std::isfinite(g) && g >= 0) && bad.empty())
      bad = fmt::format("{}: the friction bound is {} at t = {} at contact node {} ({}, {}, {}); expected a number >= 0",
                        sys.problem->where("contact.friction_bound"), g, t, part.original_node[node.local_node], x[0],
                        x[1], x[2]);
    bounds.push_back(g * node.measure);
  }
  return Eigen::Map<Vector>(bounds.data(), static_cast<Eigen::Index>(bounds.size()));
}

Vector slip_shift(const DiscreteSystem& sys, const State& s, double t) {
  const MeshPart& part = sys.part;
  const int d = part.mesh().dim();
  const ContactSpec& spec = sys.problem->contact;
  Vector at = restrict_to_free(part.dofs, s.u).head(part.n_owned_dofs);
  if (!spec.obstacles.empty())
    for (const PartContactNode& node : part.contact) {
      if (!node.owned) continue;
      const Point& x = part.mesh().node(node.local_node);
      const int k = nearest_obstacle(spec.obstacles, x, node.direction, t, node.obstacles);
      if (k < 0) continue;
      const Obstacle& o = spec.obstacles[static_cast<std::size_t>(k)];
      const Point now = o.position(x, t), before = o.position(x, s.t);
      for (int i = 0; i < d; ++i)
        if (const int j = part.dofs.free_index(part.dofs.full_index(node.local_node, i)); j >= 0)
          at[j] += now[i] - before[i];
    }
  return sys.T * at;
}

void record_slip(const DiscreteSystem& sys, const Vector& tresca, const Vector& shift, const Vector& u_free, State& s) {
  // Only what stick_slip (the bounds) and replicate read: the rows, the block, μ and the step's data.
  ContactConstraints c;
  c.m = sys.part.n_contact;
  c.rows = sys.part.owned_contact_rows();
  c.block = s.contact_block;
  c.mu = sys.mu;
  c.tresca = tresca;
  const int t = c.block - 1;
  const Vector slip = sys.T * u_free - shift;
  const std::vector<ContactStatus> stick_or_slip = stick_slip(c, s.lambda);
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  Vector status(rows), length(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    status[i] = static_cast<double>(stick_or_slip[static_cast<std::size_t>(i)]);
    length[i] = slip.segment(i * t, t).norm();
  }
  // Replicated like λ (one owner per row: the sums are exact): per node |Δ| then Δ.
  const Vector blocks = replicate_blocks(sys.part.comm, c, length, slip);
  for (int i = 0; i < c.m; ++i) {
    s.slip[i] += blocks[i * c.block];
    s.slip_step.segment(i * t, t) = blocks.segment(i * c.block + 1, t);
  }
  c.block = 1;
  s.contact_status.noalias() = replicate(sys.part.comm, c, status);  // in place: Python's views of it stay valid
}

}  // namespace vpc
