#include "fem/assembly.hpp"

#include "fem/quadrature.hpp"

#include <Eigen/Dense>

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

SparseMatrix from_triplets(int n, std::vector<Eigen::Triplet<double>>& t) {
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

}  // namespace

SparseMatrix assemble_stiffness(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                const Elasticity& elasticity, const DofMap& dofs) {
  const int d = mesh.dim(), nd = (d + 1) * d;
  const Eigen::MatrixXd D = elasticity.voigt();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(mesh.n_cells()) * nd * nd);
  std::vector<int> idx(nd);
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const Eigen::MatrixXd B = strain_matrix(d, geo[c]);
    const Eigen::MatrixXd Ke = geo[c].volume * B.transpose() * D * B;
    for (int a = 0; a <= d; ++a)
      for (int i = 0; i < d; ++i) idx[a * d + i] = dofs.free_index(dofs.full_index(mesh.cell(c)[a], i));
    for (int r = 0; r < nd; ++r) {
      if (idx[r] < 0) continue;
      for (int s = 0; s < nd; ++s)
        if (idx[s] >= 0) t.emplace_back(idx[r], idx[s], Ke(r, s));
    }
  }
  return from_triplets(dofs.n_free(), t);
}

SparseMatrix assemble_mass(const Mesh& mesh, const std::vector<CellGeometry>& geo) {
  const int d = mesh.dim();
  // Exact P1 mass: ∫ λ_a λ_b = |T| (1 + δ_ab) / ((d + 1)(d + 2)).
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(mesh.n_cells()) * (d + 1) * (d + 1));
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const double m = geo[c].volume / ((d + 1) * (d + 2));
    for (int a = 0; a <= d; ++a)
      for (int b = 0; b <= d; ++b) t.emplace_back(mesh.cell(c)[a], mesh.cell(c)[b], a == b ? 2 * m : m);
  }
  return from_triplets(mesh.n_nodes(), t);
}

SparseMatrix assemble_laplacian(const Mesh& mesh, const std::vector<CellGeometry>& geo) {
  const int d = mesh.dim();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(mesh.n_cells()) * (d + 1) * (d + 1));
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const auto& g = geo[c];
    for (int a = 0; a <= d; ++a)
      for (int b = 0; b <= d; ++b) {
        double s = 0;
        for (int i = 0; i < d; ++i) s += g.grad[a][i] * g.grad[b][i];
        t.emplace_back(mesh.cell(c)[a], mesh.cell(c)[b], g.volume * s);
      }
  }
  return from_triplets(mesh.n_nodes(), t);
}

Vector assemble_load(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                     const std::vector<int>& traction_facets, const VectorField& f0,
                     const VectorField& f2, double t) {
  const int d = mesh.dim();
  Vector F = Vector::Zero(static_cast<Eigen::Index>(mesh.n_nodes()) * d);
  auto integrate = [&](const int* nodes, int n_vertices, double measure, const VectorField& f) {
    for (const auto& q : simplex_rule(n_vertices - 1)) {
      Point x{0, 0, 0};
      for (int a = 0; a < n_vertices; ++a)
        for (int j = 0; j < 3; ++j) x[j] += q.lambda[a] * mesh.node(nodes[a])[j];
      const Point fx = f(x, t);
      for (int a = 0; a < n_vertices; ++a)
        for (int i = 0; i < d; ++i) F[nodes[a] * d + i] += measure * q.weight * q.lambda[a] * fx[i];
    }
  };
  if (f0)
    for (int c = 0; c < mesh.n_cells(); ++c) integrate(mesh.cell(c), d + 1, geo[c].volume, f0);
  if (f2)
    for (int f : traction_facets) integrate(mesh.facet(f), d, mesh.facet_measure(f), f2);
  return F;
}

Vector assemble_stress_divergence(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                  const std::vector<SymTensor>& tau) {
  const int d = mesh.dim();
  Vector F = Vector::Zero(static_cast<Eigen::Index>(mesh.n_nodes()) * d);
  for (int c = 0; c < mesh.n_cells(); ++c) {
    // (τ, ε(λ_a e_i)) = |T| Σ_j τ_ij ∂_j λ_a, using the symmetry of τ.
    for (int a = 0; a <= d; ++a)
      for (int i = 0; i < d; ++i) {
        double s = 0;
        for (int j = 0; j < d; ++j) s += tau[c](i, j) * geo[c].grad[a][j];
        F[mesh.cell(c)[a] * d + i] += geo[c].volume * s;
      }
  }
  return F;
}

Vector assemble_p0_source(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                          const std::vector<double>& s) {
  const int d = mesh.dim();
  Vector F = Vector::Zero(mesh.n_nodes());
  for (int c = 0; c < mesh.n_cells(); ++c)
    for (int a = 0; a <= d; ++a) F[mesh.cell(c)[a]] += s[c] * geo[c].volume / (d + 1);
  return F;
}

void compute_strain(const Mesh& mesh, const std::vector<CellGeometry>& geo, const Vector& u,
                    std::vector<SymTensor>& eps) {
  const int d = mesh.dim();
  eps.assign(mesh.n_cells(), SymTensor{});
  for (int c = 0; c < mesh.n_cells(); ++c) {
    double G[3][3] = {};  // displacement gradient ∂_j u_i
    for (int a = 0; a <= d; ++a) {
      const int n = mesh.cell(c)[a];
      for (int i = 0; i < d; ++i)
        for (int j = 0; j < d; ++j) G[i][j] += u[n * d + i] * geo[c].grad[a][j];
    }
    SymTensor& e = eps[c];
    for (int i = 0; i < 3; ++i) e[i] = G[i][i];
    e[3] = 0.5 * (G[1][2] + G[2][1]);
    e[4] = 0.5 * (G[0][2] + G[2][0]);
    e[5] = 0.5 * (G[0][1] + G[1][0]);
  }
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
