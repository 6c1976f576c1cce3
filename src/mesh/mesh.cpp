#include "mesh/mesh.hpp"

#include "core/error.hpp"
#include "mesh/facet_key.hpp"
#include "mesh/node_cells.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace vpc {

int Mesh::add_node(const Point& p) {
  x_.push_back(p);
  return n_nodes() - 1;
}

void Mesh::add_cell(const int* nodes) {
  cells_.insert(cells_.end(), nodes, nodes + nodes_per_cell());
  if (!cell_region_.empty()) cell_region_.push_back(-1);
  if (!cell_body_.empty()) cell_body_.push_back(n_bodies_ - 1);
}

void Mesh::set_cell_body(int c, int body) {
  require(body >= 0 && c >= 0 && c < n_cells(), "cell {} (of {}) into body {}", c, n_cells(), body);
  if (cell_body_.empty()) cell_body_.assign(static_cast<std::size_t>(n_cells()), 0);
  cell_body_[static_cast<std::size_t>(c)] = body;
  n_bodies_ = std::max(n_bodies_, body + 1);
}

int Mesh::append(const Mesh& other, const std::string& name) {
  require(other.dim() == dim_, "mesh of body '{}': dimension {} where the other bodies' is {}", name, other.dim(), dim_);
  const int offset = n_nodes(), first_cell = n_cells();
  if (cell_body_.empty()) cell_body_.assign(static_cast<std::size_t>(n_cells()), 0);
  ++n_bodies_;
  x_.insert(x_.end(), other.x_.begin(), other.x_.end());
  std::vector<int> shifted(static_cast<std::size_t>(nodes_per_cell()));
  for (int c = 0; c < other.n_cells(); ++c) {
    for (int a = 0; a < nodes_per_cell(); ++a) shifted[a] = other.cell(c)[a] + offset;
    add_cell(shifted.data());
    if (const int r = other.cell_region(c); r >= 0) set_cell_region(first_cell + c, name + "." + other.region_names_[r]);
  }
  for (int f = 0; f < other.n_facets(); ++f) {
    for (int a = 0; a < nodes_per_facet(); ++a) shifted[a] = other.facet(f)[a] + offset;
    const int part = other.facet_part(f);
    add_facet(shifted.data(), part < 0 ? std::string() : name + "." + other.part_names_[part]);
  }
  return n_bodies_ - 1;
}

int Mesh::find_region(const std::string& name) const {
  auto it = std::find(region_names_.begin(), region_names_.end(), name);
  return it == region_names_.end() ? -1 : static_cast<int>(it - region_names_.begin());
}

int Mesh::region_id(const std::string& name) {
  const int r = find_region(name);
  if (r >= 0) return r;
  region_names_.push_back(name);
  return static_cast<int>(region_names_.size()) - 1;
}

void Mesh::set_cell_region(int c, const std::string& region) {
  const int r = region_id(region);
  if (cell_region_.empty()) cell_region_.assign(n_cells(), -1);
  cell_region_[c] = r;
}

int Mesh::region_size(const std::string& name) const {
  const int r = find_region(name);
  return r < 0 ? 0 : static_cast<int>(std::count(cell_region_.begin(), cell_region_.end(), r));
}

void Mesh::tag_cells(const std::string& name, const std::function<bool(const Point&)>& pred) {
  for (int c = 0; c < n_cells(); ++c)
    if (pred(cell_centroid(c))) set_cell_region(c, name);
}

int Mesh::find_part(const std::string& name) const {
  auto it = std::find(part_names_.begin(), part_names_.end(), name);
  return it == part_names_.end() ? -1 : static_cast<int>(it - part_names_.begin());
}

int Mesh::part_id(const std::string& name) {
  const int p = find_part(name);
  if (p >= 0) return p;
  part_names_.push_back(name);
  return static_cast<int>(part_names_.size()) - 1;
}

int Mesh::part_size(const std::string& name) const {
  const int p = find_part(name);
  if (p < 0) return 0;
  return static_cast<int>(std::count(facet_part_.begin(), facet_part_.end(), p));
}

void Mesh::add_facet(const int* nodes, const std::string& part) {
  facets_.insert(facets_.end(), nodes, nodes + nodes_per_facet());
  facet_part_.push_back(part.empty() ? -1 : part_id(part));
  facet_cell_.clear();
}

void Mesh::set_facet_part(int f, const std::string& part) {
  facet_part_[f] = part.empty() ? -1 : part_id(part);
}

namespace {

/// Calls visit(key, c, i) for facet i of every cell c, cell after cell.
template <class Visit>
void for_each_cell_facet(const Mesh& mesh, Visit visit) {
  const int npc = mesh.nodes_per_cell();
  int f[3];
  for (int c = 0; c < mesh.n_cells(); ++c)
    for (int i = 0; i < npc; ++i) {
      cell_facet(mesh.cell(c), npc, i, f);
      visit(facet_key(f, mesh.nodes_per_facet()), c, i);
    }
}

}  // namespace

Point centroid(const std::vector<Point>& x, const int* v, int n) {
  Point m{0, 0, 0};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j) m[j] += x[v[i]][j] / n;
  return m;
}

void Mesh::build_boundary(const std::function<bool(const Point&)>& keep) {
  std::unordered_map<FacetKey, std::pair<int, int>, FacetKeyHash> count;  // key -> (uses, cell*local)
  const int npc = nodes_per_cell(), npf = nodes_per_facet();
  int f[3];
  for_each_cell_facet(*this, [&](const FacetKey& key, int c, int i) {
    if (keep) {  // only the facets `keep` accepts are counted (a generated box's sides: far fewer than all)
      cell_facet(cell(c), npc, i, f);
      if (!keep(centroid(x_, f, npf))) return;
    }
    auto& e = count[key];
    e.first += 1;
    e.second = c * npc + i;
  });
  facets_.clear();
  facet_part_.clear();
  facet_cell_.clear();
  // Deterministic order: by owning cell, then local facet.
  std::vector<int> owners;
  for (const auto& [key, e] : count)
    if (e.first == 1) owners.push_back(e.second);
  std::sort(owners.begin(), owners.end());
  for (int o : owners) {
    cell_facet(cell(o / npc), npc, o % npc, f);
    facets_.insert(facets_.end(), f, f + npf);
    facet_part_.push_back(-1);
    facet_cell_.push_back(o / npc);
  }
}

void Mesh::find_facet_cells() const {
  if (static_cast<int>(facet_cell_.size()) == n_facets()) return;
  // Each facet's cell among the cells of its first node (the last that holds all its nodes), not
  // from a table of every cell's facets: hashing 4 keys a tetrahedron took 1.5 s of a refined
  // block's 1.6M cells (issue 30); the cells of the facets' first nodes are a few per facet.
  const int npc = nodes_per_cell(), npf = nodes_per_facet();
  const NodeCells around(*this);
  facet_cell_.assign(static_cast<std::size_t>(n_facets()), -1);
  for (int f = 0; f < n_facets(); ++f) {
    const int* v = facet(f);
    for (int k = around.start[static_cast<std::size_t>(v[0])]; k < around.start[static_cast<std::size_t>(v[0]) + 1]; ++k) {
      const int c = around.list[static_cast<std::size_t>(k)];
      const int* w = cell(c);
      bool all = true;
      for (int b = 1; b < npf && all; ++b) all = std::find(w, w + npc, v[b]) != w + npc;
      if (all) facet_cell_[static_cast<std::size_t>(f)] = c;
    }
    require(facet_cell_[static_cast<std::size_t>(f)] >= 0, "mesh: boundary facet {} is not a face of any cell", f);
  }
}

int Mesh::facet_cell(int f) const {
  find_facet_cells();
  return facet_cell_[f];
}

void Mesh::tag_facets(const std::string& name, const std::function<bool(const Point&)>& pred) {
  const int p = part_id(name);
  for (int f = 0; f < n_facets(); ++f)
    if (pred(facet_centroid(f))) facet_part_[f] = p;
}

Point Mesh::facet_centroid(int f) const { return centroid(x_, facet(f), nodes_per_facet()); }

Point Mesh::cell_centroid(int c) const { return centroid(x_, cell(c), nodes_per_cell()); }

namespace {
Point sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Point& a) { return std::sqrt(dot(a, a)); }
}  // namespace

double simplex_measure(int dim, const Point* x) {
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  for (int a = 1; a <= dim; ++a)
    for (int i = 0; i < dim; ++i) J(i, a - 1) = x[a][i] - x[0][i];
  static const double factorial[4] = {1, 1, 2, 6};
  return std::abs(J.determinant()) / factorial[dim];
}

double Mesh::facet_measure(int f) const {
  const int* v = facet(f);
  switch (dim_) {
    case 1: return 1.0;
    case 2: return norm(sub(x_[v[1]], x_[v[0]]));
    default: return 0.5 * norm(cross(sub(x_[v[1]], x_[v[0]]), sub(x_[v[2]], x_[v[0]])));
  }
}

Point Mesh::facet_normal(int f) const {
  const int* v = facet(f);
  Point n{0, 0, 0};
  switch (dim_) {
    case 1: n = {1, 0, 0}; break;
    case 2: {
      const Point t = sub(x_[v[1]], x_[v[0]]);
      n = {t[1], -t[0], 0};
      break;
    }
    default: n = cross(sub(x_[v[1]], x_[v[0]]), sub(x_[v[2]], x_[v[0]])); break;
  }
  // Orient away from the owning cell's centroid.
  if (dot(n, sub(facet_centroid(f), cell_centroid(facet_cell(f)))) < 0)
    for (double& c : n) c = -c;
  const double l = norm(n);
  for (double& c : n) c /= l;
  return n;
}

std::vector<int> Mesh::facets_of_parts(const std::vector<std::string>& parts) const {
  std::vector<int> ids;
  for (const auto& p : parts) {
    const int id = find_part(p);
    if (id >= 0) ids.push_back(id);
  }
  std::vector<int> out;
  for (int f = 0; f < n_facets(); ++f)
    if (std::find(ids.begin(), ids.end(), facet_part_[f]) != ids.end()) out.push_back(f);
  return out;
}

std::vector<int> Mesh::nodes_of_parts(const std::vector<std::string>& parts) const {
  std::vector<int> out;
  for (int f : facets_of_parts(parts))
    for (int i = 0; i < nodes_per_facet(); ++i) out.push_back(facet(f)[i]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::pair<Point, Point> Mesh::bounding_box() const {
  Point lo = x_.at(0), hi = lo;
  for (const Point& x : x_)
    for (int j = 0; j < 3; ++j) {
      lo[j] = std::min(lo[j], x[j]);
      hi[j] = std::max(hi[j], x[j]);
    }
  return {lo, hi};
}

std::pair<double, double> Mesh::size_range() const {
  double hmin = INFINITY, hmax = 0;
  const int npc = nodes_per_cell();
  for (int c = 0; c < n_cells(); ++c) {
    double h = 0;
    for (int i = 0; i < npc; ++i)
      for (int j = i + 1; j < npc; ++j) h = std::max(h, norm(sub(x_[cell(c)[i]], x_[cell(c)[j]])));
    hmin = std::min(hmin, h);
    hmax = std::max(hmax, h);
  }
  return {hmin, hmax};
}

}  // namespace vpc
