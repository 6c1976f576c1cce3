#pragma once
// The pieces of the extension module vpcontact._core (docs/python.md), one job each:
//   errors.cpp      vpc::Error -> vpcontact.CaseError / RunError (with file, line, key)
//   case.cpp        Case: a case file or a built-in case with its overrides
//   arrays.cpp      read-only numpy views of C++ memory, kept alive by their owner
//   simulation.cpp  Simulation: the library's run loop (RunLoop) stepped from Python,
//                   with views of the state and the mesh, and the constant matrices
//   call_lock.cpp   one caller of a Simulation at a time (vpcontact.BusyError otherwise)
#include "cases/builtin_cases.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vpc::python {

namespace py = pybind11;

/// What Python says a case is: its source (a file or a built-in case) and the changes
/// to its keys, applied by the library's case reader (load_case) each time it is built.
struct CaseSpec {
  std::string given;             // the name or file as given
  CaseSource source;
  CaseOverrides overrides{};
  std::optional<int> cells{};    // --n: cells per edge of a generated mesh

  /// The case as the command line builds it (vpc::load_case, its mesh included).
  Case load() const;
  /// load(), once for these overrides (for the case's properties).
  const Case& built() const;
  mutable std::shared_ptr<const Case> cache{};
};

/// A read-only array of `shape` over `data` (C order), whose base `owner` keeps it alive.
template <typename T>
py::array view(const T* data, std::vector<py::ssize_t> shape, py::handle owner);

void bind_errors(py::module_& m);
void bind_case(py::module_& m);
void bind_simulation(py::module_& m);

}  // namespace vpc::python
