#pragma once
// The active sets one solve of an active-set method has met, over every rank. The
// primal–dual update can cycle where the matrix is not an M-matrix (the contact dual's
// S, K with contact rows); a set that comes back is the sign to switch to monotone
// updates (solve_box_qp, the primal contact solver). Each set is kept as a 64-bit hash
// of every rank's flags, so a check costs one all-gather of one number per rank.
#include "core/hash.hpp"
#include "la/comm.hpp"

#include <cstdint>
#include <set>
#include <vector>

namespace vpc {

class ActiveSetHistory {
 public:
  /// Records the set whose local flags are `state`; true if it was met before. Collective.
  template <typename Flag>
  bool came_back(const std::vector<Flag>& state, const la::Comm& comm) {
    const std::uint64_t local = fnv1a(state.data(), state.size() * sizeof(Flag));
    std::uint64_t all = kFnv1aOffset;
    for (long long h : comm.all_gather(static_cast<long long>(local))) all = fnv1a(&h, sizeof h, all);
    return !seen_.insert(all).second;
  }

 private:
  std::set<std::uint64_t> seen_;
};

}  // namespace vpc
