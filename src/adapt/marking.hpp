#pragma once
// Which cells an adaptation refines and which it may coarsen, from per-cell indicators (adapt/indicator.hpp).
#include <vector>

namespace vpc {

/// Dörfler's bulk marking: the fewest cells whose values carry at least `fraction` of the sum, largest first
/// (ties by the cell's index, so the result does not depend on the sort). Returns them in that order.
std::vector<int> bulk_marking(const std::vector<double>& eta2, double fraction);

/// The cells with the smallest values that together carry at most `fraction` of the sum (coarsening's
/// candidates), smallest first.
std::vector<int> smallest_share(const std::vector<double>& eta2, double fraction);

}  // namespace vpc
