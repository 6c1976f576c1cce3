#include "la/layout.hpp"

#include "core/error.hpp"

#include <algorithm>

namespace vpc::la {

Layout::Layout(int n) : n_owned_(n), n_global_(n) {}

Layout::Layout(Comm comm, int n_owned, std::vector<long long> ghosts, std::vector<long long> original)
    : comm_(std::move(comm)), n_owned_(n_owned), ghosts_(std::move(ghosts)), original_(std::move(original)) {
  require(static_cast<int>(original_.size()) == n_owned_, "internal: layout with {} owned entries and {} original indices",
          n_owned_, original_.size());
  const int p = comm_.size(), me = comm_.rank();
  // Ownership ranges: rank r owns [end[r] − n_r, end[r]).
  const std::vector<long long> counts = comm_.all_gather(n_owned_);
  std::vector<long long> end(p);
  long long total = 0;
  for (int r = 0; r < p; ++r) end[r] = total += counts[r];
  n_global_ = total;
  begin_ = end[me] - n_owned_;
  // Ask each owner for the ghosts it owns; it remembers which of its entries to send.
  std::vector<std::vector<long long>> ask(p);
  recv_.assign(p, {});
  for (size_t k = 0; k < ghosts_.size(); ++k) {
    const long long g = ghosts_[k];
    const int owner = static_cast<int>(std::upper_bound(end.begin(), end.end(), g) - end.begin());
    require(g >= 0 && owner < p && owner != me, "internal: ghost {} is not owned by another rank", g);
    ask[owner].push_back(g);
    recv_[owner].push_back(static_cast<int>(k));
  }
  const auto asked = comm_.exchange(ask);
  send_.assign(p, {});
  for (int r = 0; r < p; ++r)
    for (long long g : asked[r]) send_[r].push_back(static_cast<int>(g - begin_));
  // Rank 0 keeps every rank's original numbers, for gather and scatter.
  std::vector<std::vector<long long>> o(p);
  o[0] = original_;
  originals_ = comm_.exchange(o);
}

void Layout::forward(Eigen::VectorXd& local) const {
  if (comm_.serial()) return;
  std::vector<std::vector<double>> out(send_.size());
  for (size_t r = 0; r < send_.size(); ++r)
    for (int i : send_[r]) out[r].push_back(local[i]);
  const auto in = comm_.exchange(out);
  for (size_t r = 0; r < recv_.size(); ++r)
    for (size_t k = 0; k < recv_[r].size(); ++k) local[n_owned_ + recv_[r][k]] = in[r][k];
}

void Layout::reverse_add(Eigen::VectorXd& local) const {
  if (comm_.serial()) return;
  std::vector<std::vector<double>> out(recv_.size());
  for (size_t r = 0; r < recv_.size(); ++r)
    for (int k : recv_[r]) out[r].push_back(local[n_owned_ + k]);
  const auto in = comm_.exchange(out);
  for (size_t r = 0; r < send_.size(); ++r)
    for (size_t k = 0; k < send_[r].size(); ++k) local[send_[r][k]] += in[r][k];
}

Eigen::VectorXd Layout::gather(const Eigen::VectorXd& local) const {
  if (comm_.serial()) return local.head(n_owned_);
  std::vector<std::vector<double>> out(comm_.size());
  out[0].assign(local.data(), local.data() + n_owned_);
  const auto in = comm_.exchange(out);
  if (comm_.rank() != 0) return {};
  Eigen::VectorXd global(n_global_);
  for (size_t r = 0; r < in.size(); ++r)
    for (size_t k = 0; k < in[r].size(); ++k) global[originals_[r][k]] = in[r][k];
  return global;
}

void Layout::scatter(const Eigen::VectorXd& global, Eigen::VectorXd& local) const {
  local.resize(n_local());
  if (comm_.serial()) {
    local = global;
    return;
  }
  std::vector<std::vector<double>> out(comm_.size());
  if (comm_.rank() == 0) {
    require(global.size() == n_global_, "internal: scatter of {} values over a layout of {}", global.size(), n_global_);
    for (size_t r = 0; r < out.size(); ++r)
      for (long long i : originals_[r]) out[r].push_back(global[i]);
  }
  const auto in = comm_.exchange(out);
  std::copy(in[0].begin(), in[0].end(), local.data());
  forward(local);
}

}  // namespace vpc::la
