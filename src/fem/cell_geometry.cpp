#include "fem/cell_geometry.hpp"

#include "core/error.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace vpc {

CellGeometry cell_geometry(int dim, const Point* x) {
  // J = [x1 − x0, ..., xd − x0]; ∇λ_a = J^{-T} e_a for a ≥ 1, ∇λ_0 = −Σ ∇λ_a.
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  for (int a = 1; a <= dim; ++a)
    for (int i = 0; i < dim; ++i) J(i, a - 1) = x[a][i] - x[0][i];
  CellGeometry g;
  g.volume = simplex_measure(dim, x);
  if (!(g.volume > 0) || !std::isfinite(g.volume)) return g;
  const Eigen::Matrix3d JinvT = J.inverse().transpose();
  for (int i = 0; i < dim; ++i) {
    double s = 0;
    for (int a = 1; a <= dim; ++a) {
      g.grad[a][i] = JinvT(i, a - 1);
      s += g.grad[a][i];
    }
    g.grad[0][i] = -s;
  }
  return g;
}

std::vector<CellGeometry> compute_geometry(const Mesh& mesh) {
  const int d = mesh.dim();
  std::vector<CellGeometry> geo(mesh.n_cells());
  double max_volume = 0;
  for (int c = 0; c < mesh.n_cells(); ++c) {
    Point x[4];
    for (int a = 0; a <= d; ++a) x[a] = mesh.node(mesh.cell(c)[a]);
    geo[c] = cell_geometry(d, x);
    max_volume = std::max(max_volume, geo[c].volume);
  }
  for (int c = 0; c < mesh.n_cells(); ++c)
    require(geo[c].volume > 1e-14 * max_volume, "mesh: cell {} is degenerate (measure {:.3e})", c,
            geo[c].volume);
  return geo;
}

}  // namespace vpc
