#include "la/layout.hpp"

#include "core/error.hpp"

#include <algorithm>

namespace vpc::la {

BlockSplit::BlockSplit(long long n, int blocks) : end_(static_cast<std::size_t>(blocks)) {
  require(n >= 0 && blocks >= 1, "internal: a split of {} entries into {} blocks", n, blocks);
  long long at = 0;
  for (int r = 0; r < blocks; ++r) end_[r] = at += n / blocks + (r < n % blocks ? 1 : 0);
}

BlockSplit BlockSplit::first_only(long long n, int blocks) {
  BlockSplit s(n, blocks);
  std::fill(s.end_.begin(), s.end_.end(), n);
  return s;
}

int BlockSplit::block_of(long long i) const {
  return static_cast<int>(std::upper_bound(end_.begin(), end_.end(), i) - end_.begin());
}

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
  ghost_owner_.resize(ghosts_.size());
  for (size_t k = 0; k < ghosts_.size(); ++k) {
    const long long g = ghosts_[k];
    const int owner = static_cast<int>(std::upper_bound(end.begin(), end.end(), g) - end.begin());
    require(g >= 0 && owner < p && owner != me, "internal: ghost {} is not owned by another rank", g);
    ghost_owner_[k] = owner;
    ask[owner].push_back(g);
    recv_[owner].push_back(static_cast<int>(k));
  }
  const auto asked = comm_.exchange(ask);
  send_.assign(p, {});
  for (int r = 0; r < p; ++r)
    for (long long g : asked[r]) send_[r].push_back(static_cast<int>(g - begin_));
}

void Layout::forward(Eigen::VectorXd& local) const { forward(local, 1); }

void Layout::forward(Eigen::VectorXd& local, int width) const {
  if (comm_.serial()) return;
  const auto w = static_cast<Eigen::Index>(width);
  std::vector<std::vector<double>> out(send_.size());
  for (size_t r = 0; r < send_.size(); ++r)
    for (int i : send_[r]) out[r].insert(out[r].end(), local.data() + i * w, local.data() + (i + 1) * w);
  const auto in = comm_.exchange(out);
  for (size_t r = 0; r < recv_.size(); ++r)
    for (size_t k = 0; k < recv_[r].size(); ++k)
      std::copy_n(in[r].data() + k * w, w, local.data() + (n_owned_ + recv_[r][k]) * w);
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
  return to_blocks(local, BlockSplit::first_only(n_global_, comm_.size()));
}

void Layout::scatter(const Eigen::VectorXd& global, Eigen::VectorXd& local) const {
  if (comm_.serial()) {
    local = global;
    return;
  }
  const BlockSplit root = BlockSplit::first_only(n_global_, comm_.size());
  require(comm_.rank() != 0 || global.size() == n_global_, "internal: scatter of {} values over a layout of {}",
          global.size(), n_global_);
  static const Eigen::VectorXd none;  // the other ranks' blocks are empty
  from_blocks(comm_.rank() == 0 ? global : none, root, local);
}

std::vector<std::vector<int>> Layout::by_block(const BlockSplit& split) const {
  require(split.n_blocks() == comm_.size() && split.n() == n_global_,
          "internal: a split of {} entries into {} blocks for a layout of {} entries on {} ranks", split.n(),
          split.n_blocks(), n_global_, comm_.size());
  std::vector<std::vector<int>> at(comm_.size());
  for (int i = 0; i < n_owned_; ++i) at[split.block_of(original_[i])].push_back(i);
  return at;
}

Eigen::VectorXd Layout::to_blocks(const Eigen::Ref<const Eigen::VectorXd>& values, const BlockSplit& split, int width) const {
  const auto w = static_cast<Eigen::Index>(width);
  if (comm_.serial()) return values.head(n_owned_ * w);
  const std::vector<std::vector<int>> at = by_block(split);
  const int p = comm_.size(), me = comm_.rank();
  const long long first = split.begin(me);
  Eigen::VectorXd block(split.size(me) * w);
  // This rank's entries of its own block: in place, no message.
  for (int i : at[me]) std::copy_n(values.data() + i * w, w, block.data() + (original_[i] - first) * w);
  long long received = static_cast<long long>(at[me].size());
  // The others' in rounds, each entry with its original index, so that besides the block no
  // rank holds more than one round's messages: at most kRoundValues values sent by each rank
  // (the block's rank puts each in place). Every rank takes part in every round.
  constexpr long long kRoundValues = 1 << 18;
  const long long per_rank = std::max(1LL, kRoundValues / (w * std::max(1, p - 1)));  // entries to each rank per round
  long long most = 0;
  for (int r = 0; r < p; ++r)
    if (r != me) most = std::max(most, static_cast<long long>(at[r].size()));
  const auto rounds = static_cast<long long>(comm_.max(static_cast<double>((most + per_rank - 1) / per_rank)));
  std::vector<std::vector<long long>> where(p);
  std::vector<std::vector<double>> what(p);
  for (long long k = 0; k < rounds; ++k) {
    for (int r = 0; r < p; ++r) {
      where[r].clear();
      what[r].clear();
      if (r == me) continue;
      const auto n = static_cast<long long>(at[r].size());
      const long long b = std::min(n, k * per_rank), e = std::min(n, b + per_rank);
      where[r].reserve(static_cast<std::size_t>(e - b));
      what[r].reserve(static_cast<std::size_t>((e - b) * w));
      for (long long j = b; j < e; ++j) {
        const int i = at[r][static_cast<std::size_t>(j)];
        where[r].push_back(original_[i]);
        what[r].insert(what[r].end(), values.data() + i * w, values.data() + (i + 1) * w);
      }
    }
    const auto from = comm_.exchange(where);
    const auto data = comm_.exchange(what);
    for (int r = 0; r < p; ++r) {
      for (std::size_t j = 0; j < from[r].size(); ++j)
        std::copy_n(data[r].data() + j * w, w, block.data() + (from[r][j] - first) * w);
      received += static_cast<long long>(from[r].size());
    }
  }
  require(received == split.size(me), "internal: block {} received {} of its {} entries", me, received, split.size(me));
  return block;
}

void Layout::from_blocks(const Eigen::VectorXd& block, const BlockSplit& split, Eigen::VectorXd& local,
                         int width) const {
  const auto w = static_cast<Eigen::Index>(width);
  if (comm_.serial()) {
    local = block;
    return;
  }
  // Ask each block's rank for the owned entries it holds, by original index; ghosts come from their owners.
  const std::vector<std::vector<int>> at = by_block(split);
  std::vector<std::vector<long long>> ask(at.size());
  for (size_t r = 0; r < at.size(); ++r)
    for (int i : at[r]) ask[r].push_back(original_[i]);
  const auto asked = comm_.exchange(ask);
  ask = {};
  const long long first = split.begin(comm_.rank());
  require(block.size() == split.size(comm_.rank()) * w, "internal: a block of {} values for {} entries of width {}",
          block.size(), split.size(comm_.rank()), width);
  std::vector<std::vector<double>> reply(asked.size());
  for (size_t r = 0; r < asked.size(); ++r)
    for (long long o : asked[r]) reply[r].insert(reply[r].end(), block.data() + (o - first) * w, block.data() + (o - first + 1) * w);
  const auto got = comm_.exchange(reply);
  reply = {};
  local.resize(n_local() * w);
  for (size_t r = 0; r < at.size(); ++r)
    for (size_t k = 0; k < at[r].size(); ++k) std::copy_n(got[r].data() + k * w, w, local.data() + at[r][k] * w);
  forward(local, width);
}

}  // namespace vpc::la
