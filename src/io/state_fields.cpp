#include "io/state_fields.hpp"

#include "core/error.hpp"

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
         for (const PartContactNode& n : c.part.contact)
           for (int j = 0; j < b; ++j) out[n.local_node * b + j] = c.state.lambda[n.row * b + j];
       });
     },
     [](const State& s) { return s.contact_block > 1; },
     "the contact forces λ_n: contact_block numbers per contact node, the normal force first (VTU: written "
     "when the block has more than one number)"},
    {"contact_force", "contact_force_vector", "contact_force", L::node, three, nullptr, nullptr,
     [](const FieldContext& c) {
       // The nodal force the foundation exerts at each contact node: −λ ν.
       return node_field(c, "contact_force", 3, [&](double* out) {
         for (const PartContactNode& n : c.part.contact)
           for (int j = 0; j < 3; ++j) out[n.local_node * 3 + j] = -normal_force(c.state, n) * n.direction[j];
       });
     },
     nullptr, "the nodal force −λ ν the foundation exerts on each node of Γ3"},
    {"contact_pressure", "contact_pressure", "contact_pressure", L::node, one, nullptr, nullptr,
     [](const FieldContext& c) {
       // λ over the node's tributary measure on Γ3.
       return node_field(c, "contact_pressure", 1, [&](double* out) {
         for (const PartContactNode& n : c.part.contact) out[n.local_node] = normal_force(c.state, n) / n.measure;
       });
     },
     nullptr, "λ over the node's tributary measure on Γ3 (a pressure)"},
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
}

}  // namespace vpc
