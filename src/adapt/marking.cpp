#include "adapt/marking.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vpc {

namespace {

constexpr double kTie = 1e-9;  // values this close (relative) are one value to marking

/// The cells by value, largest first (`descending`) or smallest first; ties by index.
std::vector<int> by_value(const std::vector<double>& eta2, bool descending) {
  std::vector<int> order(eta2.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double x = eta2[static_cast<std::size_t>(a)], y = eta2[static_cast<std::size_t>(b)];
    return x != y ? (descending ? x > y : x < y) : a < b;
  });
  return order;
}

}  // namespace

std::vector<int> bulk_marking(const std::vector<double>& eta2, double fraction) {
  const double total = std::accumulate(eta2.begin(), eta2.end(), 0.0);
  std::vector<int> marked;
  if (!(total > 0) || fraction <= 0) return marked;
  double sum = 0, last = INFINITY;
  for (int c : by_value(eta2, true)) {
    const double v = eta2[static_cast<std::size_t>(c)];
    // Past the bulk, the cells tied with the last one still (to 1e-9, relative): which of equal values a
    // sort puts first must not decide (a symmetric mesh has them, and round-off orders them by engine).
    if (v <= 0 || (sum >= fraction * total && v < last * (1 - kTie))) break;
    marked.push_back(c);
    sum += v;
    last = v;
  }
  return marked;
}

std::vector<int> bulk_marking_each(const std::vector<const std::vector<double>*>& parts, double fraction) {
  std::vector<int> out;
  for (const std::vector<double>* part : parts) {
    const std::vector<int> marked = bulk_marking(*part, fraction);
    out.insert(out.end(), marked.begin(), marked.end());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> smallest_share(const std::vector<double>& eta2, double fraction, const std::vector<char>& eligible) {
  const double total = std::accumulate(eta2.begin(), eta2.end(), 0.0);
  std::vector<int> out;
  if (fraction <= 0) return out;
  double sum = 0;
  for (int c : by_value(eta2, false)) {
    if (!eligible.empty() && !eligible[static_cast<std::size_t>(c)]) continue;
    sum += eta2[static_cast<std::size_t>(c)];
    if (sum > fraction * total) break;
    out.push_back(c);
  }
  return out;
}

}  // namespace vpc
