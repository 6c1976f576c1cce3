#pragma once
// Which cells an adaptation refines and which it may coarsen, from per-cell indicators (adapt/indicator.hpp).
#include <vector>

namespace vpc {

/// Dörfler's bulk marking: the fewest cells whose values carry at least `fraction` of the sum, largest first,
/// and the cells tied with the last of them (within 1e-9, relative: a symmetric mesh's equal values, which
/// round-off orders differently on another engine). Returns them in that order (ties by the cell's index).
std::vector<int> bulk_marking(const std::vector<double>& eta2, double fraction);

/// The union of bulk_marking(part, fraction) over the parts given (each part's Dörfler set: a part that
/// concentrates in a few cells, such as the contact's, does not starve the others), in increasing order.
std::vector<int> bulk_marking_each(const std::vector<const std::vector<double>*>& parts, double fraction);

/// The cells with the smallest values that together carry at most `fraction` of the sum over all cells
/// (coarsening's candidates), smallest first, among the `eligible` ones (empty: all; the refined cells:
/// the coarse cells, which cannot be coarsened, must not use up the share).
std::vector<int> smallest_share(const std::vector<double>& eta2, double fraction, const std::vector<char>& eligible = {});

}  // namespace vpc
