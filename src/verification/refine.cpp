#include "verification/refine.hpp"

#include "core/error.hpp"

#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <unordered_map>

namespace vpc {

namespace {

double distance2(const Point& a, const Point& b) {
  double s = 0;
  for (int j = 0; j < 3; ++j) s += (a[j] - b[j]) * (a[j] - b[j]);
  return s;
}

/// Edge midpoints of the fine mesh, created once per coarse edge.
class Midpoints {
 public:
  Midpoints(Mesh& fine, std::vector<std::array<int, 2>>& parents) : fine_(fine), parents_(parents) {}

  int operator()(int a, int b) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
    auto [it, inserted] = index_.try_emplace(key, -1);
    if (inserted) {
      const Point xa = fine_.node(a), xb = fine_.node(b);
      it->second = fine_.add_node({0.5 * (xa[0] + xb[0]), 0.5 * (xa[1] + xb[1]), 0.5 * (xa[2] + xb[2])});
      parents_.push_back({a, b});
    }
    return it->second;
  }

 private:
  Mesh& fine_;
  std::vector<std::array<int, 2>>& parents_;
  std::unordered_map<std::uint64_t, int> index_;
};

/// Children of one coarse cell with vertices v[0..d] (global node numbers).
void refine_cell(int d, const int* v, Midpoints& mid, const Mesh& fine, std::vector<std::array<int, 4>>& out) {
  out.clear();
  if (d == 1) {
    const int m = mid(v[0], v[1]);
    out.push_back({v[0], m, -1, -1});
    out.push_back({m, v[1], -1, -1});
    return;
  }
  if (d == 2) {
    const int m01 = mid(v[0], v[1]), m12 = mid(v[1], v[2]), m02 = mid(v[0], v[2]);
    out.push_back({v[0], m01, m02, -1});
    out.push_back({m01, v[1], m12, -1});
    out.push_back({m02, m12, v[2], -1});
    out.push_back({m01, m12, m02, -1});
    return;
  }
  // d = 3: Bey's red refinement. m[a][b] is the midpoint of edge (a, b).
  int m[4][4];
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) m[a][b] = m[b][a] = mid(v[a], v[b]);
  for (int a = 0; a < 4; ++a) {
    std::array<int, 4> t{};
    for (int b = 0; b < 4; ++b) t[b] = a == b ? v[a] : m[a][b];
    out.push_back(t);
  }
  // The inner octahedron has the three diagonals (m01, m23), (m02, m13), (m03, m12);
  // split it along the shortest one (the first on ties) into four tetrahedra.
  static const int diag[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
  int best = 0;
  double best_len = INFINITY;
  for (int i = 0; i < 3; ++i) {
    const auto* q = diag[i];
    const double len = distance2(fine.node(m[q[0]][q[1]]), fine.node(m[q[2]][q[3]]));
    if (len < best_len) {
      best_len = len;
      best = i;
    }
  }
  // Diagonal (m_ab, m_cd): its four neighbours form the cycle m_ac, m_ad, m_bd, m_bc.
  const int a = diag[best][0], b = diag[best][1], c = diag[best][2], e = diag[best][3];
  const int p = m[a][b], q = m[c][e];
  const int ring[4] = {m[a][c], m[a][e], m[b][e], m[b][c]};
  for (int i = 0; i < 4; ++i) out.push_back({p, q, ring[i], ring[(i + 1) % 4]});
}

/// Children of one boundary facet (d nodes).
void refine_facet(int d, const int* v, Midpoints& mid, std::vector<std::array<int, 3>>& out) {
  out.clear();
  if (d == 1) {
    out.push_back({v[0], -1, -1});
  } else if (d == 2) {
    const int m = mid(v[0], v[1]);
    out.push_back({v[0], m, -1});
    out.push_back({m, v[1], -1});
  } else {
    const int m01 = mid(v[0], v[1]), m12 = mid(v[1], v[2]), m02 = mid(v[0], v[2]);
    out.push_back({v[0], m01, m02});
    out.push_back({m01, v[1], m12});
    out.push_back({m02, m12, v[2]});
    out.push_back({m01, m12, m02});
  }
}

}  // namespace

Refinement refine_uniform(const Mesh& coarse) {
  const int d = coarse.dim();
  require(d >= 1 && d <= 3, "refine: the mesh dimension must be 1, 2 or 3 (got {})", d);
  Refinement r;
  r.fine = Mesh(d);
  for (int i = 0; i < coarse.n_nodes(); ++i) {
    r.fine.add_node(coarse.node(i));
    r.node_parents.push_back({i, i});
  }
  for (const auto& name : coarse.part_names()) r.fine.part_id(name);  // same part numbering
  Midpoints mid(r.fine, r.node_parents);

  std::vector<std::array<int, 4>> cells;
  for (int c = 0; c < coarse.n_cells(); ++c) {
    refine_cell(d, coarse.cell(c), mid, r.fine, cells);
    for (const auto& t : cells) {
      r.fine.add_cell(t.data());
      r.parent_cell.push_back(c);
      if (const int region = coarse.cell_region(c); region >= 0)
        r.fine.set_cell_region(r.fine.n_cells() - 1, coarse.region_names()[region]);
    }
  }
  std::vector<std::array<int, 3>> facets;
  for (int f = 0; f < coarse.n_facets(); ++f) {
    const int part = coarse.facet_part(f);
    const std::string name = part < 0 ? std::string() : coarse.part_names()[part];
    refine_facet(d, coarse.facet(f), mid, facets);
    for (const auto& t : facets) {
      r.fine.add_facet(t.data(), name);
      r.parent_facet.push_back(f);
    }
  }
  return r;
}

Vector prolong_p1(const Refinement& r, const Vector& coarse, int components) {
  const int n_fine = static_cast<int>(r.node_parents.size());
  Vector fine(static_cast<Eigen::Index>(n_fine) * components);
  for (int i = 0; i < n_fine; ++i) {
    const auto [a, b] = r.node_parents[i];
    for (int c = 0; c < components; ++c)
      fine[i * components + c] = 0.5 * (coarse[a * components + c] + coarse[b * components + c]);
  }
  return fine;
}

MeshHierarchy::MeshHierarchy(const Mesh& base, int n_refinements) {
  require(n_refinements >= 0, "mesh hierarchy: the number of refinements must be >= 0 (got {})", n_refinements);
  meshes_.push_back(base);
  for (int l = 0; l < n_refinements; ++l) {
    Refinement r = refine_uniform(meshes_.back());
    meshes_.push_back(std::move(r.fine));
    r.fine = Mesh();
    refinements_.push_back(std::move(r));
  }
  ancestors_.resize(meshes_.size());
}

Vector MeshHierarchy::prolong_p1(const Vector& v, int from, int to, int components) const {
  Vector out = v;
  for (int l = from; l < to; ++l) out = vpc::prolong_p1(refinements_[l], out, components);
  return out;
}

const std::vector<int>& MeshHierarchy::ancestors(int from, int to) const {
  auto& row = ancestors_[from];
  if (row.size() <= static_cast<size_t>(to)) row.resize(to + 1);
  auto& a = row[to];
  if (!a.empty() || meshes_[to].n_cells() == 0) return a;
  if (from == to) {
    a.resize(meshes_[to].n_cells());
    std::iota(a.begin(), a.end(), 0);
    return a;
  }
  const std::vector<int>& up = ancestors(from, to - 1);
  const std::vector<int>& parent = refinements_[to - 1].parent_cell;
  a.resize(parent.size());
  for (size_t c = 0; c < parent.size(); ++c) a[c] = up[parent[c]];
  return a;
}

}  // namespace vpc
