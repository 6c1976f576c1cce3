// vpc::Error as a Python exception: vpcontact.CaseError (a ValueError: a bad case,
// override or option) or, for vpc::CollectiveError (a failed step, no checkpoint to
// resume from), vpcontact.RunError (a RuntimeError). vpcontact/errors.py makes them
// from the message and reads its location (file, line, column, key) from it. A call refused
// by a Simulation's CallLock (another call in progress) is vpcontact.BusyError.
#include "bindings.hpp"
#include "call_lock.hpp"

#include "core/error.hpp"

#include <exception>

namespace vpc::python {

namespace {

void raise(const char* kind, const std::string& message) {
  const py::object error = py::module_::import("vpcontact.errors").attr("from_message")(message, kind);
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(error.ptr())), error.ptr());
}

}  // namespace

void bind_errors(py::module_&) {
  py::register_exception_translator([](std::exception_ptr p) {
    if (!p) return;
    try {
      std::rethrow_exception(p);
    } catch (const Busy& e) {
      const py::object error = py::module_::import("vpcontact.errors").attr("BusyError")(e.what(), e.call, e.thread);
      PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(error.ptr())), error.ptr());
    } catch (const CollectiveError& e) {
      raise("run", e.what());
    } catch (const Error& e) {
      raise("case", e.what());
    }
  });
}

}  // namespace vpc::python
