#include "scheme/step_data.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"

#include <cmath>
#include <tuple>

namespace vpc {

namespace {

/// A pair's master node may be moved by a prescribed displacement (a part driven as a rigid
/// punch): N holds the free dofs only, so its motion moves the bound instead. The row
/// ν·u_j − Σ_k w_k ν·u_k ≤ g with u_k = u_k,free + u_D,k is N u_free ≤ g + Σ_k w_k ν·u_D,k
/// (the slave's own prescribed components are zero: contact_pairs.cpp refuses moving ones).
void add_master_motion(const DiscreteSystem& sys, const Vector& u_D, Vector& gap) {
  if (u_D.size() == 0) return;
  const int d = sys.part.mesh().dim();
  Eigen::Index k = 0;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    for (const auto& [master, w] : node.masters)
      for (int i = 0; i < d; ++i) gap[k] += w * node.direction[i] * u_D[static_cast<Eigen::Index>(master) * d + i];
    ++k;
  }
}

}  // namespace

StepData step_data(const DiscreteSystem& sys, double t) {
  StepData data{t, load(sys, t), prescribed_displacement(sys, t), {}, {}, {}};
  std::string bad;
  data.gap = contact_gap(sys, t, bad);
  add_master_motion(sys, data.u_D, data.gap);
  check_step_data(sys, bad);
  return data;
}

void check_step_data(const DiscreteSystem& sys, const std::string& bad) {
  la::collective(sys.part.comm, [&] {
    check_formulas(*sys.problem);
    require(bad.empty(), "{}", bad);
  });
}

Vector checked_contact_gap(const DiscreteSystem& sys, double t) {
  std::string bad;
  Vector gap = contact_gap(sys, t, bad);
  add_master_motion(sys, prescribed_displacement(sys, t), gap);  // a pair's moving masters
  check_step_data(sys, bad);
  return gap;
}

Vector load(const DiscreteSystem& sys, double t) {
  const Problem& p = *sys.problem;
  const Mesh& mesh = sys.part.mesh();
  const int d = mesh.dim();
  const bool f0_once = sys.basis_integral_cells.size() > 0, f2_once = sys.basis_integral_traction.size() > 0;
  Vector F = assemble_load(mesh, sys.geo, sys.part.traction_facets, f0_once ? nullptr : p.f0, f2_once ? nullptr : p.f2, t);
  for (auto [once, f, w] : {std::tuple{f0_once, &p.f0, &sys.basis_integral_cells},
                            std::tuple{f2_once, &p.f2, &sys.basis_integral_traction}}) {
    if (!once) continue;
    const Point v = (*f)(Point{0, 0, 0}, t);
    for (int a = 0; a < mesh.n_nodes(); ++a)
      for (int i = 0; i < d; ++i) F[a * d + i] += v[i] * (*w)[a];
  }
  for (std::size_t k = 0; k < p.pressure.size(); ++k)
    add_pressure_load(mesh, sys.part.pressure_facets[k], p.pressure[k].p, t, F);
  return F;
}

Vector prescribed_displacement(const DiscreteSystem& sys, double t) {
  const auto& conditions = sys.problem->displacement;
  if (conditions.empty()) return {};
  const MeshPart& part = sys.part;
  const int d = part.mesh().dim();
  Vector u_D = Vector::Zero(part.dofs.n_full());
  for (const auto& [node, bits] : part.dirichlet_nodes)
    for (int c = 0; c < d; ++c)
      if (const int k = part.dirichlet[node * d + c]; k > 0) u_D[node * d + c] = conditions[k - 1].value[c](part.mesh().node(node), t);
  return u_D;
}

Vector contact_gap(const DiscreteSystem& sys, double t, std::string& bad) {
  const ContactSpec& spec = sys.problem->contact;
  const MeshPart& part = sys.part;
  std::vector<double> gaps;
  for (const PartContactNode& node : sys.contact->nodes) {
    if (!node.owned) continue;
    if ((!spec.gap_moves && spec.obstacles.empty()) || node.pair >= 0) {  // a pair's gap is the reference's
      gaps.push_back(node.gap);
      continue;
    }
    // A moving obstacle (SPEC §6): g(x, t_n) < 0 is an obstacle that pushes the body
    // back (N u ≤ g < 0 is still a feasible constraint); a value that is not a number
    // is an error, reported by every process.
    const Point& x = part.mesh().node(node.local_node);
    gaps.push_back(contact_gap_at(spec, x, node.direction, t, sys.contact->miss_gap, node.obstacles));
    if (!std::isfinite(gaps.back()) && bad.empty())
      bad = fmt::format("the gap g is not finite ({}) at t = {} at contact node {} ({}, {}, {})", gaps.back(), t,
                        part.original_node[node.local_node], x[0], x[1], x[2]);
  }
  return Eigen::Map<Vector>(gaps.data(), static_cast<Eigen::Index>(gaps.size()));
}

}  // namespace vpc
