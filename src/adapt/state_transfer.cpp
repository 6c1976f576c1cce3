#include "adapt/state_transfer.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "fem/cell_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace vpc {

namespace {

constexpr int kTensor = 6;  // SymTensor's numbers

/// The part's node and cell of each node and cell of the leaf mesh (the identity on one process's whole
/// mesh; on the PETSc engine's one rank, its partitioner's order).
struct PartNumbers {
  std::vector<int> node, cell;
};

PartNumbers part_numbers(const MeshPart& part) {
  PartNumbers p;
  p.node.assign(part.original_node.size(), -1);
  p.cell.assign(part.original_cell.size(), -1);
  for (std::size_t l = 0; l < part.original_node.size(); ++l)
    p.node.at(static_cast<std::size_t>(part.original_node[l])) = static_cast<int>(l);
  for (std::size_t c = 0; c < part.original_cell.size(); ++c)
    p.cell.at(static_cast<std::size_t>(part.original_cell[c])) = static_cast<int>(c);
  return p;
}

/// The cell tensors in the leaf mesh's order: t[cell[p]] for p = 0, 1, ….
void push_tensors(const std::vector<SymTensor>& t, const std::vector<int>& cell, std::vector<double>& out) {
  out.clear();
  out.reserve(t.size() * kTensor);
  for (int c : cell) out.insert(out.end(), t[static_cast<std::size_t>(c)].c.begin(), t[static_cast<std::size_t>(c)].c.end());
}

/// Back into the part's order: out[cell[p]] = the p-th tensor of v.
std::vector<SymTensor> tensors(const std::vector<double>& v, const std::vector<int>& cell) {
  std::vector<SymTensor> out(v.size() / kTensor);
  for (std::size_t p = 0; p < out.size(); ++p)
    std::copy_n(v.begin() + static_cast<std::ptrdiff_t>(p * kTensor), kTensor, out[static_cast<std::size_t>(cell[p])].c.begin());
  return out;
}

/// Where the packed contact fields of ForestState::contact keep the status (−1: no friction).
int status_slot(int block) { return block > 1 ? 2 * block : -1; }

}  // namespace

SymTensor forest_cell_strain(const BisectionForest& forest, const std::vector<double>& u, int dim, int c) {
  const auto v = forest.vertices(c);
  Point x[4];
  for (int k = 0; k <= dim; ++k) x[k] = forest.node(v[static_cast<std::size_t>(k)]);
  return simplex_strain(dim, v.data(), cell_geometry(dim, x), u.data());
}

ForestState gather_state(const BisectionForest& forest, const TimeStepper& s, const State& carry) {
  const Mesh& mesh = s.mesh();
  const int d = mesh.dim();
  ForestState fs;
  fs.n = carry.n;
  fs.t = carry.t;
  fs.dim = d;
  fs.leaves = forest.leaves();
  require(static_cast<int>(fs.leaves.size()) == mesh.n_cells(), "mesh adaptivity: the forest has {} leaves, the mesh {} cells",
          fs.leaves.size(), mesh.n_cells());
  const std::vector<int> number = forest.mesh_numbers();
  const PartNumbers local = part_numbers(s.part());
  const auto n = static_cast<std::size_t>(forest.n_nodes());
  fs.u.assign(n * static_cast<std::size_t>(d), 0.0);
  fs.beta.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (number[i] < 0) continue;
    const int k = local.node[static_cast<std::size_t>(number[i])];
    fs.beta[i] = carry.beta[k];
    for (int j = 0; j < d; ++j) fs.u[i * static_cast<std::size_t>(d) + static_cast<std::size_t>(j)] = carry.u[k * d + j];
  }
  push_tensors(carry.sigma, local.cell, fs.sigma);
  push_tensors(carry.eps, local.cell, fs.eps);
  push_tensors(carry.z, local.cell, fs.z);

  // The contact rows, by their mesh node: packed per forest node.
  fs.contact_block = carry.contact_block;
  const int b = carry.contact_block;
  fs.contact_width = b + (b > 1 ? b - 1 + 2 : 0);
  for (const SurfaceField& f : carry.surface) fs.contact_width += f.width;
  const auto w = static_cast<std::size_t>(fs.contact_width);
  fs.contact.assign(n * w, NAN);
  std::vector<int> forest_node(static_cast<std::size_t>(mesh.n_nodes()), -1);  // per part node
  for (std::size_t i = 0; i < n; ++i)
    if (number[i] >= 0) forest_node[static_cast<std::size_t>(local.node[static_cast<std::size_t>(number[i])])] = static_cast<int>(i);
  const std::vector<PartContactNode>& rows = s.contact().nodes;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    double* out = &fs.contact[static_cast<std::size_t>(forest_node[static_cast<std::size_t>(rows[r].local_node)]) * w];
    const auto R = static_cast<Eigen::Index>(r);
    const double measure = rows[r].measure > 0 ? rows[r].measure : 1.0;
    for (int j = 0; j < b; ++j) *out++ = carry.lambda[R * b + j] / measure;
    if (b > 1) {
      for (int j = 0; j < b - 1; ++j) *out++ = carry.slip_step[R * (b - 1) + j];
      *out++ = carry.slip[R];
      *out++ = carry.contact_status[R];
    }
    for (const SurfaceField& f : carry.surface)
      for (int j = 0; j < f.width; ++j) *out++ = f.values[R * f.width + j];
  }
  return fs;
}

void carry_through_coarsening(const BisectionForest& forest, const std::vector<const Elasticity*>& elasticity,
                              ForestState& fs) {
  const std::vector<int> before = fs.leaves;
  fs.leaves = forest.leaves();
  fs.z = forest.inherit(before, fs.z, kTensor);
  fs.eps = forest.inherit(before, fs.eps, kTensor);  // (the cells kept; the parents' below)
  fs.sigma = forest.inherit(before, fs.sigma, kTensor);
  const std::unordered_set<int> kept(before.begin(), before.end());
  for (std::size_t k = 0; k < fs.leaves.size(); ++k) {
    const int c = fs.leaves[k];
    if (kept.count(c)) continue;
    // A parent made a leaf again: ε(u) of the injected u on it, σ = ℰε + z.
    const SymTensor e = forest_cell_strain(forest, fs.u, fs.dim, c);
    SymTensor z;
    std::copy_n(fs.z.begin() + static_cast<std::ptrdiff_t>(k * kTensor), kTensor, z.c.begin());
    const SymTensor s = elasticity[static_cast<std::size_t>(forest.root(c))]->apply(e) + z;
    std::copy(e.c.begin(), e.c.end(), fs.eps.begin() + static_cast<std::ptrdiff_t>(k * kTensor));
    std::copy(s.c.begin(), s.c.end(), fs.sigma.begin() + static_cast<std::ptrdiff_t>(k * kTensor));
  }
}

void carry_through_refinement(const BisectionForest& forest, ForestState& fs) {
  const std::vector<int> before = fs.leaves;
  fs.leaves = forest.leaves();
  fs.sigma = forest.inherit(before, fs.sigma, kTensor);
  fs.eps = forest.inherit(before, fs.eps, kTensor);
  fs.z = forest.inherit(before, fs.z, kTensor);
  forest.interpolate(fs.u, fs.dim);
  forest.interpolate(fs.beta, 1);
  // The contact fields: the mean of the edge's ends where both are contact nodes, the one end's values
  // where only one is (a node beside a clamped one), NaN where neither; a status takes the lesser one
  // (free before stick before slip: recomputed by the next step).
  const auto w = static_cast<std::size_t>(fs.contact_width);
  const int status = status_slot(fs.contact_block);
  for (auto i = fs.contact.size() / std::max<std::size_t>(w, 1); w > 0 && i < static_cast<std::size_t>(forest.n_nodes()); ++i) {
    const auto [a, b] = forest.made_at(static_cast<int>(i));
    const std::size_t A = static_cast<std::size_t>(a) * w, B = static_cast<std::size_t>(b) * w;
    const bool has_a = !std::isnan(fs.contact[A]), has_b = !std::isnan(fs.contact[B]);
    for (std::size_t j = 0; j < w; ++j) {
      const double x = fs.contact[A + j], y = fs.contact[B + j];
      fs.contact.push_back(has_a && has_b ? (static_cast<int>(j) == status ? std::min(x, y) : 0.5 * (x + y))
                           : has_a        ? x
                                          : y);
    }
  }
}

State scatter_state(const BisectionForest& forest, const ForestState& fs, const TimeStepper& s) {
  const Mesh& mesh = s.mesh();
  const int d = fs.dim;
  const std::vector<int> number = forest.mesh_numbers();
  const PartNumbers local = part_numbers(s.part());
  State out;
  out.n = fs.n;
  out.t = fs.t;
  out.u = Eigen::VectorXd::Zero(mesh.n_nodes() * d);
  out.beta = Eigen::VectorXd::Zero(mesh.n_nodes());
  std::vector<int> forest_node(static_cast<std::size_t>(mesh.n_nodes()), -1);  // per part node
  for (std::size_t i = 0; i < number.size(); ++i) {
    if (number[i] < 0) continue;
    const int k = local.node[static_cast<std::size_t>(number[i])];
    forest_node[static_cast<std::size_t>(k)] = static_cast<int>(i);
    out.beta[k] = fs.beta[i];
    for (int j = 0; j < d; ++j) out.u[k * d + j] = fs.u[i * static_cast<std::size_t>(d) + static_cast<std::size_t>(j)];
  }
  require(fs.leaves.size() == static_cast<std::size_t>(mesh.n_cells()), "mesh adaptivity: {} leaves carried for {} cells",
          fs.leaves.size(), mesh.n_cells());
  out.sigma = tensors(fs.sigma, local.cell);
  out.eps = tensors(fs.eps, local.cell);
  out.z = tensors(fs.z, local.cell);

  const int b = fs.contact_block;
  out.contact_block = b;
  const std::vector<PartContactNode>& rows = s.contact().nodes;
  const auto m = static_cast<Eigen::Index>(rows.size());
  out.lambda = Eigen::VectorXd::Zero(m * b);
  if (b > 1) {
    out.slip_step = Eigen::VectorXd::Zero(m * (b - 1));
    out.slip = Eigen::VectorXd::Zero(m);
    out.contact_status = Eigen::VectorXd::Zero(m);
  }
  out.surface = s.state().surface;  // the new mesh's initial values where a row carries none
  const auto w = static_cast<std::size_t>(fs.contact_width);
  for (Eigen::Index r = 0; r < m; ++r) {
    const auto& row = rows[static_cast<std::size_t>(r)];
    const int i = forest_node[static_cast<std::size_t>(row.local_node)];
    const double* in = &fs.contact[static_cast<std::size_t>(i) * w];
    if (std::isnan(in[0])) continue;  // not a contact node before (a new Γ3 node of no contact edge)
    for (int j = 0; j < b; ++j) out.lambda[r * b + j] = *in++ * row.measure;
    if (b > 1) {
      for (int j = 0; j < b - 1; ++j) out.slip_step[r * (b - 1) + j] = *in++;
      out.slip[r] = *in++;
      out.contact_status[r] = *in++;
    }
    for (SurfaceField& f : out.surface)
      for (int j = 0; j < f.width; ++j) f.values[r * f.width + j] = *in++;
  }
  return out;
}

}  // namespace vpc
