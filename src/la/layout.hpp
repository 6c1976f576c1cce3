#pragma once
// The layout (index map) of a distributed vector: each rank owns a contiguous
// range [begin, begin + n_owned) of the global numbering and keeps, after its
// owned entries, copies of ghost entries owned by other ranks. Local storage is
// owned entries, then ghosts in the order given (as PETSc's VecCreateGhost).
// `original` numbers the owned entries in the numbering of the mesh as read, for
// gather-to-root and scatter-from-root. The exchanges are written once over
// Comm::exchange; on one process they are identities.
#include "la/comm.hpp"

#include <Eigen/Dense>
#include <vector>

namespace vpc::la {

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

 private:
  Comm comm_;
  int n_owned_ = 0;
  long long n_global_ = 0, begin_ = 0;
  std::vector<long long> ghosts_, original_;
  std::vector<std::vector<int>> send_;        // per rank: our owned entries that rank holds as ghosts
  std::vector<std::vector<int>> recv_;        // per rank: positions in ghosts_ of the entries it owns
  std::vector<std::vector<long long>> originals_;  // on rank 0: each rank's `original`
};

}  // namespace vpc::la
