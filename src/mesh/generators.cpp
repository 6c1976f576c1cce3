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

/// The boundary facets and their sides: those on the box's sides, which are the whole mesh's
/// facets used by one cell (on a block, the faces where it is cut are not boundary; and only
/// the sides' facets are counted, not every cell's).
void finish_boundary(Mesh& m, const Point& lo, const Point& hi) {
  m.build_boundary([&](const Point& p) {
    for (int a = 0; a < m.dim(); ++a) {
      const double tol = 1e-9 * (hi[a] - lo[a]);
      if (std::abs(p[a] - lo[a]) < tol || std::abs(p[a] - hi[a]) < tol) return true;
    }
    return false;
  });
  tag_sides(m, lo, hi);
}

/// Checks the box, the block and the mesh size before anything is allocated: `per_box`
/// simplices per square or cube; the block's count is the one limited (check_mesh_size), and
/// the whole mesh's numbers of cells and nodes (at most 5 per cube) must fit an int.
void check_box(const Point& lo, const Point& hi, int dim, const int* n, int per_box, const GridBlock& block) {
  double cells = per_box, all_cells = per_box, whole = per_box;
  for (int a = 0; a < dim; ++a) {
    require(n[a] >= 1, "mesh generator: number of cells along axis {} must be >= 1 (got {})", a, n[a]);
    require(hi[a] > lo[a], "mesh generator: upper corner must exceed lower corner along axis {}", a);
    require(block.lo[a] >= 0 && block.lo[a] < block.hi[a] && block.hi[a] <= n[a],
            "internal: mesh generator: block [{}, {}) along axis {} is not within the {} cells", block.lo[a],
            block.hi[a], a, n[a]);
    cells *= block.hi[a] - block.lo[a];
    all_cells *= n[a];
    whole *= n[a] + 1;
  }
  if (cells == all_cells) check_mesh_size(cells);
  require(cells <= kMaxGeneratedCells,
          "this rank's block of the mesh would have {:.0f} cells (of {:.0f}); at most {} are allowed on a rank (use "
          "fewer cells per edge, or more ranks)", cells, all_cells, kMaxGeneratedCells);
  require(whole < 2e9, "the mesh would have about {:.3g} cells or nodes, beyond the numbers of a mesh (2^31)", whole);
}

/// A block mesh being built: its nodes and cells, and with `ids` their numbers in the whole mesh.
struct Builder {
  BlockMesh out;
  bool ids = false;
  Builder(int dim, bool with_ids) : ids(with_ids) { out.mesh = Mesh(dim); }
  void node(const Point& x, long long id) {
    out.mesh.add_node(x);
    if (ids) out.node_id.push_back(static_cast<int>(id));
  }
  void cell(const int* v, long long id) {
    out.mesh.add_cell(v);
    if (ids) out.cell_id.push_back(static_cast<int>(id));
  }
};

/// The grid's nodes (i, j, k) of a block, numbered x fastest in the block (`local`) and in the
/// whole grid (`global`); unused axes have n = lo = hi = 0.
struct GridNodes {
  std::array<int, 3> n;
  GridBlock b;
  int width(int a) const { return b.hi[a] - b.lo[a] + 1; }
  int count() const { return width(0) * width(1) * width(2); }
  long long whole_count() const { return static_cast<long long>(n[0] + 1) * (n[1] + 1) * (n[2] + 1); }
  int local(int i, int j, int k) const { return ((k - b.lo[2]) * width(1) + (j - b.lo[1])) * width(0) + (i - b.lo[0]); }
  long long global(int i, int j, int k) const {
    return (static_cast<long long>(k) * (n[1] + 1) + j) * (n[0] + 1) + i;
  }
  /// Cells (squares, cubes) numbered x fastest, in the block and in the whole grid.
  int local_cell(int i, int j, int k) const {
    return ((k - b.lo[2]) * (b.hi[1] - b.lo[1]) + (j - b.lo[1])) * (b.hi[0] - b.lo[0]) + (i - b.lo[0]);
  }
  long long global_cell(int i, int j, int k) const { return (static_cast<long long>(k) * n[1] + j) * n[0] + i; }
};

/// "crossed" cubes: a node at the centre of every cube and of every face; each
/// face is cut into 4 triangles about its centre and each triangle joined to the
/// cube's centre (24 tetrahedra per cube, symmetric under every mirror of the cube).
/// `at(x, y, z)` places a point in cell units. The centres are numbered after the grid's
/// nodes (cube by cube), then the faces' (by normal axis, then x fastest), in the block
/// as in the whole mesh.
template <class At>
void add_crossed_cubes(Builder& m, const GridNodes& g, const At& at) {
  const GridBlock& b = g.b;
  const int centre0 = g.count();
  const long long whole_centre0 = g.whole_count();
  for (int k = b.lo[2]; k < b.hi[2]; ++k)
    for (int j = b.lo[1]; j < b.hi[1]; ++j)
      for (int i = b.lo[0]; i < b.hi[0]; ++i) m.node(at(i + 0.5, j + 0.5, k + 0.5), whole_centre0 + g.global_cell(i, j, k));
  // Face centres, by normal axis a: the face at index c[a] of the cube c (0..n[a]).
  int face0[3];
  long long whole_face0[3];
  int local_faces = centre0 + static_cast<int>(b.cells());
  long long whole_faces = whole_centre0 + static_cast<long long>(g.n[0]) * g.n[1] * g.n[2];
  for (int a = 0; a < 3; ++a) {
    face0[a] = local_faces;
    whole_face0[a] = whole_faces;
    std::array<int, 3> e = g.n, w{b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]};
    ++e[a];
    ++w[a];
    local_faces += w[0] * w[1] * w[2];
    whole_faces += static_cast<long long>(e[0]) * e[1] * e[2];
    for (int k = b.lo[2]; k < b.lo[2] + w[2]; ++k)
      for (int j = b.lo[1]; j < b.lo[1] + w[1]; ++j)
        for (int i = b.lo[0]; i < b.lo[0] + w[0]; ++i) {
          double x[3] = {i + 0.5, j + 0.5, k + 0.5};
          x[a] -= 0.5;
          m.node(at(x[0], x[1], x[2]), whole_face0[a] + (static_cast<long long>(k) * e[1] + j) * e[0] + i);
        }
  }
  auto face_id = [&](int a, int i, int j, int k) {
    std::array<int, 3> w{b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]};
    ++w[a];
    return face0[a] + ((k - b.lo[2]) * w[1] + (j - b.lo[1])) * w[0] + (i - b.lo[0]);
  };
  for (int k = b.lo[2]; k < b.hi[2]; ++k)
    for (int j = b.lo[1]; j < b.hi[1]; ++j)
      for (int i = b.lo[0]; i < b.hi[0]; ++i) {
        const int c = centre0 + g.local_cell(i, j, k);
        const long long first = 24 * g.global_cell(i, j, k);
        for (int a = 0; a < 3; ++a)
          for (int side = 0; side < 2; ++side) {
            int o[3] = {i, j, k};
            o[a] += side;
            const int f = face_id(a, o[0], o[1], o[2]);
            const int bb = (a + 1) % 3, e = (a + 2) % 3;
            int ring[4];
            static const int cycle[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int q = 0; q < 4; ++q) {
              int v[3] = {o[0], o[1], o[2]};
              v[bb] += cycle[q][0];
              v[e] += cycle[q][1];
              ring[q] = g.local(v[0], v[1], v[2]);
            }
            for (int q = 0; q < 4; ++q) {
              const int t[4] = {c, f, ring[q], ring[(q + 1) % 4]};
              m.cell(t, first + (a * 2 + side) * 4 + q);
            }
          }
      }
}

/// Cuts `b` into `parts` blocks, appended to `out` (split_grid).
void bisect(const GridBlock& b, int dim, int parts, std::vector<GridBlock>& out) {
  if (parts == 1) {
    out.push_back(b);
    return;
  }
  int a = 0;
  for (int k = 1; k < dim; ++k)
    if (b.hi[k] - b.lo[k] > b.hi[a] - b.lo[a]) a = k;
  const int first = parts / 2, len = b.hi[a] - b.lo[a];
  const int cut = b.lo[a] + std::clamp(static_cast<int>(std::lround(static_cast<double>(len) * first / parts)), 1,
                                       std::max(len - 1, 1));
  GridBlock left = b, right = b;
  left.hi[a] = cut;
  right.lo[a] = cut;
  require(len >= 2 && left.cells() >= first && right.cells() >= parts - first,
          "the generated mesh's grid of {} cells cannot be split into {} parts with a cell each (use more cells "
          "per edge or fewer processes)", b.cells(), parts);
  bisect(left, dim, first, out);
  bisect(right, dim, parts - first, out);
}

}  // namespace

long long GridBlock::cells() const {
  long long c = 1;
  for (int a = 0; a < 3; ++a)
    if (hi[a] > lo[a]) c *= hi[a] - lo[a];
  return c;
}

GridBlock whole_grid(const std::array<int, 3>& n, int dim) {
  GridBlock b;
  for (int a = 0; a < dim; ++a) b.hi[a] = n[a];
  return b;
}

std::vector<GridBlock> split_grid(const GridBlock& grid, int dim, int parts) {
  require(parts >= 1, "internal: split_grid into {} parts", parts);
  std::vector<GridBlock> out;
  bisect(grid, dim, parts, out);
  return out;
}

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

namespace {

BlockMesh interval_block(double x0, double x1, int n, const GridBlock& b, bool ids) {
  const int ns[1] = {n};
  check_box({x0, 0, 0}, {x1, 0, 0}, 1, ns, 1, b);
  Builder m(1, ids);
  for (int i = b.lo[0]; i <= b.hi[0]; ++i) m.node({x0 + (x1 - x0) * i / n, 0, 0}, i);
  for (int i = b.lo[0]; i < b.hi[0]; ++i) {
    const int c[2] = {i - b.lo[0], i + 1 - b.lo[0]};
    m.cell(c, i);
  }
  finish_boundary(m.out.mesh, {x0, 0, 0}, {x1, 0, 0});
  m.out.whole_nodes = n + 1;
  m.out.whole_cells = n;
  return std::move(m.out);
}

BlockMesh rectangle_block(Point lo, Point hi, int nx, int ny, Diagonal diagonal, const GridBlock& b, bool ids) {
  const int ns[2] = {nx, ny};
  const bool crossed = diagonal == Diagonal::crossed;
  check_box(lo, hi, 2, ns, crossed ? 4 : 2, b);
  const GridNodes g{{nx, ny, 0}, b};
  Builder m(2, ids);
  for (int j = b.lo[1]; j <= b.hi[1]; ++j)
    for (int i = b.lo[0]; i <= b.hi[0]; ++i)
      m.node({lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny, 0}, g.global(i, j, 0));
  auto id = [&](int i, int j) { return g.local(i, j, 0); };
  if (crossed) {  // a centre node per square, numbered after the grid
    for (int j = b.lo[1]; j < b.hi[1]; ++j)
      for (int i = b.lo[0]; i < b.hi[0]; ++i)
        m.node({lo[0] + (hi[0] - lo[0]) * (i + 0.5) / nx, lo[1] + (hi[1] - lo[1]) * (j + 0.5) / ny, 0},
               g.whole_count() + g.global_cell(i, j, 0));
  }
  for (int j = b.lo[1]; j < b.hi[1]; ++j)
    for (int i = b.lo[0]; i < b.hi[0]; ++i) {
      const long long square = g.global_cell(i, j, 0);
      if (crossed) {
        const int c = g.count() + g.local_cell(i, j, 0);
        const int ring[4] = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
        for (int q = 0; q < 4; ++q) {
          const int t[3] = {c, ring[q], ring[(q + 1) % 4]};
          m.cell(t, 4 * square + q);
        }
        continue;
      }
      // "right": the diagonal (i, j)–(i+1, j+1); "left": (i+1, j)–(i, j+1).
      const bool left = diagonal == Diagonal::left || (diagonal == Diagonal::alternate && (i + j) % 2 == 1);
      if (!left) {
        const int t1[3] = {id(i, j), id(i + 1, j), id(i + 1, j + 1)};
        const int t2[3] = {id(i, j), id(i + 1, j + 1), id(i, j + 1)};
        m.cell(t1, 2 * square);
        m.cell(t2, 2 * square + 1);
      } else {
        const int t1[3] = {id(i, j), id(i + 1, j), id(i, j + 1)};
        const int t2[3] = {id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
        m.cell(t1, 2 * square);
        m.cell(t2, 2 * square + 1);
      }
    }
  finish_boundary(m.out.mesh, lo, hi);
  const long long squares = static_cast<long long>(nx) * ny;
  m.out.whole_nodes = g.whole_count() + (crossed ? squares : 0);
  m.out.whole_cells = (crossed ? 4 : 2) * squares;
  return std::move(m.out);
}

BlockMesh box_block(Point lo, Point hi, int nx, int ny, int nz, Diagonal diagonal, const GridBlock& b, bool ids) {
  const int ns[3] = {nx, ny, nz};
  const bool crossed = diagonal == Diagonal::crossed;
  check_box(lo, hi, 3, ns, crossed ? 24 : 6, b);
  const GridNodes g{{nx, ny, nz}, b};
  Builder m(3, ids);
  auto at = [&](double i, double j, double k) {
    return Point{lo[0] + (hi[0] - lo[0]) * i / nx, lo[1] + (hi[1] - lo[1]) * j / ny, lo[2] + (hi[2] - lo[2]) * k / nz};
  };
  for (int k = b.lo[2]; k <= b.hi[2]; ++k)
    for (int j = b.lo[1]; j <= b.hi[1]; ++j)
      for (int i = b.lo[0]; i <= b.hi[0]; ++i) m.node(at(i, j, k), g.global(i, j, k));
  if (crossed) {
    add_crossed_cubes(m, g, at);
  } else {
    // Kuhn subdivision: one tetrahedron per path 000 -> 111 along the axes in the
    // order of a permutation; identical in every cube, hence conforming. "left"
    // mirrors every cube in x; "alternate" mirrors a cube along each axis whose
    // index is odd: neighbours then are mirror images across their shared face,
    // whose triangulation both see alike (conforming), and the mesh is symmetric
    // about the mid-plane of every axis with an even number of cells.
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int k = b.lo[2]; k < b.hi[2]; ++k)
      for (int j = b.lo[1]; j < b.hi[1]; ++j)
        for (int i = b.lo[0]; i < b.hi[0]; ++i) {
          const int cube[3] = {i, j, k};
          int mirror[3] = {0, 0, 0};
          if (diagonal == Diagonal::left) mirror[0] = 1;
          if (diagonal == Diagonal::alternate)
            for (int a = 0; a < 3; ++a) mirror[a] = cube[a] % 2;
          const long long first = 6 * g.global_cell(i, j, k);
          for (int q = 0; q < 6; ++q) {
            const int* p = perms[q];
            int off[3] = {0, 0, 0};
            int t[4];
            t[0] = g.local(i + mirror[0], j + mirror[1], k + mirror[2]);
            for (int s = 0; s < 3; ++s) {
              off[p[s]] = 1;
              t[s + 1] = g.local(i + (off[0] ^ mirror[0]), j + (off[1] ^ mirror[1]), k + (off[2] ^ mirror[2]));
            }
            m.cell(t, first + q);
          }
        }
  }
  finish_boundary(m.out.mesh, lo, hi);
  const long long cubes = static_cast<long long>(nx) * ny * nz;
  const long long faces = static_cast<long long>(nx + 1) * ny * nz + nx * (ny + 1LL) * nz + nx * ny * (nz + 1LL);
  m.out.whole_nodes = g.whole_count() + (crossed ? cubes + faces : 0);
  m.out.whole_cells = (crossed ? 24 : 6) * cubes;
  return std::move(m.out);
}

}  // namespace

Mesh make_interval(double x0, double x1, int n) {
  return interval_block(x0, x1, n, whole_grid({n, 0, 0}, 1), false).mesh;
}

Mesh make_rectangle(Point lo, Point hi, int nx, int ny, Diagonal diagonal) {
  return rectangle_block(lo, hi, nx, ny, diagonal, whole_grid({nx, ny, 0}, 2), false).mesh;
}

Mesh make_box(Point lo, Point hi, int nx, int ny, int nz, Diagonal diagonal) {
  return box_block(lo, hi, nx, ny, nz, diagonal, whole_grid({nx, ny, nz}, 3), false).mesh;
}

Mesh generate(int dim, const Point& lo, const Point& hi, const std::array<int, 3>& n, Diagonal diagonal) {
  if (dim == 1) return make_interval(lo[0], hi[0], n[0]);
  if (dim == 2) return make_rectangle({lo[0], lo[1], 0}, {hi[0], hi[1], 0}, n[0], n[1], diagonal);
  return make_box(lo, hi, n[0], n[1], n[2], diagonal);
}

BlockMesh generate_block(int dim, const Point& lo, const Point& hi, const std::array<int, 3>& n, Diagonal diagonal,
                         const GridBlock& block) {
  if (dim == 1) return make_interval_block(lo[0], hi[0], n[0], block);
  if (dim == 2) return make_rectangle_block({lo[0], lo[1], 0}, {hi[0], hi[1], 0}, n[0], n[1], diagonal, block);
  return make_box_block(lo, hi, n[0], n[1], n[2], diagonal, block);
}

BlockMesh make_interval_block(double x0, double x1, int n, const GridBlock& block) {
  return interval_block(x0, x1, n, block, true);
}

BlockMesh make_rectangle_block(Point lo, Point hi, int nx, int ny, Diagonal diagonal, const GridBlock& block) {
  return rectangle_block(lo, hi, nx, ny, diagonal, block, true);
}

BlockMesh make_box_block(Point lo, Point hi, int nx, int ny, int nz, Diagonal diagonal, const GridBlock& block) {
  return box_block(lo, hi, nx, ny, nz, diagonal, block, true);
}

}  // namespace vpc
