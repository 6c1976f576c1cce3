#include "verification/refine.hpp"

#include "core/error.hpp"
#include "mesh/refine.hpp"

#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <unordered_map>

namespace vpc {

Refinement refine_uniform(const Mesh& coarse) {
  const int d = coarse.dim();
  require(d >= 1 && d <= 3, "refine: the mesh dimension must be 1, 2 or 3 (got {})", d);
  const MeshRefinement one(coarse, 1);
  BlockMesh b = one.refine_all();  // the whole mesh: node i is number i
  Refinement r;
  r.fine = std::move(b.mesh);
  r.node_parents = one.midpoints();
  for (const int id : b.cell_id) r.parent_cell.push_back(id >> d);  // 2^d children a cell
  for (int f = 0; f < coarse.n_facets(); ++f)
    for (int k = 0; k < 1 << (d - 1); ++k) r.parent_facet.push_back(f);
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
