#include "fem/assembly.hpp"

#include "fem/quadrature.hpp"

#include <Eigen/Dense>
#include <omp.h>

#include <algorithm>
#include <array>
#include <functional>

namespace vpc {

namespace {

constexpr int n_voigt(int d) { return d == 1 ? 1 : (d == 2 ? 3 : 6); }

/// Engineering-Voigt strain-displacement matrix B of one cell: ε_voigt = B u_e,
/// u_e ordered (node a, component i) -> a * d + i.
Eigen::MatrixXd strain_matrix(int d, const CellGeometry& g) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n_voigt(d), (d + 1) * d);
  for (int a = 0; a <= d; ++a) {
    const auto& dl = g.grad[a];
    const int c = a * d;
    if (d == 1) {
      B(0, c) = dl[0];
    } else if (d == 2) {
      B(0, c) = dl[0];
      B(1, c + 1) = dl[1];
      B(2, c) = dl[1];
      B(2, c + 1) = dl[0];
    } else {
      B(0, c) = dl[0];
      B(1, c + 1) = dl[1];
      B(2, c + 2) = dl[2];
      B(3, c + 1) = dl[2];
      B(3, c + 2) = dl[1];
      B(4, c) = dl[2];
      B(4, c + 2) = dl[0];
      B(5, c) = dl[1];
      B(5, c + 1) = dl[0];
    }
  }
  return B;
}

/// Below this many cells a loop runs on one thread (the fork costs more).
constexpr int kParallelCells = 4096;

int threads_for(int n_cells) { return n_cells < kParallelCells ? 1 : omp_get_max_threads(); }

/// Runs kernel(c, out) for every cell, each thread scattering into its own
/// vector of `size` entries, then adds them up: no atomics, deterministic for a
/// given number of threads.
template <typename Kernel>
Vector scatter_over_cells(int n_cells, Eigen::Index size, Kernel&& kernel) {
  const int nt = threads_for(n_cells);
  if (nt == 1) {
    Vector out = Vector::Zero(size);
    for (int c = 0; c < n_cells; ++c) kernel(c, out);
    return out;
  }
  std::vector<Vector> parts(nt);
#pragma omp parallel num_threads(nt)
  {
    Vector& mine = parts[omp_get_thread_num()];
    mine = Vector::Zero(size);
#pragma omp for schedule(static)
    for (int c = 0; c < n_cells; ++c) kernel(c, mine);
  }
  for (int t = 1; t < nt; ++t) parts[0] += parts[t];
  return std::move(parts[0]);
}

/// The sparsity of a P1 operator with `block` unknowns per node: the (row, col)
/// pairs of unknowns of nodes sharing a cell. `index(node, comp)` numbers the
/// unknowns (−1: eliminated) and must increase with (node, comp). Built once, so
/// assembly adds element matrices in place instead of storing triplets (which
/// would cost 16 bytes per element-matrix entry at the memory peak of setup).
SparseMatrix sparsity_pattern(const Mesh& mesh, int block, int n, const std::function<int(int, int)>& index) {
  const int npc = mesh.nodes_per_cell();
  std::vector<std::vector<int>> adjacent(mesh.n_nodes());
  for (int c = 0; c < mesh.n_cells(); ++c)
    for (int a = 0; a < npc; ++a)
      for (int b = 0; b < npc; ++b) adjacent[mesh.cell(c)[a]].push_back(mesh.cell(c)[b]);
  SparseMatrix A(n, n);
  std::vector<int> col_nnz(n, 0);
  for (auto& adj : adjacent) {
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
  }
  for (int node = 0; node < mesh.n_nodes(); ++node)
    for (int cj = 0; cj < block; ++cj) {
      const int j = index(node, cj);
      if (j < 0) continue;
      for (int other : adjacent[node])
        for (int ci = 0; ci < block; ++ci) col_nnz[j] += index(other, ci) >= 0;
    }
  A.reserve(col_nnz);
  for (int node = 0; node < mesh.n_nodes(); ++node)
    for (int cj = 0; cj < block; ++cj) {
      const int j = index(node, cj);
      if (j < 0) continue;
      for (int other : adjacent[node])
        for (int ci = 0; ci < block; ++ci) {
          const int i = index(other, ci);
          if (i >= 0) A.insert(i, j) = 0.0;
        }
    }
  A.makeCompressed();
  return A;
}

/// A(idx[r], idx[s]) += Ke(r, s) for the entries whose indices are ≥ 0; the
/// pattern must contain them.
void add_element(SparseMatrix& A, const int* idx, int nd, const double* Ke) {
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  double* values = A.valuePtr();
  for (int s = 0; s < nd; ++s) {
    const int j = idx[s];
    if (j < 0) continue;
    const int* begin = inner + outer[j];
    const int* end = inner + outer[j + 1];
    for (int r = 0; r < nd; ++r) {
      const int i = idx[r];
      if (i < 0) continue;
      const int* pos = std::lower_bound(begin, end, i);
      values[pos - inner] += Ke[r + s * nd];  // column-major Ke
    }
  }
}

SparseMatrix scalar_pattern(const Mesh& mesh) {
  return sparsity_pattern(mesh, 1, mesh.n_nodes(), [](int node, int) { return node; });
}

}  // namespace

SparseMatrix assemble_stiffness(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                const Elasticity& elasticity, const DofMap& dofs) {
  const std::vector<int> one_material(mesh.n_cells(), 0);
  return assemble_stiffness(mesh, geo, std::span(&elasticity, 1), one_material, dofs);
}

SparseMatrix assemble_stiffness(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                std::span<const Elasticity> elasticity, std::span<const int> cell_material,
                                const DofMap& dofs) {
  const int d = mesh.dim(), nd = (d + 1) * d;
  std::vector<Eigen::MatrixXd> D;
  for (const Elasticity& e : elasticity) D.push_back(e.voigt());
  SparseMatrix K = sparsity_pattern(mesh, d, dofs.n_free(),
                                    [&](int node, int c) { return dofs.free_index(dofs.full_index(node, c)); });
  std::vector<int> idx(nd);
  Eigen::MatrixXd Ke(nd, nd);
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const Eigen::MatrixXd B = strain_matrix(d, geo[c]);
    Ke.noalias() = geo[c].volume * B.transpose() * D[cell_material[c]] * B;
    for (int a = 0; a <= d; ++a)
      for (int i = 0; i < d; ++i) idx[a * d + i] = dofs.free_index(dofs.full_index(mesh.cell(c)[a], i));
    add_element(K, idx.data(), nd, Ke.data());
  }
  return K;
}

SparseMatrix assemble_mass(const Mesh& mesh, const std::vector<CellGeometry>& geo) {
  const int d = mesh.dim(), n = d + 1;
  // Exact P1 mass: ∫ λ_a λ_b = |T| (1 + δ_ab) / ((d + 1)(d + 2)).
  SparseMatrix M = scalar_pattern(mesh);
  double Me[16];
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const double m = geo[c].volume / ((d + 1) * (d + 2));
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) Me[a + b * n] = a == b ? 2 * m : m;
    add_element(M, mesh.cell(c), n, Me);
  }
  return M;
}

SparseMatrix assemble_laplacian(const Mesh& mesh, const std::vector<CellGeometry>& geo, std::span<const double> weight) {
  const int d = mesh.dim(), n = d + 1;
  SparseMatrix A = scalar_pattern(mesh);
  double Ae[16];
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const auto& g = geo[c];
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        double s = 0;
        for (int i = 0; i < d; ++i) s += g.grad[a][i] * g.grad[b][i];
        Ae[a + b * n] = (weight.empty() ? g.volume : weight[static_cast<std::size_t>(c)] * g.volume) * s;
      }
    add_element(A, mesh.cell(c), n, Ae);
  }
  return A;
}

namespace {

/// ∫_S f·ψ_a over a simplex with V vertices in d dimensions (measure |S|), by the
/// degree-2 rule, added into F. Fixed sizes: this runs at every quadrature point
/// of every cell at every step.
template <int V, int D>
void integrate_load(const Mesh& mesh, const int* nodes, double measure, const VectorField& f, double t, Vector& F) {
  std::array<const Point*, V> x;
  for (int a = 0; a < V; ++a) x[a] = &mesh.node(nodes[a]);
  for (const auto& q : simplex_rule(V - 1)) {
    Point xq{0, 0, 0};
    for (int a = 0; a < V; ++a)
      for (int j = 0; j < 3; ++j) xq[j] += q.lambda[a] * (*x[a])[j];
    const Point fx = f(xq, t);
    for (int a = 0; a < V; ++a) {
      const double w = measure * q.weight * q.lambda[a];
      for (int i = 0; i < D; ++i) F[nodes[a] * D + i] += w * fx[i];
    }
  }
}

template <int D>
Vector assemble_load_d(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                       const std::vector<int>& traction_facets, const VectorField& f0,
                       const VectorField& f2, double t) {
  const Eigen::Index size = static_cast<Eigen::Index>(mesh.n_nodes()) * D;
  Vector F = f0 ? scatter_over_cells(mesh.n_cells(), size,
                                     [&](int c, Vector& out) {
                                       integrate_load<D + 1, D>(mesh, mesh.cell(c), geo[c].volume, f0, t, out);
                                     })
               : Vector::Zero(size);
  if (f2)
    for (int f : traction_facets) integrate_load<D, D>(mesh, mesh.facet(f), mesh.facet_measure(f), f2, t, F);
  return F;
}

}  // namespace

Vector assemble_load(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                     const std::vector<int>& traction_facets, const VectorField& f0,
                     const VectorField& f2, double t) {
  switch (mesh.dim()) {
    case 1: return assemble_load_d<1>(mesh, geo, traction_facets, f0, f2, t);
    case 2: return assemble_load_d<2>(mesh, geo, traction_facets, f0, f2, t);
    default: return assemble_load_d<3>(mesh, geo, traction_facets, f0, f2, t);
  }
}

void add_pressure_load(const Mesh& mesh, const std::vector<int>& facets, const ScalarField& p, double t, Vector& F) {
  for (int f : facets) {
    const Point n = mesh.facet_normal(f);
    const VectorField traction = [&](const Point& x, double s) {
      const double px = p(x, s);
      return Point{-px * n[0], -px * n[1], -px * n[2]};
    };
    switch (mesh.dim()) {
      case 1: integrate_load<1, 1>(mesh, mesh.facet(f), mesh.facet_measure(f), traction, t, F); break;
      case 2: integrate_load<2, 2>(mesh, mesh.facet(f), mesh.facet_measure(f), traction, t, F); break;
      default: integrate_load<3, 3>(mesh, mesh.facet(f), mesh.facet_measure(f), traction, t, F); break;
    }
  }
}

Vector assemble_stress_divergence(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                  const std::vector<SymTensor>& tau) {
  const int d = mesh.dim();
  return scatter_over_cells(mesh.n_cells(), static_cast<Eigen::Index>(mesh.n_nodes()) * d, [&](int c, Vector& F) {
    for (int a = 0; a <= d; ++a)
      for (int i = 0; i < d; ++i) F[mesh.cell(c)[a] * d + i] += stress_divergence_entry(geo[c], tau[c], d, a, i);
  });
}

Vector assemble_p0_source(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                          const std::vector<double>& s) {
  const int d = mesh.dim();
  return scatter_over_cells(mesh.n_cells(), mesh.n_nodes(), [&](int c, Vector& F) {
    for (int a = 0; a <= d; ++a) F[mesh.cell(c)[a]] += s[c] * geo[c].volume / (d + 1);
  });
}

SymTensor cell_strain(const Mesh& mesh, const CellGeometry& g, const Vector& u, int c) {
  return simplex_strain(mesh.dim(), mesh.cell(c), g, u.data());
}

SymTensor simplex_strain(int d, const int* nodes, const CellGeometry& g, const double* u) {
  double G[3][3] = {};  // displacement gradient ∂_j u_i
  for (int a = 0; a <= d; ++a) {
    const int n = nodes[a];
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) G[i][j] += u[n * d + i] * g.grad[a][j];
  }
  SymTensor e;
  for (int i = 0; i < 3; ++i) e[i] = G[i][i];
  e[3] = 0.5 * (G[1][2] + G[2][1]);
  e[4] = 0.5 * (G[0][2] + G[2][0]);
  e[5] = 0.5 * (G[0][1] + G[1][0]);
  return e;
}

void compute_strain(const Mesh& mesh, const std::vector<CellGeometry>& geo, const Vector& u,
                    std::vector<SymTensor>& eps) {
  const int n_cells = mesh.n_cells();
  eps.resize(n_cells);  // every entry is written below
#pragma omp parallel for schedule(static) if (n_cells >= kParallelCells)
  for (int c = 0; c < n_cells; ++c) eps[c] = cell_strain(mesh, geo[c], u, c);
}

Vector restrict_to_free(const DofMap& dofs, const Vector& full) {
  Vector v(dofs.n_free());
  for (int i = 0; i < dofs.n_full(); ++i)
    if (dofs.free_index(i) >= 0) v[dofs.free_index(i)] = full[i];
  return v;
}

Vector extend_from_free(const DofMap& dofs, const Vector& free) {
  Vector v = Vector::Zero(dofs.n_full());
  for (int i = 0; i < dofs.n_full(); ++i)
    if (dofs.free_index(i) >= 0) v[i] = free[dofs.free_index(i)];
  return v;
}

}  // namespace vpc
