#pragma once
// The layout (index map) of a distributed vector: each rank owns a contiguous
// range [begin, begin + n_owned) of the global numbering and keeps, after its
// owned entries, copies of ghost entries owned by other ranks. Local storage is
// owned entries, then ghosts in the order given (as PETSc's VecCreateGhost).
// `original` numbers the owned entries in the numbering of the mesh as read: values
// leave the layout to (and come back from) contiguous blocks of that numbering, one
// per rank (BlockSplit: checkpoints in pieces), or all on rank 0 (gather and scatter).
// No rank holds more than its own entries' original numbers. The exchanges are
// written once over Comm::exchange; on one process they are identities.
#include "la/comm.hpp"

#include <Eigen/Dense>
#include <vector>

namespace vpc::la {

/// The numbering [0, n) cut into contiguous blocks, one per rank: block r is
/// [begin(r), end(r)). By default PETSc's split (PETSC_DECIDE): n / blocks each, one
/// more in the first n mod blocks.
class BlockSplit {
 public:
  BlockSplit(long long n, int blocks);
  /// Everything in block 0, the other blocks empty (gather to rank 0).
  static BlockSplit first_only(long long n, int blocks);

  int n_blocks() const { return static_cast<int>(end_.size()); }
  long long n() const { return end_.back(); }
  long long begin(int r) const { return r == 0 ? 0 : end_[r - 1]; }
  long long end(int r) const { return end_[r]; }
  long long size(int r) const { return end(r) - begin(r); }
  /// The block holding entry i (0 <= i < n).
  int block_of(long long i) const;

 private:
  BlockSplit() = default;
  std::vector<long long> end_;
};

class Layout {
 public:
  /// One process, n entries, the original numbering the identity.
  explicit Layout(int n);
  /// Collective. `ghosts`: global indices of the ghost entries (owned elsewhere);
  /// `original`: the original index of each owned entry (a permutation over the ranks).
  Layout(Comm comm, int n_owned, std::vector<long long> ghosts, std::vector<long long> original);

  const Comm& comm() const { return comm_; }
  int n_owned() const { return n_owned_; }
  int n_ghosts() const { return static_cast<int>(ghosts_.size()); }
  int n_local() const { return n_owned_ + n_ghosts(); }
  long long n_global() const { return n_global_; }
  /// Global index of the first owned entry.
  long long begin() const { return begin_; }
  const std::vector<long long>& ghosts() const { return ghosts_; }
  /// The rank that owns ghost entry k (0 <= k < n_ghosts()).
  int ghost_owner(int k) const { return ghost_owner_[static_cast<std::size_t>(k)]; }

  /// Owners' values into the ghost entries of `local` (owned, then ghosts).
  void forward(Eigen::VectorXd& local) const;
  /// Adds the ghost entries of `local` into their owners' entries (ghosts unchanged).
  void reverse_add(Eigen::VectorXd& local) const;
  /// The owned entries of every rank on rank 0, in the original numbering
  /// (n_global values there, none elsewhere). Collective.
  Eigen::VectorXd gather(const Eigen::VectorXd& local) const;
  /// The inverse: `global` (original numbering, read on rank 0 only) into the owned
  /// and ghost entries of `local`. Collective.
  void scatter(const Eigen::VectorXd& global, Eigen::VectorXd& local) const;
  /// The owned entries of every rank, `width` values each (entry i: values[i * width + j]),
  /// sent to the rank whose block of `split` (over the original numbering, one block per
  /// rank) holds them: this rank's block, split.size(rank) * width values. Collective.
  /// Besides the block, no rank holds more than a bounded round of messages (2¹⁸ values
  /// sent per rank per round): a large array does not take several times its size.
  Eigen::VectorXd to_blocks(const Eigen::Ref<const Eigen::VectorXd>& values, const BlockSplit& split, int width = 1) const;
  /// The inverse: each rank's block of `split` (split.size(rank) * width values) into
  /// the owned and ghost entries of `local` (n_local * width values). Collective.
  void from_blocks(const Eigen::VectorXd& block, const BlockSplit& split, Eigen::VectorXd& local, int width = 1) const;

 private:
  Comm comm_;
  int n_owned_ = 0;
  long long n_global_ = 0, begin_ = 0;
  std::vector<long long> ghosts_, original_;
  std::vector<int> ghost_owner_;             // per ghost entry: its owner
  std::vector<std::vector<int>> send_;        // per rank: our owned entries that rank holds as ghosts
  std::vector<std::vector<int>> recv_;        // per rank: positions in ghosts_ of the entries it owns

  /// forward() for `width` values per entry.
  void forward(Eigen::VectorXd& local, int width) const;
  /// Per rank: the owned entries (positions) whose original index lies in that rank's block of `split`.
  std::vector<std::vector<int>> by_block(const BlockSplit& split) const;
};

}  // namespace vpc::la
