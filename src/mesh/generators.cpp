#include "mesh/generators.hpp"

#include "core/error.hpp"

#include <algorithm>
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

/// "crossed" cubes: a node at the centre of every cube and of every face; each
/// face is cut into 4 triangles about its centre and each triangle joined to the
/// cube's centre (24 tetrahedra per cube, symmetric under every mirror of the cube).
/// `id(i, j, k)` numbers the grid nodes; `at(x, y, z)` places a point in cell units.
template <class Id, class At>
void add_crossed_cubes(Mesh& m, const int* n, const Id& id, const At& at) {
  const int centre0 = m.n_nodes();
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) m.add_node(at(i + 0.5, j + 0.5, k + 0.5));
  // Face centres, by normal axis a: the face at index c[a] of the cube c (0..n[a]).
  int face0[3];
  for (int a = 0; a < 3; ++a) {
    face0[a] = m.n_nodes();
    int e[3] = {n[0], n[1], n[2]};
    ++e[a];
    for (int k = 0; k < e[2]; ++k)
      for (int j = 0; j < e[1]; ++j)
        for (int i = 0; i < e[0]; ++i) {
          double x[3] = {i + 0.5, j + 0.5, k + 0.5};
          x[a] -= 0.5;
          m.add_node(at(x[0], x[1], x[2]));
        }
  }
  auto face_id = [&](int a, int i, int j, int k) {
    int e[3] = {n[0], n[1], n[2]};
    ++e[a];
    return face0[a] + (k * e[1] + j) * e[0] + i;
  };
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const int c = centre0 + (k * n[1] + j) * n[0] + i;
        for (int a = 0; a < 3; ++a)
          for (int side = 0; side < 2; ++side) {
            int o[3] = {i, j, k};
            o[a] += side;
            const int f = face_id(a, o[0], o[1], o[2]);
            const int b = (a + 1) % 3, e = (a + 2) % 3;
            int ring[4];
            static const int cycle[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int q = 0; q < 4; ++q) {
              int v[3] = {o[0], o[1], o[2]};
              v[b] += cycle[q][0];
              v[e] += cycle[q][1];
              ring[q] = id(v[0], v[1], v[2]);
            }
            for (int q = 0; q < 4; ++q) {
              const int t[4] = {c, f, ring[q], ring[(q + 1) % 4]};
              m.add_cell(t);
            }
          }
      }
}

}  // namespace

const std::vector<std::string>& diagonal_names() {
  static const std::vector<std::string> names = {"right", "left", "alternate", "crossed"};
  return names;
}

Diagonal diagonal_from_name(const std::string& name) {
  const auto& names = diagonal_names();
  const auto it = std::find(names.begin(), names.end(), name);
  require(it != names.end(), "unknown diagonal '{}'; expected one of: right, left, alternate, crossed", name);
  return static_cast<Diagonal>(it - names.begin());
}

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

Mesh make_rectangle(Point lo, Point hi, int nx, int ny, Diagonal diagonal) {
  const int ns[2] = {nx, ny};
  const bool crossed = diagonal == Diagonal::crossed;
  check_box(lo, hi, 2, ns, crossed ? 4 : 2);
  Mesh m(2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.add_node({lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny, 0});
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  if (crossed) {  // a centre node per square, numbered after the grid
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.add_node({lo[0] + (hi[0] - lo[0]) * (i + 0.5) / nx, lo[1] + (hi[1] - lo[1]) * (j + 0.5) / ny, 0});
  }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (crossed) {
        const int c = (nx + 1) * (ny + 1) + j * nx + i;
        const int ring[4] = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
        for (int q = 0; q < 4; ++q) {
          const int t[3] = {c, ring[q], ring[(q + 1) % 4]};
          m.add_cell(t);
        }
        continue;
      }
      // "right": the diagonal (i, j)–(i+1, j+1); "left": (i+1, j)–(i, j+1).
      const bool left = diagonal == Diagonal::left || (diagonal == Diagonal::alternate && (i + j) % 2 == 1);
      if (!left) {
        const int t1[3] = {id(i, j), id(i + 1, j), id(i + 1, j + 1)};
        const int t2[3] = {id(i, j), id(i + 1, j + 1), id(i, j + 1)};
        m.add_cell(t1);
        m.add_cell(t2);
      } else {
        const int t1[3] = {id(i, j), id(i + 1, j), id(i, j + 1)};
        const int t2[3] = {id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
        m.add_cell(t1);
        m.add_cell(t2);
      }
    }
  m.build_boundary();
  tag_sides(m, lo, hi);
  return m;
}

Mesh make_box(Point lo, Point hi, int nx, int ny, int nz, Diagonal diagonal) {
  const int ns[3] = {nx, ny, nz};
  const bool crossed = diagonal == Diagonal::crossed;
  check_box(lo, hi, 3, ns, crossed ? 24 : 6);
  Mesh m(3);
  auto at = [&](double i, double j, double k) {
    return Point{lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny, lo[2] + (hi[2] - lo[2]) * k / nz};
  };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.add_node(at(i, j, k));
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  if (crossed) {
    add_crossed_cubes(m, ns, id, at);
  } else {
    // Kuhn subdivision: one tetrahedron per path 000 -> 111 along the axes in the
    // order of a permutation; identical in every cube, hence conforming. "left"
    // mirrors every cube in x; "alternate" mirrors a cube along each axis whose
    // index is odd: neighbours then are mirror images across their shared face,
    // whose triangulation both see alike (conforming), and the mesh is symmetric
    // about the mid-plane of every axis with an even number of cells.
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const int cube[3] = {i, j, k};
          int mirror[3] = {0, 0, 0};
          if (diagonal == Diagonal::left) mirror[0] = 1;
          if (diagonal == Diagonal::alternate)
            for (int a = 0; a < 3; ++a) mirror[a] = cube[a] % 2;
          for (const auto& p : perms) {
            int off[3] = {0, 0, 0};
            int t[4];
            t[0] = id(i + mirror[0], j + mirror[1], k + mirror[2]);
            for (int s = 0; s < 3; ++s) {
              off[p[s]] = 1;
              t[s + 1] = id(i + (off[0] ^ mirror[0]), j + (off[1] ^ mirror[1]), k + (off[2] ^ mirror[2]));
            }
            m.add_cell(t);
          }
        }
  }
  m.build_boundary();
  tag_sides(m, lo, hi);
  return m;
}

}  // namespace vpc
