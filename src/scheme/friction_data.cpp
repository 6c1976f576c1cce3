#include "scheme/friction_data.hpp"

#include "fem/assembly.hpp"
#include "solvers/stick_slip.hpp"

#include <cmath>
#include <optional>

namespace vpc {

Vector friction_bounds(const DiscreteSystem& sys, double t, std::string& bad) {
  const MeshPart& part = sys.part;
  std::vector<double> bounds;
  std::size_t row = 0;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    const FrictionLaw* law = sys.contact->friction.row_friction[row++];
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

namespace {

/// A pair's master node moved by a prescribed displacement slides under its slave as an obstacle
/// does; T holds the free dofs only, so t_ij·Σ_k w_k Δu_D,k (the prescribed components' motion
/// over the step: u_D at t less the state's) joins h.
void add_master_slip(const DiscreteSystem& sys, const Vector& u_before, const Vector& u_D, Vector& shift) {
  const MeshPart& part = sys.part;
  const DofMap& dofs = part.dofs;
  const int d = part.mesh().dim();
  const auto t = static_cast<Eigen::Index>(sys.problem->contact.block_size(d) - 1);
  Eigen::Index k = 0;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    Point moved{0, 0, 0};
    for (const auto& [master, w] : node.masters)
      for (int i = 0; i < d; ++i)
        if (const int f = dofs.full_index(master, i); dofs.free_index(f) < 0) moved[i] += w * (u_D[f] - u_before[f]);
    if (moved != Point{0, 0, 0})
      for (Eigen::Index j = k * t; j < (k + 1) * t; ++j)
        for (int i = 0; i < d; ++i)
          if (const int own = dofs.free_index(dofs.full_index(node.local_node, i)); own >= 0)
            shift[j] += sys.contact->friction.T.coeff(j, own) * moved[i];  // t_ij's component i (T's entry at the slave's dof)
    ++k;
  }
}

}  // namespace

Point obstacle_translation(const DiscreteSystem& sys, const PartContactNode& node, double from, double to) {
  const ContactSpec& spec = sys.problem->contact;
  const Point& x = sys.part.mesh().node(node.local_node);
  const int k = spec.obstacles.empty() ? -1 : nearest_obstacle(spec.obstacles, x, node.direction, to, node.obstacles);
  if (k < 0) return {0, 0, 0};
  const Obstacle& o = spec.obstacles[static_cast<std::size_t>(k)];
  const Point now = o.position(x, to), before = o.position(x, from);
  return {now[0] - before[0], now[1] - before[1], now[2] - before[2]};
}

Vector prescribed_slip(const DiscreteSystem& sys, const Vector& u_before, const Vector& u, double from, double to) {
  const MeshPart& part = sys.part;
  const DofMap& dofs = part.dofs;
  const int d = part.mesh().dim();
  std::vector<double> out;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    std::optional<Point> w;  // the obstacle's translation, found for a node with a prescribed direction only
    double sum = 0;
    for (int i = 0; i < d; ++i) {
      const int f = dofs.full_index(node.local_node, i);
      if (dofs.free_index(f) >= 0) continue;  // a free tangent: friction's slip (T u − h)
      if (!w) w = obstacle_translation(sys, node, from, to);
      double rel = u[f] - u_before[f] - (*w)[i];
      for (const auto& [master, share] : node.masters) {
        const int g = dofs.full_index(master, i);
        rel -= share * (u[g] - u_before[g]);
      }
      sum += rel * rel;
    }
    out.push_back(std::sqrt(sum));
  }
  return Eigen::Map<Vector>(out.data(), static_cast<Eigen::Index>(out.size()));
}

Vector slip_shift(const DiscreteSystem& sys, const State& s, double t, const Vector& u_D) {
  const MeshPart& part = sys.part;
  const int d = part.mesh().dim();
  const ContactSpec& spec = sys.problem->contact;
  // u_{n−1} over the local free dofs, ghosts included: T_local's rows whole (a spread pair row's
  // ghost masters' terms too), exact without communication.
  Vector at = restrict_to_free(part.dofs, s.u);
  if (!spec.obstacles.empty())
    for (const PartContactNode& node : sys.contact->nodes) {
      if (!node.owned) continue;
      const Point w = obstacle_translation(sys, node, s.t, t);
      for (int i = 0; i < d; ++i)
        if (const int j = part.dofs.free_index(part.dofs.full_index(node.local_node, i)); j >= 0) at[j] += w[i];
    }
  Vector h = sys.contact->friction.T_local * at;
  if (u_D.size() > 0) add_master_slip(sys, s.u, u_D, h);  // a pair's moving masters
  return h;
}

void record_slip(const DiscreteSystem& sys, const ContactConstraints& c, const Vector& u_free, double slack, State& s) {
  const int t = c.block - 1;
  const Vector slip = slip_increment(sys.part.comm, c, u_free);  // with other ranks' pieces of its rows
  const std::vector<ContactStatus> stick_or_slip = stick_slip(c, s.lambda, slack);
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
  s.contact_status.noalias() = replicate(sys.part.comm, c, status);  // in place: Python's views of it stay valid
}

namespace {

class Frictionless final : public StepFriction {
 public:
  void before_solve(const DiscreteSystem&, const State&, const StepData&, ContactSolver&) const override {}
  void after_solve(const DiscreteSystem&, const ContactSolver&, const Vector&, const ContactReport&, State&) const override {}
};

class Frictional final : public StepFriction {
 public:
  void before_solve(const DiscreteSystem& sys, const State& s, const StepData& data, ContactSolver& contact) const override {
    std::string bad;
    Vector bounds = friction_bounds(sys, data.t, bad);
    check_step_data(sys, bad);
    contact.set_friction(bounds, slip_shift(sys, s, data.t, data.u_D));
  }
  void after_solve(const DiscreteSystem& sys, const ContactSolver& contact, const Vector& u_free, const ContactReport& rep,
                   State& s) const override {
    record_slip(sys, contact.constraints(), u_free, kSlipForceShare * rep.residuals.force_scale, s);
  }
};

}  // namespace

std::unique_ptr<const StepFriction> step_friction(const ContactSpec& spec) {
  if (spec.tangential()) return std::make_unique<Frictional>();  // friction, or wear (its slip)
  return std::make_unique<Frictionless>();
}

}  // namespace vpc
