#pragma once
// Global assembly loops for the P1/P0/P1 discretization of Problem 3.1. Each loop
// calls a small element kernel and scatters into a global matrix or vector; none
// of them knows about contact or damage bounds.
#include "core/sym_tensor.hpp"
#include "fem/cell_geometry.hpp"
#include "fem/dof_map.hpp"
#include "material/elasticity.hpp"
#include "mesh/mesh.hpp"

#include <Eigen/Sparse>
#include <functional>
#include <span>
#include <vector>

namespace vpc {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Vector = Eigen::VectorXd;
/// A vector field of (x, t), e.g. f0 and f2; components beyond d are ignored.
using VectorField = std::function<Point(const Point& x, double t)>;
using ScalarField = std::function<double(const Point& x, double t)>;

/// Elastic stiffness K_ij = (ℰε(φ_j), ε(φ_i)) on the free dofs.
SparseMatrix assemble_stiffness(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                const Elasticity& elasticity, const DofMap& dofs);
/// The same with ℰ per cell: elasticity[cell_material[c]] on cell c (several materials).
SparseMatrix assemble_stiffness(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                std::span<const Elasticity> elasticity, std::span<const int> cell_material,
                                const DofMap& dofs);

/// P1 scalar mass matrix M_ij = (ψ_j, ψ_i).
SparseMatrix assemble_mass(const Mesh& mesh, const std::vector<CellGeometry>& geo);

/// P1 scalar stiffness (Laplacian) A_ij = (∇ψ_j, ∇ψ_i); with `weight` (one per cell) Σ_c weight_c A_c.
SparseMatrix assemble_laplacian(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                std::span<const double> weight = {});

/// Full-space load vector (f(t), φ_i)_V = ∫Ω f0·φ_i + ∫Γ2 f2·φ_i  (2.25).
Vector assemble_load(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                     const std::vector<int>& traction_facets, const VectorField& f0,
                     const VectorField& f2, double t);

/// Adds the load of a normal pressure p(x, t) on `facets` to the full-space F:
/// ∫ −p n·φ_i over each facet, n its outward normal (same quadrature as f2).
void add_pressure_load(const Mesh& mesh, const std::vector<int>& facets, const ScalarField& p, double t, Vector& F);

/// (τ, ε(λ_a e_i)) over one cell for a constant τ: its vertex a's share in component i of
/// the vector below (the divergence term, and the reactions at prescribed dofs).
inline double stress_divergence_entry(const CellGeometry& g, const SymTensor& tau, int d, int a, int i) {
  double s = 0;  // |T| Σ_j τ_ij ∂_j λ_a, using the symmetry of τ
  for (int j = 0; j < d; ++j) s += tau(i, j) * g.grad[a][j];
  return g.volume * s;
}

/// Full-space vector (τ, ε(φ_i))_Q for a P0 tensor field τ: the term Bᵀz of (3.9).
Vector assemble_stress_divergence(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                  const std::vector<SymTensor>& tau);

/// Scalar load (s, ψ_i) for a P0 field s: the damage source vector F_φ of (3.8).
Vector assemble_p0_source(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                          const std::vector<double>& s);

/// The mean of a nodal (P1 scalar) field over the vertices of cell c: its value at the centroid.
inline double cell_mean(const Mesh& mesh, const Vector& nodal, int c) {
  double s = 0;
  for (int a = 0; a < mesh.nodes_per_cell(); ++a) s += nodal[mesh.cell(c)[a]];
  return s / mesh.nodes_per_cell();
}

/// The strain ε(u) on cell c (geometry g) of a full-space P1 displacement.
SymTensor cell_strain(const Mesh& mesh, const CellGeometry& g, const Vector& u_full, int c);
/// The strain ε = sym ∇u of a P1 displacement on a simplex of dimension d with geometry g whose
/// vertex a is node nodes[a] of `u` (d numbers a node): cell_strain's, for cells of another numbering
/// (a bisection forest's parents).
SymTensor simplex_strain(int d, const int* nodes, const CellGeometry& g, const double* u);

/// P0 strains ε(u) of a full-space P1 displacement.
void compute_strain(const Mesh& mesh, const std::vector<CellGeometry>& geo, const Vector& u_full,
                    std::vector<SymTensor>& eps);

/// Restriction of a full-space vector to the free dofs, and its extension by zero.
Vector restrict_to_free(const DofMap& dofs, const Vector& full);
Vector extend_from_free(const DofMap& dofs, const Vector& free);

}  // namespace vpc
