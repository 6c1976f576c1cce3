#pragma once
// Numbering of the P1 vector displacement unknowns: dof (node, component) =
// node * d + component in the full space; the free space V^h drops the
// prescribed components: all of those of the nodes on the clamped boundary Γ1
// (u = 0 there, (2.4)) and those a prescribed displacement sets (SPEC §6).
#include <vector>

namespace vpc {

class DofMap {
 public:
  DofMap() = default;
  /// `clamped_nodes`: nodes of Γ1, all of whose components are fixed to zero.
  DofMap(int n_nodes, int dim, const std::vector<int>& clamped_nodes);
  /// `prescribed[node * dim + component]` ≥ 0 where that component is prescribed.
  DofMap(int dim, const std::vector<int>& prescribed);

  int dim() const { return dim_; }
  int n_full() const { return static_cast<int>(free_.size()); }
  int n_free() const { return n_free_; }
  /// Free index of full dof i, or -1 if prescribed.
  int free_index(int i) const { return free_[i]; }
  int full_index(int node, int comp) const { return node * dim_ + comp; }

 private:
  int dim_ = 0, n_free_ = 0;
  std::vector<int> free_;
};

}  // namespace vpc
