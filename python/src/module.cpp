// vpcontact._core: the C++ half of the Python module vpcontact (docs/python.md).
#include "bindings.hpp"
#include "call_lock.hpp"

#include "io/build_info.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "vpcontact's C++ library: cases, the run loop, views of the state (docs/python.md)";
  m.attr("__version__") = vpc::version();
  m.attr("git_commit") = vpc::git_commit();
  vpc::python::bind_errors(m);
  vpc::python::bind_case(m);
  vpc::python::bind_call_lock(m);
  vpc::python::bind_simulation(m);
}
