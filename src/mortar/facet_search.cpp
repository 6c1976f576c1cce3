#include "mortar/facet_search.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace vpc::mortar {

Box facet_box(const Surface& s, int f) {
  Box b{vec(s.node(s.facet(f)[0])), vec(s.node(s.facet(f)[0]))};
  for (int a = 1; a < s.nodes_per_facet(); ++a) {
    const Eigen::Vector3d x = vec(s.node(s.facet(f)[a]));
    b.lo = b.lo.cwiseMin(x);
    b.hi = b.hi.cwiseMax(x);
  }
  return b;
}

FacetPairs candidate_pairs(const Surface& slave, const Surface& master, double margin) {
  require(margin >= 0 && std::isfinite(margin), "mortar search: the margin is {} (expected a finite value >= 0)",
          margin);
  FacetPairs pairs;
  pairs.offset_.assign(slave.n_facets() + 1, 0);
  if (master.n_facets() == 0) return pairs;

  std::vector<Box> boxes(master.n_facets());
  Box all = facet_box(master, 0);
  double mean_extent = 0;
  for (int f = 0; f < master.n_facets(); ++f) {
    boxes[f] = facet_box(master, f);
    all.lo = all.lo.cwiseMin(boxes[f].lo);
    all.hi = all.hi.cwiseMax(boxes[f].hi);
    mean_extent += (boxes[f].hi - boxes[f].lo).maxCoeff();
  }
  const double h = mean_extent / master.n_facets();  // > 0: Surface has no degenerate facet
  // Cells along each axis; a flat extent (z in 2D) has one.
  Eigen::Array3i n_cells;
  for (int d = 0; d < 3; ++d) n_cells[d] = static_cast<int>(std::min(std::floor((all.hi[d] - all.lo[d]) / h) + 1, 1e6));
  const auto cell_of = [&](const Eigen::Vector3d& x) {
    Eigen::Array3i c;
    for (int d = 0; d < 3; ++d)
      c[d] = static_cast<int>(std::clamp(std::floor((x[d] - all.lo[d]) / h), 0.0, n_cells[d] - 1.0));
    return c;
  };
  const auto key = [&](int i, int j, int k) {
    return static_cast<std::int64_t>(i) + n_cells[0] * (static_cast<std::int64_t>(j) + n_cells[1] * std::int64_t{k});
  };
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  for (int f = 0; f < master.n_facets(); ++f) {
    const Eigen::Array3i a = cell_of(boxes[f].lo), b = cell_of(boxes[f].hi);
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i) grid[key(i, j, k)].push_back(f);
  }

  std::vector<int> seen(master.n_facets(), -1);  // the last slave facet that met each master facet
  for (int s = 0; s < slave.n_facets(); ++s) {
    const Box box = facet_box(slave, s);
    const Eigen::Vector3d m = Eigen::Vector3d::Constant(margin);
    const size_t first = pairs.master_.size();
    if (box.near(all, margin)) {
      const Eigen::Array3i a = cell_of(box.lo - m), b = cell_of(box.hi + m);
      for (int k = a[2]; k <= b[2]; ++k)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int i = a[0]; i <= b[0]; ++i) {
            const auto it = grid.find(key(i, j, k));
            if (it == grid.end()) continue;
            for (const int f : it->second)
              if (seen[f] != s) {
                seen[f] = s;
                if (box.near(boxes[f], margin)) pairs.master_.push_back(f);
              }
          }
    }
    std::sort(pairs.master_.begin() + first, pairs.master_.end());
    pairs.offset_[s + 1] = static_cast<int>(pairs.master_.size());
  }
  return pairs;
}

}  // namespace vpc::mortar
