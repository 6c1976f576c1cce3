#pragma once
// The norms of Theorem 3.5 (3.39), for discrete fields on one mesh and for the
// error of a discrete state against an exact solution:
//   u: the energy norm (ℰε(e), ε(e))^{1/2} (equivalent to |·|_V on V, which is zero
//      on Γ1) and, as an extra, the L2 norm;
//   σ: the L2 norm of a P0 symmetric tensor field (Frobenius, τ:τ);
//   β: the L2 norm and the H1 seminorm |∇·|_L2 of a P1 scalar field.
#include "core/sym_tensor.hpp"
#include "fem/assembly.hpp"
#include "fem/cell_geometry.hpp"
#include "fem/quadrature.hpp"
#include "material/elasticity.hpp"
#include "mesh/mesh.hpp"
#include "scheme/state.hpp"

#include <array>
#include <vector>

namespace vpc {

/// Norms of discrete fields on one mesh (P1 displacement and damage, P0 tensors).
/// The integrals are exact: they use the P1 mass and Laplacian matrices of
/// fem/assembly.hpp and the constant strain of each cell.
class DiscreteNorms {
 public:
  DiscreteNorms(const Mesh& mesh, const Elasticity& elasticity);

  /// (ℰε(e), ε(e))^{1/2} of a full-space P1 displacement (node * d + i).
  double energy(const Vector& e) const;
  /// L2 norm of a full-space P1 vector field.
  double l2_vector(const Vector& e) const;
  /// L2 norm of a P0 tensor field.
  double l2(const std::vector<SymTensor>& tau) const;
  /// L2 norm of a P1 scalar field: (eᵀMe)^{1/2}.
  double l2(const Vector& e) const;
  /// H1 seminorm of a P1 scalar field: (eᵀAe)^{1/2}.
  double h1_seminorm(const Vector& e) const;

  const std::vector<CellGeometry>& geometry() const { return geo_; }

 private:
  const Mesh& mesh_;
  Elasticity elasticity_;
  std::vector<CellGeometry> geo_;
  SparseMatrix M_, A_;
};

/// An exact solution (u, σ, β) of Problem 2.1, evaluated pointwise.
class ExactSolution {
 public:
  /// Everything the error norms need at one point.
  struct Values {
    Point u{};
    std::array<Point, 3> grad_u{};
    SymTensor sigma;
    double beta = 0;
    Point grad_beta{};
  };

  virtual ~ExactSolution() = default;
  /// All values at once; the default calls the functions below one by one.
  virtual Values values(const Point& x, double t) const;
  virtual Point u(const Point& x, double t) const = 0;
  /// ∇u: grad[i][j] = ∂u_i/∂x_j.
  virtual std::array<Point, 3> grad_u(const Point& x, double t) const = 0;
  virtual SymTensor sigma(const Point& x, double t) const = 0;
  virtual double beta(const Point& x, double t) const = 0;
  virtual Point grad_beta(const Point& x, double t) const = 0;
};

/// The norms of one error e_n = (exact − discrete) at one time.
struct FieldErrors {
  double u_energy = 0;   // (ℰε(e_u), ε(e_u))^{1/2}
  double u_l2 = 0;       // |e_u|_L2
  double sigma_l2 = 0;   // |e_σ|_L2
  double beta_l2 = 0;    // |e_β|_L2
  double beta_grad = 0;  // |∇e_β|_L2
};

/// Quadrature on a d-simplex exact for polynomials of degree 2m − 1 (collapsed
/// Gauss–Jacobi product rule with m points per direction, m^d points); weights sum
/// to 1. Used for errors against exact solutions: the error of P1/P0 fields against
/// a smooth function needs more than the degree-2 rule of the loads.
std::vector<QuadraturePoint> conical_product_rule(int d, int m);

/// Errors of a discrete state (u, σ, β on `mesh`) against `exact` at time t,
/// integrated with `rule` on every cell.
FieldErrors errors_against_exact(const Mesh& mesh, const std::vector<CellGeometry>& geo,
                                 const Elasticity& elasticity, const State& state, const ExactSolution& exact,
                                 double t, const std::vector<QuadraturePoint>& rule);

}  // namespace vpc
