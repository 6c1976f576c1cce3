#include "io/state_fields.hpp"

#include "core/error.hpp"
#include "la/vector.hpp"
#include "part/contact_tangents.hpp"

#include <algorithm>

namespace vpc {

namespace {

using L = FieldLocation;
using Span = std::span<const double>;

Span span_of(const Eigen::VectorXd& v) { return {v.data(), static_cast<std::size_t>(v.size())}; }
Span span_of(const std::vector<SymTensor>& t) { return {t.empty() ? nullptr : t[0].c.data(), 6 * t.size()}; }
void set(Eigen::VectorXd& v, Span x) { v = Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())); }
void set(std::vector<SymTensor>& t, Span x) {
  t.resize(x.size() / 6);
  for (std::size_t i = 0; i < t.size(); ++i) std::copy_n(x.data() + 6 * i, 6, t[i].c.data());
}

int one(const State&, int) { return 1; }
int tensor(const State&, int) { return 6; }
int dim(const State&, int d) { return d; }
int block(const State& s, int) { return s.contact_block; }
int three(const State&, int) { return 3; }
int tangents(const State& s, int) { return std::max(s.contact_block - 1, 0); }
bool frictional(const State& s) { return s.contact_block > 1; }
// Friction's slip fields (State::slip_step, slip, contact_status): those of a frictional run.
bool has_slip(const State& s) { return s.contact_block > 1 && s.slip.size() * s.contact_block == s.lambda.size(); }

std::size_t n_nodes(const FieldContext& c) { return static_cast<std::size_t>(c.part.mesh().n_nodes()); }

/// A node field of `width` numbers per node, zero where `fill` writes nothing.
template <typename Fill>
VtuField node_field(const FieldContext& c, std::string_view name, int width, Fill fill) {
  VtuField f{std::string(name), width, std::vector<double>(n_nodes(c) * width, 0.0)};
  fill(f.values.data());
  return f;
}

// λ's normal force at contact node c (the first of its block).
double normal_force(const State& s, const PartContactNode& c) { return s.lambda[c.row * s.contact_block]; }

/// Per local node, `width` numbers: Σ_j w_jk x_j over the contact pairs' slave rows j with master
/// node k (x_j: `of(row, component)`). A row's rank sums at its masters: it owns them (cut_part) or,
/// where the pairs are spread (PartPieces::pairs_spread), may hold them as ghosts, whose sums it then
/// adds to their owners'; the ranks that show a master node as a ghost get the owner's sum. Empty
/// without pairs. Collective on the part's communicator.
template <typename Of>
std::vector<double> master_sums(const FieldContext& c, int width, Of of) {
  const bool pairs = std::ranges::any_of(c.contact, [](const PartContactNode& n) { return n.pair >= 0; });
  if (!c.part.comm.any(pairs)) return {};
  std::vector<double> out(static_cast<std::size_t>(width) * n_nodes(c), 0.0);
  for (int j = 0; j < width; ++j) {
    la::Vector r(c.part.node_layout);
    for (const PartContactNode& n : c.contact)
      for (const auto& [k, w] : n.masters) r.local()[k] += w * of(n, j);
    if (c.part.pairs_spread) r.add_ghosts_to_owners();
    r.update_ghosts();
    for (std::size_t i = 0; i < n_nodes(c); ++i) out[width * i + j] = r.local()[static_cast<Eigen::Index>(i)];
  }
  return out;
}

/// Adds into `out` (`width` numbers a node) each master node's Σ_j w_jk x_j (master_sums); nothing
/// without pairs. Collective.
template <typename Of>
void add_master_sums(const FieldContext& c, int width, Of of, double* out) {
  const std::vector<double> sums = master_sums(c, width, of);
  for (std::size_t i = 0; i < sums.size(); ++i) out[i] += sums[i];
}

/// On the master nodes of contact pairs, the slave rows' x_j / D_jj averaged with the weights
/// w_jk D_jj: Σ_j w_jk x_j / Σ_j w_jk D_jj (D_jj: the slave node's covered measure). For x = λ
/// it is the master's pressure: Σ_j w_jk D_jj = Σ_j M_jk = ∫ N_k over the covered master
/// surface (the dual basis sums to 1), so the reaction over the node's measure in contact.
/// Added into `out` (`width` numbers a node) where a master node has weight; nothing without pairs.
template <typename Of>
void add_master_averages(const FieldContext& c, int width, Of of, double* out) {
  const std::vector<double> num = master_sums(c, width, of);
  const std::vector<double> den = master_sums(c, 1, [](const PartContactNode& n, int) { return n.measure; });
  const auto w = static_cast<std::size_t>(width);
  for (std::size_t i = 0; i < num.size(); ++i)
    if (den[i / w] > 0) out[i] += num[i] / den[i / w];
}

/// How a friction vector field reads on a pair's master nodes (tangent_vector_field).
enum class OnMasters { none, sum, average };

/// Friction's vectors Σ_j x_j t_j at the contact nodes (zero elsewhere), x_j the numbers of
/// `values` (per contact row: the block − 1 numbers after `offset` of every `stride`) along
/// the node's tangents (contact_tangents), each times `sign` and divided by `per` (1, or the
/// node's measure). On a pair's master nodes the slave rows' vectors with the mortar weights: their
/// sum (a force) or their average as add_master_averages takes it (a traction), or nothing.
/// λ_τ is the force on the obstacle (the master side): a force field on the body that owns the
/// node takes sign −1 at the contact nodes and the master sums as they are, as contact_force does.
template <typename Per>
VtuField tangent_vector_field(const FieldContext& c, std::string_view name, const Eigen::VectorXd& values, int stride,
                              int offset, double sign, Per per, OnMasters on_masters = OnMasters::none) {
  const int b = c.state.contact_block;
  const std::vector<Point> t = contact_tangents(c.part.dofs, c.contact, b);
  std::vector<Point> v(c.contact.size());
  for (std::size_t k = 0; k < v.size(); ++k)
    v[k] = along_tangents(t, k, b, values.data() + c.contact[k].row * stride + offset);
  const auto of = [&](const PartContactNode& n, int i) {
    return v[static_cast<std::size_t>(&n - c.contact.data())][static_cast<std::size_t>(i)];
  };
  return node_field(c, name, 3, [&](double* out) {
    for (std::size_t k = 0; k < c.contact.size(); ++k) {
      const PartContactNode& n = c.contact[k];
      for (int i = 0; i < 3; ++i) out[n.local_node * 3 + i] = sign * v[k][static_cast<std::size_t>(i)] / per(n);
    }
    if (on_masters == OnMasters::sum) add_master_sums(c, 3, of, out);
    if (on_masters == OnMasters::average) add_master_averages(c, 3, of, out);
  });
}

/// A field of one number per contact node as a node field (zero off Γ3).
VtuField contact_scalar_field(const FieldContext& c, std::string_view name, const Eigen::VectorXd& values) {
  return node_field(c, name, 1, [&](double* out) {
    for (const PartContactNode& n : c.contact) out[n.local_node] = values[n.row];
  });
}

constexpr StateField kFields[] = {
    {"u", "u", "displacement", L::node, dim, [](const State& s) { return span_of(s.u); },
     [](State& s, Span v) { set(s.u, v); },
     [](const FieldContext& c) {
       const int d = c.part.mesh().dim();
       return node_field(c, "displacement", 3, [&](double* out) {
         for (std::size_t i = 0; i < n_nodes(c); ++i)
           for (int j = 0; j < d; ++j) out[i * 3 + j] = c.state.u[static_cast<Eigen::Index>(i * d + j)];
       });
     },
     nullptr, "the displacement u_n (VTU: 3 components, unused ones 0)"},
    {"beta", "beta", "beta", L::node, one, [](const State& s) { return span_of(s.beta); },
     [](State& s, Span v) { set(s.beta, v); },
     [](const FieldContext& c) {
       return VtuField{"beta", 1, std::vector<double>(c.state.beta.data(), c.state.beta.data() + n_nodes(c))};
     },
     nullptr, "the damage β_n (1: undamaged, 0: fully damaged)"},
    {"lambda", "contact_force", "contact_lambda", L::contact_node, block, [](const State& s) { return span_of(s.lambda); },
     [](State& s, Span v) { set(s.lambda, v); },
     [](const FieldContext& c) {
       const int b = c.state.contact_block;
       return node_field(c, "contact_lambda", b, [&](double* out) {
         for (const PartContactNode& n : c.contact)
           for (int j = 0; j < b; ++j) out[n.local_node * b + j] = c.state.lambda[n.row * b + j];
       });
     },
     [](const State& s) { return s.contact_block > 1; },
     "the contact forces λ_n: contact_block numbers per contact node, the normal force first (VTU: written "
     "when the block has more than one number)"},
    {"contact_force", "contact_force_vector", "contact_force", L::node, three, nullptr, nullptr,
     [](const FieldContext& c) {
       // The nodal force the foundation exerts at each contact node: −λ ν; on a contact pair's master
       // nodes the slave's reaction, Σ_j w_jk λ_j ν_j (problem/contact_pairs.hpp).
       return node_field(c, "contact_force", 3, [&](double* out) {
         for (const PartContactNode& n : c.contact)
           for (int j = 0; j < 3; ++j) out[n.local_node * 3 + j] = -normal_force(c.state, n) * n.direction[j];
         add_master_sums(c, 3, [&](const PartContactNode& n, int j) { return normal_force(c.state, n) * n.direction[j]; },
                         out);
       });
     },
     nullptr, "the nodal force −λ ν the foundation exerts on each node of Γ3; with contact pairs, the force each "
     "body exerts on the other's nodes"},
    {"contact_pressure", "contact_pressure", "contact_pressure", L::node, one, nullptr, nullptr,
     [](const FieldContext& c) {
       // λ over the node's tributary measure on Γ3; on a pair's master nodes, the reaction over
       // the node's measure in contact (add_master_averages).
       return node_field(c, "contact_pressure", 1, [&](double* out) {
         for (const PartContactNode& n : c.contact) out[n.local_node] = normal_force(c.state, n) / n.measure;
         add_master_averages(c, 1, [&](const PartContactNode& n, int) { return normal_force(c.state, n); }, out);
       });
     },
     nullptr, "λ over the node's tributary measure on Γ3 (a pressure); on a contact pair's master nodes, the "
     "slave's reaction over the node's measure in contact"},
    {"gap", "gap", "gap", L::node, one, nullptr, nullptr,
     [](const FieldContext& c) {
       require(c.state.gap.size() == static_cast<Eigen::Index>(c.part.n_contact),
               "the gap is recorded only for cases with contact pairs");
       return node_field(c, "gap", 1, [&](double* out) {
         for (const PartContactNode& n : c.contact) out[n.local_node] = c.state.gap[n.row];
         add_master_averages(c, 1, [&](const PartContactNode& n, int) { return c.state.gap[n.row] * n.measure; }, out);
       });
     },
     [](const State& s) { return s.gap.size() > 0; },
     "the gap left g − N u at each node of Γ3 and each slave node (negative: a compliant law's penetration), and on "
     "a pair's master nodes the slave gaps averaged with the mortar weights (cases with contact pairs only; zero "
     "elsewhere)"},
    // Friction (SPEC §7): written when the contact block has more than one number.
    {"tangential_force", "tangential_force", "tangential_force", L::node, three, nullptr, nullptr,
     [](const FieldContext& c) {
       const int b = c.state.contact_block;
       return tangent_vector_field(c, "tangential_force", c.state.lambda, b, 1, -1.0,
                                   [](const PartContactNode&) { return 1.0; }, OnMasters::sum);
     },
     frictional,
     "the tangential nodal force on the body that owns the node, as a vector, like contact_force: −Σ_j λ_τ,j t_j "
     "at each node of Γ3 and each slave node (against its slip; λ_τ is the force on the obstacle or master side), "
     "and on a contact pair's master nodes the force the slave side exerts on them, Σ_j w_jk λ_τ,j t_j; per body "
     "the slave's and the master's sum to equal and opposite forces (friction only)", true},
    {"tangential_traction", "tangential_traction", "tangential_traction", L::node, three, nullptr, nullptr,
     [](const FieldContext& c) {
       const int b = c.state.contact_block;
       return tangent_vector_field(c, "tangential_traction", c.state.lambda, b, 1, -1.0,
                                   [](const PartContactNode& n) { return n.measure; }, OnMasters::average);
     },
     frictional, "tangential_force over the node's tributary measure on Γ3 (a traction on the body that owns the "
     "node, like contact_pressure; on a contact pair's master nodes, the slave side's over the node's measure in "
     "contact; friction only)", true},
    {"slip_step", "slip_step", "", L::contact_node, tangents, [](const State& s) { return span_of(s.slip_step); },
     [](State& s, Span v) { set(s.slip_step, v); }, nullptr, nullptr,
     "the last step's slip increment Δ = T u_n − h: contact_block − 1 numbers per contact node, along its "
     "tangents (friction only)", true},
    {"slip_increment", "slip_increment", "slip_increment", L::node, three, nullptr, nullptr,
     [](const FieldContext& c) {
       const int t = c.state.contact_block - 1;
       return tangent_vector_field(c, "slip_increment", c.state.slip_step, t, 0, 1.0,
                                   [](const PartContactNode&) { return 1.0; });
     },
     has_slip, "the last step's slip increment at each node of Γ3 as a vector Σ_j Δ_j t_j (friction only)", true},
    {"slip", "slip", "slip", L::contact_node, one, [](const State& s) { return span_of(s.slip); },
     [](State& s, Span v) { set(s.slip, v); },
     [](const FieldContext& c) { return contact_scalar_field(c, "slip", c.state.slip); }, has_slip,
     "the accumulated slip Σ_n ‖Δ_n‖ at each contact node, a path length (friction only; VTU: zero off Γ3)", true},
    {"contact_status", "contact_status", "contact_status", L::contact_node, one,
     [](const State& s) { return span_of(s.contact_status); }, [](State& s, Span v) { set(s.contact_status, v); },
     [](const FieldContext& c) { return contact_scalar_field(c, "contact_status", c.state.contact_status); },
     has_slip, "each contact node's status after the last step: 0 free, 1 stick, 2 slip, 3 not in contact but "
     "carrying Tresca friction (friction only; VTU: zero off Γ3)", true},
    {"sigma", "sigma", "stress", L::cell, tensor, [](const State& s) { return span_of(s.sigma); },
     [](State& s, Span v) { set(s.sigma, v); }, [](const FieldContext& c) { return tensor_field("stress", c.state.sigma); },
     nullptr, "the stress σ_n"},
    {"eps", "eps", "strain", L::cell, tensor, [](const State& s) { return span_of(s.eps); },
     [](State& s, Span v) { set(s.eps, v); }, [](const FieldContext& c) { return tensor_field("strain", c.state.eps); },
     nullptr, "the strain ε(u_n)"},
    {"von_mises", "von_mises", "von_mises", L::cell, one, nullptr, nullptr,
     [](const FieldContext& c) {
       VtuField f{"von_mises", 1, {}};
       for (const auto& t : c.state.sigma) f.values.push_back(t.von_mises());
       return f;
     },
     nullptr, "the von Mises norm of σ_n"},
    {"z", "z", "history_z", L::cell, tensor, [](const State& s) { return span_of(s.z); },
     [](State& s, Span v) { set(s.z, v); }, [](const FieldContext& c) { return tensor_field("history_z", c.state.z); },
     nullptr, "the viscoplastic history z_n = σ_n − ℰε(u_n)"},
};

}  // namespace

Eigen::VectorXd normal_forces(const State& s) {
  const int b = s.contact_block;
  if (b == 1) return s.lambda;
  return Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>>(s.lambda.data(), s.lambda.size() / b,
                                                                     Eigen::InnerStride<>(b));
}

const char* location_name(FieldLocation l) {
  switch (l) {
    case L::node: return "node";
    case L::cell: return "cell";
    case L::contact_node: return "contact node";
  }
  return "?";
}

std::span<const StateField> state_fields() { return kFields; }

const StateField& state_field(std::string_view name) {
  for (const StateField& f : kFields)
    if (f.name == name) return f;
  fail("internal: no state field '{}'", name);
}

std::vector<std::string> vtu_field_names() {
  std::vector<std::string> names;
  for (const StateField& f : kFields)
    if (!f.vtu.empty()) names.emplace_back(f.vtu);
  return names;
}

void make_vtu_fields(const FieldContext& c, const std::vector<std::string>& wanted, std::vector<VtuField>& point_data,
                     std::vector<VtuField>& cell_data) {
  for (const StateField& f : kFields) {
    if (!f.vtu_field || (f.in_vtu && !f.in_vtu(c.state))) continue;
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), f.vtu) == wanted.end()) continue;
    (f.point_data() ? point_data : cell_data).push_back(f.vtu_field(c));
  }
  for (const SurfaceField& f : c.state.surface) {  // the contact laws' declared state, after the table's
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), f.name) == wanted.end()) continue;
    point_data.push_back(node_field(c, f.name, f.width, [&](double* out) {
      for (const PartContactNode& n : c.contact)
        for (int j = 0; j < f.width; ++j) out[n.local_node * f.width + j] = f.values[n.row * f.width + j];
    }));
  }
}

}  // namespace vpc
