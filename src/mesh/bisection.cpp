#include "mesh/bisection.hpp"

#include "core/error.hpp"
#include "mesh/facet_key.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <unordered_set>

namespace vpc {

namespace {

double distance2(const Point& p, const Point& q) {
  double s = 0;
  for (int j = 0; j < 3; ++j) s += (p[j] - q[j]) * (p[j] - q[j]);
  return s;
}

/// Twice the signed area of the triangle (p, q, r) in the xy plane.
double orientation(const Point& p, const Point& q, const Point& r) {
  return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
}

/// Six times the signed volume of the tetrahedron (p, q, r, s).
double signed_volume6(const Point& p, const Point& q, const Point& r, const Point& s) {
  const double a[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, b[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]},
               c[3] = {s[0] - p[0], s[1] - p[1], s[2] - p[2]};
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

}  // namespace

std::uint64_t BisectionForest::key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return lo << 32 | hi;
}

BisectionForest::BisectionForest(const Mesh& coarse)
    : coarse_(coarse), dim_(coarse.dim()), x_(coarse.nodes()), alive_(static_cast<std::size_t>(coarse.n_nodes()), 1) {
  require(dim_ == 2 || dim_ == 3,
          "newest-vertex bisection: a triangle or tetrahedron mesh is needed (d = 2 or 3), got d = {}", dim_);
  cells_.reserve(static_cast<std::size_t>(coarse.n_cells()));
  std::unordered_map<FacetKey, int, FacetKeyHash> boundary;  // 3D: the coarse boundary facets
  if (dim_ == 3)
    for (int f = 0; f < coarse.n_facets(); ++f) boundary.emplace(facet_key(coarse.facet(f), 3), f);
  for (int c = 0; c < coarse.n_cells(); ++c) {
    const int* v = coarse.cell(c);
    Cell cell;
    cell.root = c;
    if (dim_ == 3) {
      // Maubach's order from the global node numbers (increasing), generation 0: see the header.
      std::copy_n(v, 4, cell.v.begin());
      std::sort(cell.v.begin(), cell.v.end());
      for (int k = 0; k < 4; ++k) {
        int f[3];
        cell_facet(cell.v.data(), 4, k, f);
        if (const auto it = boundary.find(facet_key(f, 3)); it != boundary.end()) cell.facet[static_cast<std::size_t>(k)] = it->second;
      }
      cells_.push_back(cell);
      add_edges(c);
      continue;
    }
    // The refinement edge: the longest, ties by the least (smaller, larger) pair of node numbers.
    int best = 0;
    auto edge_rank = [&](int e) {
      const int a = v[e], b = v[(e + 1) % 3];
      return std::make_tuple(-distance2(x_[static_cast<std::size_t>(a)], x_[static_cast<std::size_t>(b)]),
                             std::min(a, b), std::max(a, b));
    };
    for (int e = 1; e < 3; ++e)
      if (edge_rank(e) < edge_rank(best)) best = e;
    cell.v = {v[best], v[(best + 1) % 3], v[(best + 2) % 3], -1};
    const auto& p = cell.v;
    if (orientation(x_[static_cast<std::size_t>(p[0])], x_[static_cast<std::size_t>(p[1])],
                    x_[static_cast<std::size_t>(p[2])]) < 0)
      std::swap(cell.v[0], cell.v[1]);  // counterclockwise, the same refinement edge and peak
    cells_.push_back(cell);
    add_edges(c);
  }
}

std::array<int, 2> BisectionForest::refinement_edge(int c) const {
  const auto& v = cells_[static_cast<std::size_t>(c)].v;
  return dim_ == 2 ? std::array<int, 2>{v[0], v[1]} : std::array<int, 2>{v[0], v[3]};
}

namespace {

/// The vertex pairs of a simplex's edges (the first 3 of a triangle's: (0,1), (1,2), (2,0)).
constexpr int kEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

}  // namespace

void BisectionForest::add_edges(int c) {
  const auto& v = cells_[static_cast<std::size_t>(c)].v;
  for (int e = 0; e < (dim_ == 2 ? 3 : 6); ++e) {
    std::vector<int>& around = edge_cells_[key(v[kEdge[e][0]], v[kEdge[e][1]])];
    require(dim_ == 3 || around.size() < 2, "newest-vertex bisection: an edge of three cells (the mesh is not a manifold)");
    around.push_back(c);
  }
}

void BisectionForest::remove_edges(int c) {
  const auto& v = cells_[static_cast<std::size_t>(c)].v;
  for (int e = 0; e < (dim_ == 2 ? 3 : 6); ++e) {
    const auto it = edge_cells_.find(key(v[kEdge[e][0]], v[kEdge[e][1]]));
    std::vector<int>& around = it->second;
    around.erase(std::find(around.begin(), around.end(), c));
    if (around.empty()) edge_cells_.erase(it);
  }
}

std::array<int, 4> BisectionForest::child_facets(const Cell& parent, const std::array<int, 4>& cv, int m) const {
  // Face k of the child is opposite its vertex w = cv[k]: opposite the new vertex m, the parent's face
  // opposite the refinement edge's end the child lacks; opposite the end it holds, the cut (inside the
  // parent); opposite another vertex, inside the parent's face opposite that vertex.
  const auto place = [&](int w) { return static_cast<std::size_t>(std::find(parent.v.begin(), parent.v.end(), w) - parent.v.begin()); };
  const int end = cv[0], other_end = end == parent.v[0] ? parent.v[3] : parent.v[0];
  std::array<int, 4> out{};
  for (std::size_t k = 0; k < 4; ++k) {
    const int w = cv[k];
    out[k] = w == end ? -1 : parent.facet[place(w == m ? other_end : w)];
  }
  return out;
}

void BisectionForest::split(int c) {
  const Cell parent = cells_[static_cast<std::size_t>(c)];
  const auto [a, b] = refinement_edge(c);
  const auto [it, fresh] = midpoint_.try_emplace(key(a, b), n_nodes());
  if (fresh) {
    const Point& xa = x_[static_cast<std::size_t>(a)];
    const Point& xb = x_[static_cast<std::size_t>(b)];
    x_.push_back({(xa[0] + xb[0]) / 2, (xa[1] + xb[1]) / 2, (xa[2] + xb[2]) / 2});
    made_at_.push_back({a, b});
    alive_.push_back(1);
  }
  const int m = it->second;
  remove_edges(c);
  cells_[static_cast<std::size_t>(c)].is_leaf = false;
  const auto& v = parent.v;
  for (int k = 0; k < 2; ++k) {
    Cell child;
    if (dim_ == 2) {
      child.v = k == 0 ? std::array<int, 4>{v[2], a, m, -1} : std::array<int, 4>{b, v[2], m, -1};
    } else {  // Maubach (see the header): the generation's type decides the second child's order
      child.v = k == 0 ? std::array<int, 4>{v[0], m, v[1], v[2]}
                       : (parent.level % 3 == 0 ? std::array<int, 4>{v[3], m, v[2], v[1]}
                                                : std::array<int, 4>{v[3], m, v[1], v[2]});
      child.facet = child_facets(parent, child.v, m);
    }
    child.parent = c;
    child.root = parent.root;
    child.level = parent.level + 1;
    cells_[static_cast<std::size_t>(c)].child[static_cast<std::size_t>(k)] = n_cells();
    cells_.push_back(child);
    add_edges(n_cells() - 1);
  }
}

void BisectionForest::bisect(int c, int& bisected, int depth) {
  // A closure this deep means a labelling the closure does not terminate for (none that the constructor
  // makes, see the header): an error rather than a hang.
  require(depth < 1000, "newest-vertex bisection: the closure of cell {} did not terminate (the labelling is not compatible)", c);
  const auto edge = refinement_edge(c);
  const std::uint64_t e = key(edge[0], edge[1]);
  for (;;) {
    // a leaf around the edge whose own refinement edge is another: bisect it first; its child at the edge then
    // has it as its own (or, in 3D, after further bisections)
    int other = -1;
    for (int k : edge_cells_.at(e)) {
      const auto r = refinement_edge(k);
      if (k != c && key(r[0], r[1]) != e) {
        other = k;
        break;
      }
    }
    if (other < 0) break;
    bisect(other, bisected, depth + 1);
  }
  const std::vector<int> around = edge_cells_.at(e);  // every leaf at the edge, bisected at one midpoint
  for (int k : around)
    if (k != c) {
      split(k);
      ++bisected;
    }
  split(c);
  ++bisected;
}

int BisectionForest::refine(const std::vector<int>& leaves) {
  int bisected = 0;
  for (int c : leaves) {
    require(c >= 0 && c < n_cells(), "newest-vertex bisection: no cell {} (of {})", c, n_cells());
    // (an earlier closure may have bisected it already: then it is refined, as asked)
    if (leaf(c)) bisect(c, bisected, 0);
  }
  return bisected;
}

void BisectionForest::unsplit(int c) {
  Cell& parent = cells_[static_cast<std::size_t>(c)];
  for (int k : parent.child) {
    remove_edges(k);
    cells_[static_cast<std::size_t>(k)].is_leaf = false;  // unreachable from here on: not a leaf, not a parent
  }
  parent.is_leaf = true;
  add_edges(c);
}

std::vector<BisectionForest::Patch> BisectionForest::coarsenable(const std::vector<int>& leaves) const {
  std::unordered_map<int, std::vector<int>> by_peak;  // a made node → the marked leaves it is the peak of
  for (int c : leaves) {
    require(c >= 0 && c < n_cells() && leaf(c), "newest-vertex bisection: cell {} is not a leaf to coarsen", c);
    if (const int m = newest_vertex(c); m >= coarse_.n_nodes() && parent(c) >= 0) by_peak[m].push_back(c);
  }
  std::vector<int> around(x_.size(), 0);  // leaves at each node
  for (int c : this->leaves())
    for (int v : vertices(c)) ++around[static_cast<std::size_t>(v)];
  std::vector<int> nodes;
  for (const auto& [m, cells] : by_peak) nodes.push_back(m);
  std::sort(nodes.begin(), nodes.end());  // the same order whatever the hash map's
  std::vector<Patch> out;
  for (int m : nodes) {
    const std::vector<int>& cells = by_peak[m];
    if (static_cast<int>(cells.size()) != around[static_cast<std::size_t>(m)]) continue;  // a leaf around m not marked
    const std::uint64_t edge = key(made_at(m)[0], made_at(m)[1]);
    std::vector<int> parents;
    bool whole = true;
    for (int c : cells) {
      const int p = parent(c);
      const Cell& P = cells_[static_cast<std::size_t>(p)];
      const auto r = refinement_edge(p);
      // m is made at P's refinement edge, and both of P's children are marked leaves around m
      whole = whole && key(r[0], r[1]) == edge && leaf(P.child[0]) && leaf(P.child[1]) &&
              std::count(cells.begin(), cells.end(), P.child[0]) == 1 && std::count(cells.begin(), cells.end(), P.child[1]) == 1;
      if (std::find(parents.begin(), parents.end(), p) == parents.end()) parents.push_back(p);
    }
    if (!whole || cells.size() != 2 * parents.size()) continue;
    out.push_back({m, std::move(parents)});
  }
  return out;
}

int BisectionForest::coarsen(const std::vector<int>& leaves) { return coarsen_patches(coarsenable(leaves)); }

int BisectionForest::coarsen_patches(const std::vector<Patch>& patches) {
  for (const Patch& patch : patches) {
    const int m = patch.node;
    require(m >= 0 && m < n_nodes() && node_alive(m) && m >= coarse_.n_nodes(),
            "newest-vertex bisection: node {} is not a made node to remove", m);
    for (int p : patch.parents)
      require(!leaf(p) && leaf(children(p)[0]) && leaf(children(p)[1]),
              "newest-vertex bisection: the patch of node {} changed since it was found", m);
    for (int p : patch.parents) unsplit(p);
    midpoint_.erase(key(made_at(m)[0], made_at(m)[1]));
    alive_[static_cast<std::size_t>(m)] = 0;
  }
  return static_cast<int>(patches.size());
}

std::vector<int> BisectionForest::mesh_numbers() const {
  std::vector<int> out(x_.size(), -1);
  int next = 0;
  for (std::size_t i = 0; i < x_.size(); ++i)
    if (alive_[i]) out[i] = next++;
  return out;
}

double BisectionForest::area(int c) const {
  const auto v = vertices(c);
  if (dim_ == 2)
    return 0.5 * std::abs(orientation(x_[static_cast<std::size_t>(v[0])], x_[static_cast<std::size_t>(v[1])],
                                      x_[static_cast<std::size_t>(v[2])]));
  Point x[4];
  for (int k = 0; k <= dim_; ++k) x[k] = x_[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])];
  return simplex_measure(dim_, x);
}

std::vector<int> BisectionForest::leaves() const {
  std::vector<int> out, stack;
  for (int r = 0; r < coarse_.n_cells(); ++r) {
    stack.push_back(r);
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      if (leaf(c)) {
        out.push_back(c);
        continue;
      }
      const auto& child = cells_[static_cast<std::size_t>(c)].child;
      stack.push_back(child[1]);
      stack.push_back(child[0]);
    }
  }
  return out;
}

Mesh BisectionForest::leaf_mesh() const {
  Mesh mesh(dim_);
  for (const std::string& part : coarse_.part_names()) mesh.part_id(part);  // numbered as the coarse mesh's
  for (const std::string& region : coarse_.region_names()) mesh.region_id(region);
  const std::vector<int> number = mesh_numbers();
  for (std::size_t i = 0; i < x_.size(); ++i)
    if (alive_[i]) mesh.add_node(x_[i]);
  const std::vector<int> cells = leaves();
  for (int c : cells) {
    const auto v = vertices(c);
    int w[4];
    for (int k = 0; k <= dim_; ++k) w[k] = number[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])];
    if (dim_ == 3) {  // positively oriented, as the generators' (Maubach's order is not)
      const Point &p = x_[static_cast<std::size_t>(v[0])], &q = x_[static_cast<std::size_t>(v[1])],
                  &r = x_[static_cast<std::size_t>(v[2])], &s = x_[static_cast<std::size_t>(v[3])];
      if (signed_volume6(p, q, r, s) < 0) std::swap(w[1], w[2]);
    }
    mesh.add_cell(w);
  }
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (const int r = coarse_.cell_region(root(cells[k])); r >= 0)
      mesh.set_cell_region(static_cast<int>(k), coarse_.region_names()[static_cast<std::size_t>(r)]);
    if (coarse_.n_bodies() > 1) mesh.set_cell_body(static_cast<int>(k), coarse_.cell_body(root(cells[k])));
  }
  if (dim_ == 3) {
    add_facets_3d(mesh, cells, number);
    return mesh;
  }
  // Each coarse boundary facet as its halves, recursively, in its part.
  const std::function<void(int, int, const std::string&)> facet = [&](int a, int b, const std::string& part) {
    if (const auto it = midpoint_.find(key(a, b)); it != midpoint_.end()) {
      facet(a, it->second, part);
      facet(it->second, b, part);
      return;
    }
    const int v[2] = {number[static_cast<std::size_t>(a)], number[static_cast<std::size_t>(b)]};
    mesh.add_facet(v, part);
  };
  for (int f = 0; f < coarse_.n_facets(); ++f) {
    const int part = coarse_.facet_part(f);
    facet(coarse_.facet(f)[0], coarse_.facet(f)[1],
          part < 0 ? std::string() : coarse_.part_names()[static_cast<std::size_t>(part)]);
  }
  return mesh;
}

void BisectionForest::add_facets_3d(Mesh& mesh, const std::vector<int>& cells, const std::vector<int>& number) const {
  // The leaves' faces in a coarse boundary facet, coarse facet after coarse facet (each in leaf order), in
  // its part; a facet between two cells (an interface a mesh may tag) once.
  std::vector<std::pair<int, std::array<int, 3>>> faces;
  for (int c : cells) {
    const Cell& cell = cells_[static_cast<std::size_t>(c)];
    int w[4];
    for (int j = 0; j < 4; ++j) w[j] = number[static_cast<std::size_t>(cell.v[static_cast<std::size_t>(j)])];
    for (int k = 0; k < 4; ++k) {
      if (cell.facet[static_cast<std::size_t>(k)] < 0) continue;
      std::array<int, 3> f{};
      cell_facet(w, 4, k, f.data());
      faces.emplace_back(cell.facet[static_cast<std::size_t>(k)], f);
    }
  }
  std::stable_sort(faces.begin(), faces.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::unordered_set<FacetKey, FacetKeyHash> seen;
  for (const auto& [f, v] : faces) {
    if (!seen.insert(facet_key(v.data(), 3)).second) continue;
    const int part = coarse_.facet_part(f);
    mesh.add_facet(v.data(), part < 0 ? std::string() : coarse_.part_names()[static_cast<std::size_t>(part)]);
  }
}

std::array<int, 2> BisectionForest::made_at(int i) const {
  const int coarse = coarse_.n_nodes();
  return i < coarse ? std::array<int, 2>{-1, -1} : made_at_[static_cast<std::size_t>(i - coarse)];
}

void BisectionForest::interpolate(std::vector<double>& values, int width) const {
  const auto w = static_cast<std::size_t>(width);
  require(width > 0 && values.size() % w == 0 && values.size() / w >= static_cast<std::size_t>(coarse_.n_nodes()) &&
              values.size() / w <= static_cast<std::size_t>(n_nodes()),
          "newest-vertex bisection: a nodal field of {} numbers, {} a node, for {} nodes", values.size(), width, n_nodes());
  for (auto i = values.size() / w; i < static_cast<std::size_t>(n_nodes()); ++i) {
    const auto [a, b] = made_at(static_cast<int>(i));
    for (std::size_t j = 0; j < w; ++j)
      values.push_back(0.5 * (values[static_cast<std::size_t>(a) * w + j] + values[static_cast<std::size_t>(b) * w + j]));
  }
}

std::vector<double> BisectionForest::inherit(const std::vector<int>& before, const std::vector<double>& values,
                                             int width) const {
  const auto w = static_cast<std::size_t>(width);
  require(width > 0 && values.size() == before.size() * w,
          "newest-vertex bisection: a cell field of {} numbers, {} a cell, for {} cells", values.size(), width, before.size());
  std::unordered_map<int, std::size_t> place;  // an old leaf's index in `before`
  for (std::size_t k = 0; k < before.size(); ++k) place.emplace(before[k], k);
  // Σ area × value over the old leaves in c's subtree, and their area (a parent made a leaf again).
  const std::function<double(int, std::vector<double>&)> gather = [&](int c, std::vector<double>& sum) {
    if (const auto it = place.find(c); it != place.end()) {
      const double a = area(c);
      for (std::size_t j = 0; j < w; ++j) sum[j] += a * values[it->second * w + j];
      return a;
    }
    const auto& child = cells_[static_cast<std::size_t>(c)].child;
    require(child[0] >= 0, "newest-vertex bisection: cell {} has no descendant among the cells given", c);  // (a cell never split)
    return gather(child[0], sum) + gather(child[1], sum);
  };
  std::vector<double> out, sum(w);
  for (int c : leaves()) {
    int a = c;
    while (a >= 0 && !place.count(a)) a = parent(a);
    if (a >= 0) {  // kept or refined: its (ancestor's) values
      const std::size_t k = place.at(a);
      out.insert(out.end(), values.begin() + static_cast<std::ptrdiff_t>(k * w),
                 values.begin() + static_cast<std::ptrdiff_t>((k + 1) * w));
      continue;
    }
    std::fill(sum.begin(), sum.end(), 0.0);  // coarsened: the mean over its old leaves
    const double total = gather(c, sum);
    for (std::size_t j = 0; j < w; ++j) out.push_back(sum[j] / total);
  }
  return out;
}

double BisectionForest::dihedral_angle(int c, int i, int j) const {
  // the angle between the two faces at edge (i, j): that of the other two vertices seen along the edge
  const auto v = vertices(c);
  int o[2], n = 0;
  for (int k = 0; k < 4; ++k)
    if (k != i && k != j) o[n++] = k;
  const Point& p = x_[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])];
  const Point& q = x_[static_cast<std::size_t>(v[static_cast<std::size_t>(j)])];
  double e[3], a[3], b[3];
  for (int r = 0; r < 3; ++r) e[r] = q[r] - p[r];
  const double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  for (int side = 0; side < 2; ++side) {
    const Point& x = x_[static_cast<std::size_t>(v[static_cast<std::size_t>(o[side])])];
    double* w = side == 0 ? a : b;
    for (int r = 0; r < 3; ++r) w[r] = x[r] - p[r];
    const double t = (w[0] * e[0] + w[1] * e[1] + w[2] * e[2]) / ee;
    for (int r = 0; r < 3; ++r) w[r] -= t * e[r];
  }
  const double cr[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

double BisectionForest::min_angle() const {
  double least = M_PI;
  if (dim_ == 3) {
    for (int c : leaves())
      for (const auto& ends : kEdge) least = std::min(least, dihedral_angle(c, ends[0], ends[1]));
    return least;
  }
  for (int c : leaves()) {
    const auto v = vertices(c);
    for (int k = 0; k < 3; ++k) {
      const Point& p = x_[static_cast<std::size_t>(v[k])];
      const Point& q = x_[static_cast<std::size_t>(v[(k + 1) % 3])];
      const Point& r = x_[static_cast<std::size_t>(v[(k + 2) % 3])];
      const double u[2] = {q[0] - p[0], q[1] - p[1]}, w[2] = {r[0] - p[0], r[1] - p[1]};
      least = std::min(least, std::atan2(std::abs(u[0] * w[1] - u[1] * w[0]), u[0] * w[0] + u[1] * w[1]));
    }
  }
  return least;
}

}  // namespace vpc
