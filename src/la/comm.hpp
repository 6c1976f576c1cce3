#pragma once
// The communicator of the linear-algebra layer: the few collective operations
// that differ between one process and many. A default Comm is one process: every
// operation is an inline identity, so the serial build carries no MPI symbol and
// pays one predictable branch. A distributed Comm (la/mpi_comm.hpp, PETSc build)
// forwards them to MPI through CommBackend. The pattern is MFEM's: one algorithm,
// whose only MPI hook is a reduction after a local computation.
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace vpc::la {

/// The collectives of a communicator of several processes.
class CommBackend {
 public:
  virtual ~CommBackend() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Element-wise sums over the ranks, in place.
  virtual void sum(double* v, int n) const = 0;
  virtual void sum(long long* v, int n) const = 0;
  virtual double max(double v) const = 0;
  virtual double min(double v) const = 0;
  /// Every rank's value, in rank order.
  virtual std::vector<long long> all_gather(long long v) const = 0;
  /// Sends to_rank[r] to rank r; returns what each rank sent to this one.
  virtual std::vector<std::vector<double>> exchange(const std::vector<std::vector<double>>& to_rank) const = 0;
  virtual std::vector<std::vector<long long>> exchange(const std::vector<std::vector<long long>>& to_rank) const = 0;
  /// The message of the lowest rank with failed set, on every rank ("" when none failed).
  virtual std::string first_failure(bool failed, const std::string& message) const = 0;
  /// Rank 0's bytes on every rank (a broadcast tree: rank 0 sends log P copies, not P).
  virtual void broadcast(std::string& bytes) const = 0;
};

class Comm {
 public:
  /// One process.
  Comm() = default;
  explicit Comm(std::shared_ptr<const CommBackend> backend) : b_(std::move(backend)) {}

  bool serial() const { return !b_; }
  const CommBackend* backend() const { return b_.get(); }
  int rank() const { return b_ ? b_->rank() : 0; }
  int size() const { return b_ ? b_->size() : 1; }

  double sum(double v) const {
    if (b_) b_->sum(&v, 1);
    return v;
  }
  long long sum(long long v) const {
    if (b_) b_->sum(&v, 1);
    return v;
  }
  void sum(double* v, int n) const {
    if (b_ && n > 0) b_->sum(v, n);
  }
  void sum(long long* v, int n) const {
    if (b_ && n > 0) b_->sum(v, n);
  }
  double max(double v) const { return b_ ? b_->max(v) : v; }
  double min(double v) const { return b_ ? b_->min(v) : v; }
  /// v holds on every rank.
  bool all(bool v) const { return b_ ? b_->min(v ? 1.0 : 0.0) > 0 : v; }
  /// v holds on some rank.
  bool any(bool v) const { return b_ ? b_->max(v ? 1.0 : 0.0) > 0 : v; }
  std::vector<long long> all_gather(long long v) const { return b_ ? b_->all_gather(v) : std::vector<long long>{v}; }
  template <typename T>
  std::vector<std::vector<T>> exchange(const std::vector<std::vector<T>>& to_rank) const {
    return b_ ? b_->exchange(to_rank) : to_rank;
  }
  /// Rank 0's bytes on every rank.
  void broadcast(std::string& bytes) const {
    if (b_) b_->broadcast(bytes);
  }
  /// Collective: when `failed` holds on some rank, every rank throws the same
  /// vpc::CollectiveError (reported once by the program), with the message of the lowest such rank (no rank left waiting
  /// in a later collective for one that threw).
  void throw_if_any(bool failed, const std::string& message) const;

 private:
  std::shared_ptr<const CommBackend> b_;
};

/// Runs `work` on every process; if it throws on any, every process throws the
/// error of the lowest rank that failed (Comm::throw_if_any). `work` must not wait
/// for other processes (they may have failed before meeting it). On one process
/// it is `work()` itself, whose exception passes unchanged.
template <typename F>
void collective(const Comm& comm, F&& work) {
  if (comm.serial()) {
    work();
    return;
  }
  std::string message;
  try {
    work();
  } catch (const std::exception& e) {
    message = e.what();
    comm.throw_if_any(true, message);
  }
  comm.throw_if_any(false, message);
}

/// Runs `work` on rank 0 only; its error is every process's. Collective.
template <typename F>
void on_root(const Comm& comm, F&& work) {
  collective(comm, [&] {
    if (comm.rank() == 0) work();
  });
}

/// Rank 0's `values` on every process (the others' are replaced), exactly. Collective.
template <typename T>
std::vector<T> broadcast(const Comm& comm, std::vector<T> values) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (comm.serial()) return values;
  std::string bytes;
  if (comm.rank() == 0) bytes.assign(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  comm.broadcast(bytes);
  values.resize(bytes.size() / sizeof(T));
  if (!bytes.empty()) std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

}  // namespace vpc::la
