#pragma once
// The rule "a Simulation is driven from one thread at a time" (docs/python.md, "Threads"),
// enforced: every call that reads or writes a Simulation's state enters its CallLock, which
// refuses (vpcontact.BusyError) a call made while a call of another thread is in progress,
// instead of letting two threads step one state (a crash, duplicated history rows) or one
// read a state half updated. A try-lock, never a wait: a second caller is a bug to report,
// and waiting could deadlock a thread that holds the GIL.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace vpc::python {

namespace py = pybind11;

/// A call refused because another call of the same Simulation is in progress
/// (vpcontact.BusyError, a RuntimeError).
class Busy : public std::runtime_error {
 public:
  Busy(const std::string& message, std::string call, std::string thread)
      : std::runtime_error(message), call(std::move(call)), thread(std::move(thread)) {}
  std::string call;    // the call in progress, e.g. "Simulation.run()"
  std::string thread;  // the name of its thread
};

class CallLock {
 public:
  enum class Access { read, write };

  /// A call in progress: it leaves the lock when destroyed.
  class Entered {
   public:
    Entered(Entered&& o) noexcept : lock_(o.lock_), id_(o.id_) { o.lock_ = nullptr; }
    Entered(const Entered&) = delete;
    Entered& operator=(const Entered&) = delete;
    Entered& operator=(Entered&&) = delete;
    ~Entered();

   private:
    friend class CallLock;
    Entered(CallLock* lock, std::uint64_t id) : lock_(lock), id_(id) {}
    CallLock* lock_;
    std::uint64_t id_;
  };

  /// Enters `call` (e.g. "Simulation.step()") from the calling Python thread (the GIL held).
  /// Throws Busy when a call of another thread is in progress (several reads at once are
  /// fine), or when a write comes from the user's code run inside a call of this thread (a
  /// progress callback: callback()). Other calls of the same thread are that call's own
  /// (run() stepping) and nest.
  [[nodiscard]] Entered enter(std::string call, Access access);

  /// Marks the user's code (a progress callback) running inside the call `e` of this
  /// thread, until the result is destroyed: from there a read nests, a write is refused.
  class Callback {
   public:
    Callback(Callback&& o) noexcept : lock_(o.lock_), id_(o.id_) { o.lock_ = nullptr; }
    Callback(const Callback&) = delete;
    Callback& operator=(const Callback&) = delete;
    Callback& operator=(Callback&&) = delete;
    ~Callback();

   private:
    friend class CallLock;
    Callback(CallLock* lock, std::uint64_t id) : lock_(lock), id_(id) {}
    CallLock* lock_;
    std::uint64_t id_;
  };
  [[nodiscard]] Callback callback(const Entered& e);

 private:
  struct Caller {
    std::uint64_t id;
    unsigned long thread;  // Python's thread ident (threading.get_ident())
    std::string call;
    Access access;
    bool in_callback = false;  // the user's code runs inside this call
  };
  void leave(std::uint64_t id);
  void set_callback(std::uint64_t id, bool on);

  std::mutex mutex_;             // guards callers_ (the GIL does too; this does not rely on it)
  std::vector<Caller> callers_;  // the calls in progress, in the order entered
  std::uint64_t next_id_ = 0;
};

/// A Python context manager (vpcontact._core._Hold) that holds `lock` as a write for `call`
/// while a `with` block runs; `owner` (the lock's Simulation) is kept alive by it.
py::object hold(py::handle owner, CallLock& lock, std::string call);
void bind_call_lock(py::module_& m);

}  // namespace vpc::python
