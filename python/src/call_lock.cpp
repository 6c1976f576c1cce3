// CallLock: one Simulation, one caller at a time (call_lock.hpp), and its Python side: the
// context managers with which the module's Python code holds it across several calls
// (Simulation.run() steps, then calls the progress callback, then steps again).
#include "call_lock.hpp"

#include "bindings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

namespace vpc::python {

namespace {

/// The name of the Python thread `ident` (threading's), else "<ident N>".
std::string thread_name(unsigned long ident) {
  try {
    const py::object threading = py::module_::import("threading");
    for (const py::handle t : threading.attr("enumerate")()) {
      const py::object id = t.attr("ident");
      if (!id.is_none() && id.cast<unsigned long>() == ident) return py::str(t.attr("name")).cast<std::string>();
    }
  } catch (const py::error_already_set&) {
    // an interpreter shutting down: the ident still names it
  }
  return fmt::format("<ident {}>", ident);
}

}  // namespace

CallLock::Entered CallLock::enter(std::string call, Access access) {
  const unsigned long me = PyThread_get_thread_ident();
  std::optional<Caller> other;
  {
    const std::lock_guard<std::mutex> hold(mutex_);
    for (const Caller& c : callers_) {
      const bool refused = c.thread != me ? c.access == Access::write || access == Access::write
                                          : c.in_callback && access == Access::write;
      if (refused) {
        other = c;
        break;
      }
    }
    if (!other) {
      callers_.push_back(Caller{next_id_, me, std::move(call), access});
      return Entered(this, next_id_++);
    }
  }
  const std::string theirs = thread_name(other->thread);
  if (other->thread == me)
    throw Busy(fmt::format("{} from the progress callback of {} (thread '{}'): refused: a callback may read the "
                           "simulation (sim.t, sim.u, sim.report, ...) but not step, checkpoint or finish it "
                           "while {} is in progress",
                           call, other->call, theirs, other->call),
               other->call, theirs);
  throw Busy(fmt::format("{} in thread '{}': refused: {} is in progress in thread '{}'; a Simulation is driven from "
                         "one thread at a time (docs/python.md, \"Threads\"): wait until that call returns, or give "
                         "each thread its own Simulation",
                         call, thread_name(me), other->call, theirs),
             other->call, theirs);
}

CallLock::Callback CallLock::callback(const Entered& e) {
  set_callback(e.id_, true);
  return Callback(this, e.id_);
}

CallLock::Entered::~Entered() {
  if (lock_) lock_->leave(id_);
}

CallLock::Callback::~Callback() {
  if (lock_) lock_->set_callback(id_, false);
}

void CallLock::leave(std::uint64_t id) {
  const std::lock_guard<std::mutex> hold(mutex_);
  std::erase_if(callers_, [id](const Caller& c) { return c.id == id; });
}

void CallLock::set_callback(std::uint64_t id, bool on) {
  const std::lock_guard<std::mutex> hold(mutex_);
  for (Caller& c : callers_)
    if (c.id == id) c.in_callback = on;
}

namespace {

/// `with sim._hold("Simulation.run()") as held:` the lock held as a write across Python
/// code; `with held.callback():` around the user's code inside it. C++ context managers:
/// `with` enters and arms the exit in one step, so Ctrl-C cannot leave the lock held.
class Hold {
 public:
  Hold(py::object owner, CallLock& lock, std::string call)
      : owner_(std::move(owner)), lock_(lock), call_(std::move(call)) {}
  void enter() {
    if (entered_) throw std::logic_error("vpcontact: a hold of the call lock entered twice");
    entered_.emplace(lock_.enter(call_, CallLock::Access::write));
  }
  void exit() {
    callback_.reset();
    entered_.reset();
  }
  void callback_enter() {
    if (!entered_) throw std::logic_error("vpcontact: a callback outside its call");
    callback_.emplace(lock_.callback(*entered_));
  }
  void callback_exit() { callback_.reset(); }

 private:
  py::object owner_;  // keeps the lock's owner (the Simulation) alive
  CallLock& lock_;
  std::string call_;
  std::optional<CallLock::Entered> entered_;
  std::optional<CallLock::Callback> callback_;
};

struct CallbackScope {
  py::object hold;  // a Hold
};

}  // namespace

py::object hold(py::handle owner, CallLock& lock, std::string call) {
  return py::cast(Hold(py::reinterpret_borrow<py::object>(owner), lock, std::move(call)));
}

void bind_call_lock(py::module_& m) {
  py::class_<Hold>(m, "_Hold")
      .def("__enter__", [](py::handle self) {
        self.cast<Hold&>().enter();
        return py::reinterpret_borrow<py::object>(self);
      })
      .def("__exit__", [](Hold& h, const py::args&) {
        h.exit();
        return false;
      })
      .def("callback", [](py::handle self) { return CallbackScope{py::reinterpret_borrow<py::object>(self)}; },
           "A context manager around the user's code run inside the call (a progress callback).");
  py::class_<CallbackScope>(m, "_CallbackScope")
      .def("__enter__", [](const CallbackScope& c) { c.hold.cast<Hold&>().callback_enter(); })
      .def("__exit__", [](const CallbackScope& c, const py::args&) {
        c.hold.cast<Hold&>().callback_exit();
        return false;
      });
}

}  // namespace vpc::python
