#include "adapt/marking.hpp"

#include <algorithm>
#include <numeric>

namespace vpc {

namespace {

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
  double sum = 0;
  for (int c : by_value(eta2, true)) {
    if (sum >= fraction * total || eta2[static_cast<std::size_t>(c)] <= 0) break;
    marked.push_back(c);
    sum += eta2[static_cast<std::size_t>(c)];
  }
  return marked;
}

std::vector<int> smallest_share(const std::vector<double>& eta2, double fraction) {
  const double total = std::accumulate(eta2.begin(), eta2.end(), 0.0);
  std::vector<int> out;
  if (fraction <= 0) return out;
  double sum = 0;
  for (int c : by_value(eta2, false)) {
    sum += eta2[static_cast<std::size_t>(c)];
    if (sum > fraction * total) break;
    out.push_back(c);
  }
  return out;
}

}  // namespace vpc
