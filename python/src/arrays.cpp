// Read-only numpy views of C++ memory. The array's base is the Python object that owns
// the memory (a Simulation), so the memory lives as long as any view of it. Read-only:
// writing into the state behind the solvers' backs would break their warm starts.
#include "bindings.hpp"

#include "core/sym_tensor.hpp"

namespace vpc::python {

template <typename T>
py::array view(const T* data, std::vector<py::ssize_t> shape, py::handle owner) {
  py::array_t<T> a(std::move(shape), data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

template py::array view<double>(const double*, std::vector<py::ssize_t>, py::handle);
template py::array view<int>(const int*, std::vector<py::ssize_t>, py::handle);

// The layouts the views rely on: a SymTensor is 6 doubles, a Point 3.
static_assert(sizeof(SymTensor) == 6 * sizeof(double));
static_assert(sizeof(Point) == 3 * sizeof(double));

}  // namespace vpc::python
