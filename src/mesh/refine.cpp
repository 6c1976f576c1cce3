#include "mesh/refine.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <iterator>
#include <numeric>
#include <utility>

namespace vpc {

namespace {

/// C(n, k) for k ≤ 3; 0 where n < k.
long long binomial(long long n, int k) {
  if (n < k) return 0;
  switch (k) {
    case 0: return 1;
    case 1: return n;
    case 2: return n * (n - 1) / 2;
    default: return n * (n - 1) * (n - 2) / 6;
  }
}

/// The place of (a[0], ..., a[j−1]), each ≥ 1 and summing to at most s, in the lexicographic order
/// of all such j-tuples (C(s, j) of them): the tuples with a smaller first entry come first.
long long lattice_index(const int* a, int j, long long s) {
  long long index = 0;
  for (int i = 0; i < j; ++i) {
    index += binomial(s, j - i) - binomial(s - a[i] + 1, j - i);
    s -= a[i];
  }
  return index;
}

/// Sorts a[0..k) (k ≤ 4) in place: an insertion sort, which the compiler sees stays within a.
template <class T, std::size_t N>
void sort_first(std::array<T, N>& a, int k) {
  for (int i = 1; i < k; ++i)
    for (int j = i; j > 0 && a[static_cast<std::size_t>(j)] < a[static_cast<std::size_t>(j - 1)]; --j)
      std::swap(a[static_cast<std::size_t>(j)], a[static_cast<std::size_t>(j - 1)]);
}

/// Calls visit(face) for each j-face of the simplex of npc `vertices` (its j + 1 vertices, sorted,
/// −1 beyond them), in a fixed order.
template <class Visit>
void for_each_face(const int* vertices, int npc, int j, Visit visit) {
  for (int mask = 0; mask < (1 << npc); ++mask) {
    if (__builtin_popcount(static_cast<unsigned>(mask)) != j + 1) continue;
    std::array<int, 3> face{-1, -1, -1};
    int k = 0;
    for (int a = 0; a < npc; ++a)
      if (mask >> a & 1) face[static_cast<std::size_t>(k++)] = vertices[a];
    sort_first(face, k);
    visit(face);
  }
}

}  // namespace

MeshRefinement::MeshRefinement(const Mesh& coarse, int levels) : coarse_(coarse), levels_(levels) {
  const int d = coarse.dim();
  require(levels >= 0 && levels <= 20, "internal: {} levels of refinement", levels);
  m_ = 1 << levels;
  const double cells = static_cast<double>(coarse.n_cells()) * std::pow(2.0, d * levels);
  require(cells < 2e9, "the mesh refined {} times would have {:.3g} cells, beyond the numbers of a mesh (2^31)", levels,
          cells);
  children_ = 1LL << (d * levels);
  // The coarse edges (and triangles in 3D): every cell's, sorted and once each.
  const int npc = d + 1;
  for (int j = 1; j < d; ++j) {
    std::vector<std::array<int, 3>>& list = entities_[j];
    for (int c = 0; c < coarse.n_cells(); ++c)
      for_each_face(coarse.cell(c), npc, j, [&](const std::array<int, 3>& face) { list.push_back(face); });
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  // Nodes numbered coarse cell after coarse cell: each cell's nodes not numbered yet (in an earlier
  // cell), its vertices, then the lattice points inside its edges, faces and itself, entity after
  // entity. A cell's children then have nearby numbers, as the coarse cells near in the file's
  // order are near in space: the matrices' rows of a rank stay local, as a generator's.
  for (int j = 0; j <= d; ++j)
    base_[j].assign(j == 0 ? static_cast<std::size_t>(coarse.n_nodes())
                           : (j < d ? entities_[j].size() : static_cast<std::size_t>(coarse.n_cells())), -1);
  long long next = 0;
  auto take = [&](int& base, long long count) {
    if (base >= 0) return;
    require(next + count < 2'000'000'000LL, "the mesh refined {} times would have more than {} nodes, beyond the numbers "
            "of a mesh (2^31)", levels, next + count);
    base = static_cast<int>(next);
    next += count;
  };
  for (int c = 0; c < coarse.n_cells(); ++c) {
    const int* v = coarse.cell(c);
    for (int a = 0; a < npc; ++a) take(base_[0][static_cast<std::size_t>(v[a])], 1);
    for (int j = 1; j < d; ++j)
      for_each_face(v, npc, j, [&](const std::array<int, 3>& face) {
        take(base_[j][static_cast<std::size_t>(entity(j, face))], binomial(m_ - 1, j));
      });
    take(base_[d][static_cast<std::size_t>(c)], binomial(m_ - 1, d));
  }
  for (int& b : base_[0]) take(b, 1);  // a node of no cell (none in a mesh read from a file)
  whole_nodes_ = next;
}

long long MeshRefinement::entity(int j, const std::array<int, 3>& sorted) const {
  const auto& list = entities_[j];
  return std::lower_bound(list.begin(), list.end(), sorted) - list.begin();
}

long long MeshRefinement::node_id(const int* vertices, int n, const Lattice& lambda, int cell) const {
  // The coarse entity the point lies inside: the vertices where its coordinates are not 0, sorted.
  std::array<std::pair<int, int>, 4> on{};
  int j = -1;
  for (int i = 0; i < n; ++i)
    if (lambda[static_cast<std::size_t>(i)] > 0) on[static_cast<std::size_t>(++j)] = {vertices[i], lambda[static_cast<std::size_t>(i)]};
  if (j == 0) return base_[0][static_cast<std::size_t>(on[0].first)];
  sort_first(on, j + 1);
  const long long e = j < coarse_.dim() ? entity(j, {on[0].first, on[1].first, j > 1 ? on[2].first : -1}) : cell;
  int a[3];
  for (int i = 0; i < j; ++i) a[i] = on[static_cast<std::size_t>(i) + 1].second;
  return base_[j][static_cast<std::size_t>(e)] + lattice_index(a, j, m_ - 1);
}

Point MeshRefinement::node_x(const int* vertices, int n, const Lattice& lambda) const {
  // In the order of the coarse nodes' numbers, so that every cell around the point gives it the
  // same coordinates, bit for bit.
  std::array<std::pair<int, int>, 4> on{};
  int k = 0;
  for (int i = 0; i < n; ++i)
    if (lambda[static_cast<std::size_t>(i)] > 0) on[static_cast<std::size_t>(k++)] = {vertices[i], lambda[static_cast<std::size_t>(i)]};
  sort_first(on, k);
  if (k == 1) return coarse_.node(on[0].first);
  Point x{0, 0, 0};
  for (int i = 0; i < k; ++i)
    for (int a = 0; a < 3; ++a) x[a] += on[static_cast<std::size_t>(i)].second * coarse_.node(on[static_cast<std::size_t>(i)].first)[a];
  for (double& v : x) v /= m_;  // a power of 2: exact
  return x;
}

template <class Emit>
void MeshRefinement::children(const int* vertices, int n, Emit emit) const {
  std::array<Lattice, 4> top{};
  for (int i = 0; i < n; ++i) top[static_cast<std::size_t>(i)][static_cast<std::size_t>(i)] = m_;
  std::function<void(const std::array<Lattice, 4>&, int)> split = [&](const std::array<Lattice, 4>& x, int level) {
    if (level == levels_ || n == 1) {
      emit(x);
      return;
    }
    auto mid = [&](int a, int b) {
      Lattice p{};
      for (std::size_t i = 0; i < 4; ++i) p[i] = (x[static_cast<std::size_t>(a)][i] + x[static_cast<std::size_t>(b)][i]) / 2;
      return p;
    };
    const Lattice& x0 = x[0];
    const Lattice& x1 = x[1];
    if (n == 2) {
      const Lattice m01 = mid(0, 1);
      split({x0, m01, {}, {}}, level + 1);
      split({m01, x1, {}, {}}, level + 1);
      return;
    }
    const Lattice& x2 = x[2];
    const Lattice m01 = mid(0, 1), m02 = mid(0, 2), m12 = mid(1, 2);
    if (n == 3) {
      split({x0, m01, m02, {}}, level + 1);
      split({m01, x1, m12, {}}, level + 1);
      split({m02, m12, x2, {}}, level + 1);
      split({m01, m12, m02, {}}, level + 1);
      return;
    }
    const Lattice& x3 = x[3];
    const Lattice m03 = mid(0, 3), m13 = mid(1, 3), m23 = mid(2, 3);
    // Bey (1995): the corners, then the inner octahedron cut along its shortest diagonal (the first
    // of equals) into four, about it: for the diagonal (m_ab, m_ce) the ring m_ac, m_ae, m_be, m_bc.
    split({x0, m01, m02, m03}, level + 1);
    split({m01, x1, m12, m13}, level + 1);
    split({m02, m12, x2, m23}, level + 1);
    split({m03, m13, m23, x3}, level + 1);
    const std::array<std::array<Lattice, 6>, 3> octahedron{{{m01, m23, m02, m03, m13, m12},
                                                            {m02, m13, m01, m03, m23, m12},
                                                            {m03, m12, m01, m02, m23, m13}}};
    std::size_t best = 0;
    double shortest = INFINITY;
    for (std::size_t i = 0; i < 3; ++i) {
      const Point p = node_x(vertices, n, octahedron[i][0]), q = node_x(vertices, n, octahedron[i][1]);
      double length = 0;
      for (int a = 0; a < 3; ++a) length += (p[a] - q[a]) * (p[a] - q[a]);
      if (length < shortest) {
        shortest = length;
        best = i;
      }
    }
    const auto& o = octahedron[best];
    for (std::size_t i = 0; i < 4; ++i) split({o[0], o[1], o[2 + i], o[2 + (i + 1) % 4]}, level + 1);
  };
  split(top, 0);
}

BlockMesh MeshRefinement::refine(const std::vector<int>& cells, const std::vector<int>& layer) const {
  return refine(cells, layer, false);
}

BlockMesh MeshRefinement::refine_all() const {
  std::vector<int> all(static_cast<std::size_t>(coarse_.n_cells()));
  std::iota(all.begin(), all.end(), 0);
  return refine(all, {}, true);
}

std::vector<std::array<int, 2>> MeshRefinement::midpoints() const {
  require(levels_ == 1, "internal: midpoints with {} levels", levels_);
  const Mesh& coarse = coarse_;
  std::vector<std::array<int, 2>> of(static_cast<std::size_t>(whole_nodes_));
  for (int v = 0; v < coarse.n_nodes(); ++v) of[static_cast<std::size_t>(base_[0][static_cast<std::size_t>(v)])] = {v, v};
  if (coarse.dim() == 1) {  // the edges are the cells
    for (int c = 0; c < coarse.n_cells(); ++c)
      of[static_cast<std::size_t>(base_[1][static_cast<std::size_t>(c)])] = {std::min(coarse.cell(c)[0], coarse.cell(c)[1]),
                                                                             std::max(coarse.cell(c)[0], coarse.cell(c)[1])};
  } else {
    for (std::size_t e = 0; e < entities_[1].size(); ++e) of[static_cast<std::size_t>(base_[1][e])] = {entities_[1][e][0], entities_[1][e][1]};
  }
  return of;
}

BlockMesh MeshRefinement::refine(const std::vector<int>& cells, const std::vector<int>& layer, bool every_facet) const {
  const int d = coarse_.dim(), npc = d + 1;
  auto increasing = [](const std::vector<int>& v) {
    return std::is_sorted(v.begin(), v.end()) && std::adjacent_find(v.begin(), v.end()) == v.end();
  };
  require(increasing(cells) && increasing(layer), "internal: coarse cells to refine not increasing");
  const double n_cells = static_cast<double>(cells.size()) * static_cast<double>(children_);
  if (static_cast<int>(cells.size()) == coarse_.n_cells()) {
    require(n_cells <= kMaxGeneratedCells, "the mesh refined {} times would have {:.0f} cells; at most {} are allowed "
            "(fewer levels, a coarser mesh, or more ranks: each refines its own part)", levels_, n_cells, kMaxGeneratedCells);
  } else {
    require(n_cells <= kMaxGeneratedCells, "this rank's part of the mesh refined {} times would have {:.0f} cells (of "
            "{}); at most {} are allowed on a rank (fewer levels, a coarser mesh, or more ranks)", levels_, n_cells,
            whole_cells(), kMaxGeneratedCells);
  }
  std::vector<int> all;
  std::set_union(cells.begin(), cells.end(), layer.begin(), layer.end(), std::back_inserter(all));
  // The nodes of the children of `cells` (numbers in the whole mesh: ints, as the constructor
  // checked): of the layer's children, those that touch one are kept.
  std::vector<int> near;
  if (!layer.empty()) {
    for (const int c : cells)
      children(coarse_.cell(c), npc, [&](const std::array<Lattice, 4>& x) {
        for (int a = 0; a < npc; ++a) near.push_back(static_cast<int>(node_id(coarse_.cell(c), npc, x[static_cast<std::size_t>(a)], c)));
      });
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
  }
  auto kept = [&](bool own, const int* ids, int n) {
    for (int a = 0; a < n && !own; ++a) own = std::binary_search(near.begin(), near.end(), ids[a]);
    return own;
  };
  auto own_cell = [&](int c) { return layer.empty() || std::binary_search(cells.begin(), cells.end(), c); };

  BlockMesh out;
  std::vector<int> cell_nodes;  // the kept children's nodes, by their numbers
  cell_nodes.reserve(static_cast<std::size_t>(n_cells) * static_cast<std::size_t>(npc));
  for (const int c : all) {
    const bool own = own_cell(c);
    long long i = 0;
    children(coarse_.cell(c), npc, [&](const std::array<Lattice, 4>& x) {
      int ids[4];
      for (int a = 0; a < npc; ++a) ids[a] = static_cast<int>(node_id(coarse_.cell(c), npc, x[static_cast<std::size_t>(a)], c));
      if (kept(own, ids, npc)) {
        cell_nodes.insert(cell_nodes.end(), ids, ids + npc);
        out.cell_id.push_back(static_cast<int>(c * children_ + i));
      }
      ++i;
    });
  }
  // The boundary facets' children on the kept cells (those touching the part's nodes where their
  // coarse cell is the layer's: a kept facet's cell is then kept).
  std::vector<char> in(static_cast<std::size_t>(coarse_.n_cells()), 0);
  for (const int c : all) in[static_cast<std::size_t>(c)] = 1;
  std::vector<int> facet_nodes, facet_part;
  for (int f = 0; f < coarse_.n_facets(); ++f) {
    if (!every_facet && !in[static_cast<std::size_t>(coarse_.facet_cell(f))]) continue;
    const bool own = every_facet || own_cell(coarse_.facet_cell(f));
    children(coarse_.facet(f), d, [&](const std::array<Lattice, 4>& x) {
      int ids[3];
      for (int a = 0; a < d; ++a) ids[a] = static_cast<int>(node_id(coarse_.facet(f), d, x[static_cast<std::size_t>(a)], -1));
      if (!kept(own, ids, d)) return;
      facet_nodes.insert(facet_nodes.end(), ids, ids + d);
      facet_part.push_back(coarse_.facet_part(f));
    });
  }
  out.node_id = cell_nodes;
  std::sort(out.node_id.begin(), out.node_id.end());
  out.node_id.erase(std::unique(out.node_id.begin(), out.node_id.end()), out.node_id.end());
  auto local = [&](int id) { return static_cast<int>(std::lower_bound(out.node_id.begin(), out.node_id.end(), id) - out.node_id.begin()); };

  // The nodes' coordinates, from the kept children's lattice points.
  Mesh& mesh = out.mesh;
  mesh = Mesh(d);
  mesh.nodes().resize(out.node_id.size());
  std::vector<char> placed(out.node_id.size(), 0);
  std::size_t next = 0;  // the next kept child
  for (const int c : all) {
    long long i = 0;
    children(coarse_.cell(c), npc, [&](const std::array<Lattice, 4>& x) {
      if (next < out.cell_id.size() && out.cell_id[next] == c * children_ + i) {
        for (int a = 0; a < npc; ++a) {
          int& v = cell_nodes[next * static_cast<std::size_t>(npc) + static_cast<std::size_t>(a)];
          v = local(v);
          if (!placed[static_cast<std::size_t>(v)]) {
            mesh.nodes()[static_cast<std::size_t>(v)] = node_x(coarse_.cell(c), npc, x[static_cast<std::size_t>(a)]);
            placed[static_cast<std::size_t>(v)] = 1;
          }
        }
        ++next;
      }
      ++i;
    });
  }
  for (const std::string& name : coarse_.part_names()) mesh.part_id(name);
  for (const std::string& name : coarse_.region_names()) mesh.region_id(name);
  for (std::size_t k = 0; k < out.cell_id.size(); ++k) {
    mesh.add_cell(&cell_nodes[k * static_cast<std::size_t>(npc)]);
    const int region = coarse_.cell_region(static_cast<int>(out.cell_id[k] / children_));
    if (region >= 0) mesh.set_cell_region(mesh.n_cells() - 1, coarse_.region_names()[static_cast<std::size_t>(region)]);
  }
  cell_nodes = {};
  for (int& v : facet_nodes) v = local(v);
  for (std::size_t f = 0; f < facet_part.size(); ++f) {
    const int part = facet_part[f];
    mesh.add_facet(&facet_nodes[f * static_cast<std::size_t>(d)],
                   part < 0 ? std::string() : coarse_.part_names()[static_cast<std::size_t>(part)]);
  }
  out.whole_nodes = whole_nodes_;
  out.whole_cells = whole_cells();
  return out;
}

Mesh refine_mesh(const Mesh& coarse, int levels) {
  if (levels == 0) return coarse;
  std::vector<int> all(static_cast<std::size_t>(coarse.n_cells()));
  std::iota(all.begin(), all.end(), 0);
  return MeshRefinement(coarse, levels).refine_all().mesh;
}

std::vector<int> split_cells(const Mesh& coarse, int ranks) {
  const int n = coarse.n_cells(), d = coarse.dim();
  require(ranks >= 1 && n >= ranks,
          "the mesh to refine has {} cell{}, fewer than the {} ranks that each refine cells of their own (fewer ranks, "
          "or a finer mesh to refine)", n, n == 1 ? "" : "s", ranks);
  std::vector<Point> at(static_cast<std::size_t>(n));
  for (int c = 0; c < n; ++c) at[static_cast<std::size_t>(c)] = coarse.cell_centroid(c);
  std::vector<int> order(static_cast<std::size_t>(n)), rank(static_cast<std::size_t>(n), 0);
  std::iota(order.begin(), order.end(), 0);
  // Every side keeps at least as many cells as ranks: k − first ≥ left and last − k ≥ r1 − r0 − left.
  std::function<void(std::size_t, std::size_t, int, int)> split = [&](std::size_t first, std::size_t last, int r0, int r1) {
    if (r1 - r0 == 1) {
      for (std::size_t i = first; i < last; ++i) rank[static_cast<std::size_t>(order[i])] = r0;
      return;
    }
    const int left = (r1 - r0) / 2;
    const std::size_t k = first + (last - first) * static_cast<std::size_t>(left) / static_cast<std::size_t>(r1 - r0);
    int axis = 0;
    double widest = -1;
    for (int a = 0; a < d; ++a) {
      double lo = at[static_cast<std::size_t>(order[first])][a], hi = lo;
      for (std::size_t i = first; i < last; ++i) {
        lo = std::min(lo, at[static_cast<std::size_t>(order[i])][a]);
        hi = std::max(hi, at[static_cast<std::size_t>(order[i])][a]);
      }
      if (hi - lo > widest) {
        widest = hi - lo;
        axis = a;
      }
    }
    // Ties by the cell's number: the same cut on every rank.
    std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(first), order.begin() + static_cast<std::ptrdiff_t>(k),
                     order.begin() + static_cast<std::ptrdiff_t>(last), [&](int x, int y) {
                       const double a = at[static_cast<std::size_t>(x)][axis], b = at[static_cast<std::size_t>(y)][axis];
                       return a < b || (a == b && x < y);
                     });
    split(first, k, r0, r0 + left);
    split(k, last, r0 + left, r1);
  };
  split(0, static_cast<std::size_t>(n), 0, ranks);
  return rank;
}

std::vector<int> layer_cells(const Mesh& coarse, const std::vector<int>& cell_rank, int rank) {
  const int npc = coarse.nodes_per_cell();
  std::vector<char> near(static_cast<std::size_t>(coarse.n_nodes()), 0);
  for (int c = 0; c < coarse.n_cells(); ++c)
    if (cell_rank[static_cast<std::size_t>(c)] == rank)
      for (int a = 0; a < npc; ++a) near[static_cast<std::size_t>(coarse.cell(c)[a])] = 1;
  std::vector<int> cells;
  for (int c = 0; c < coarse.n_cells(); ++c) {
    if (cell_rank[static_cast<std::size_t>(c)] == rank) continue;
    for (int a = 0; a < npc; ++a)
      if (near[static_cast<std::size_t>(coarse.cell(c)[a])]) {
        cells.push_back(c);
        break;
      }
  }
  return cells;
}

}  // namespace vpc
