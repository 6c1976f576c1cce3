#include "mesh/generators.hpp"

#include "core/error.hpp"

#include <cmath>

namespace vpc {

namespace {

/// Tags the sides of an axis-aligned box-shaped mesh by facet centroid.
void tag_sides(Mesh& m, const Point& lo, const Point& hi) {
  // 2D: y is bottom/top; 3D: y is front/back and z is bottom/top.
  static const char* names2[3][2] = {{"left", "right"}, {"bottom", "top"}, {"", ""}};
  static const char* names3[3][2] = {{"left", "right"}, {"front", "back"}, {"bottom", "top"}};
  const auto& names = m.dim() == 3 ? names3 : names2;
  for (int a = 0; a < m.dim(); ++a) {
    const double tol = 1e-9 * (hi[a] - lo[a]);
    m.tag_facets(names[a][0], [&](const Point& p) { return std::abs(p[a] - lo[a]) < tol; });
    m.tag_facets(names[a][1], [&](const Point& p) { return std::abs(p[a] - hi[a]) < tol; });
  }
}

/// Checks the box and the mesh size before anything is allocated: `per_box`
/// simplices per square or cube.
void check_box(const Point& lo, const Point& hi, int dim, const int* n, int per_box) {
  double cells = per_box;
  for (int a = 0; a < dim; ++a) {
    require(n[a] >= 1, "mesh generator: number of cells along axis {} must be >= 1 (got {})", a, n[a]);
    require(hi[a] > lo[a], "mesh generator: upper corner must exceed lower corner along axis {}", a);
    cells *= n[a];
  }
  check_mesh_size(cells);
}

}  // namespace

void check_mesh_size(double n_cells) {
  require(n_cells <= kMaxGeneratedCells,
          "the mesh would have {:.0f} cells; at most {} are allowed (use fewer cells per edge)", n_cells,
          kMaxGeneratedCells);
}

Mesh make_interval(double x0, double x1, int n) {
  const int ns[1] = {n};
  check_box({x0, 0, 0}, {x1, 0, 0}, 1, ns, 1);
  Mesh m(1);
  for (int i = 0; i <= n; ++i) m.add_node({x0 + (x1 - x0) * i / n, 0, 0});
  for (int i = 0; i < n; ++i) {
    const int c[2] = {i, i + 1};
    m.add_cell(c);
  }
  m.build_boundary();
  tag_sides(m, {x0, 0, 0}, {x1, 0, 0});
  return m;
}

Mesh make_rectangle(Point lo, Point hi, int nx, int ny) {
  const int ns[2] = {nx, ny};
  check_box(lo, hi, 2, ns, 2);
  Mesh m(2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.add_node({lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny, 0});
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int t1[3] = {id(i, j), id(i + 1, j), id(i + 1, j + 1)};
      const int t2[3] = {id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      m.add_cell(t1);
      m.add_cell(t2);
    }
  m.build_boundary();
  tag_sides(m, lo, hi);
  return m;
}

Mesh make_box(Point lo, Point hi, int nx, int ny, int nz) {
  const int ns[3] = {nx, ny, nz};
  check_box(lo, hi, 3, ns, 6);
  Mesh m(3);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.add_node({lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny,
                    lo[2] + (hi[2] - lo[2]) * k / nz});
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  // Kuhn subdivision: one tetrahedron per path 000 -> 111 along the axes in the
  // order of a permutation; identical in every cube, hence conforming.
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : perms) {
          int off[3] = {0, 0, 0};
          int t[4];
          t[0] = id(i, j, k);
          for (int s = 0; s < 3; ++s) {
            off[p[s]] = 1;
            t[s + 1] = id(i + off[0], j + off[1], k + off[2]);
          }
          m.add_cell(t);
        }
  m.build_boundary();
  tag_sides(m, lo, hi);
  return m;
}

}  // namespace vpc
