// Case: a case file or a built-in case and the changes to its keys. The case is built
// (read, checked, meshed) by the library's case reader at once and after every change,
// which raises the command line's located errors (vpcontact.CaseError); a Simulation
// builds it again, as the command line does.
#include "bindings.hpp"

#include <pybind11/stl.h>

#include <filesystem>

namespace vpc::python {

Case CaseSpec::load() const {
  MeshRequest request;
  request.cells = cells;
  return load_case(source, overrides, request);
}

const Case& CaseSpec::built() const {
  if (!cache) cache = std::make_shared<const Case>(load());
  return *cache;
}

namespace {

/// The changed spec, kept only if the case builds without error.
template <typename Change>
void change(CaseSpec& spec, Change&& edit) {
  CaseSpec changed = spec;
  edit(changed);
  changed.cache.reset();
  {
    py::gil_scoped_release release;
    changed.built();
  }
  spec = std::move(changed);
}

std::string output_directory(const CaseSpec& spec) {
  const CaseInfo info = case_info(spec.source.text, spec.source.name, spec.overrides);
  if (!info.output_directory.empty()) return info.output_directory;
  return (std::filesystem::path("output") / (spec.source.builtin ? spec.given : info.name)).string();
}

}  // namespace

void bind_case(py::module_& m) {
  m.def("builtin_cases", &builtin_case_names, "The names of the built-in cases.");
  m.def("case_text", [](const std::string& name) { return case_source(name).text; },
        "The TOML of a built-in case (vpcontact cases --show NAME).");

  py::class_<CaseSpec>(m, "Case", py::dynamic_attr())
      .def(py::init([](const CaseSpec& other) { return other; }), py::arg("case"))
      .def(py::init([](const std::string& name_or_file, std::optional<std::string> text, const std::string& base_dir) {
             CaseSpec s{name_or_file, text ? CaseSource{*text, name_or_file, base_dir, false} : case_source(name_or_file)};
             s.built();
             return s;
           }),
           py::arg("name_or_file"), py::arg("text") = py::none(), py::arg("base_dir") = ".")
      .def("_add_sets",
           [](CaseSpec& s, const std::vector<std::string>& sets) {
             change(s, [&](CaseSpec& c) { c.overrides.sets.insert(c.overrides.sets.end(), sets.begin(), sets.end()); });
           })
      .def_property_readonly("text", [](const CaseSpec& s) { return s.source.text; })
      .def_property_readonly("source", [](const CaseSpec& s) { return s.source.name; })
      .def_property_readonly("given", [](const CaseSpec& s) { return s.given; })
      .def_property_readonly("builtin", [](const CaseSpec& s) { return s.source.builtin; })
      .def_property_readonly("name", [](const CaseSpec& s) { return s.built().name; })
      .def_property_readonly("description", [](const CaseSpec& s) { return s.built().description; })
      .def_property_readonly("sets", [](const CaseSpec& s) { return s.overrides.sets; })
      .def_property_readonly("output_directory", &output_directory,
                             "Where run() writes by default: [output] directory, else output/NAME.")
      .def_property(
          "n", [](const CaseSpec& s) { return s.cells; },
          [](CaseSpec& s, std::optional<int> n) { change(s, [&](CaseSpec& c) { c.cells = n; }); },
          "Cells per edge of a generated mesh (--n): n along every edge, whatever the domain's aspect (a 2 x 1 "
          "rectangle gets n x n cells, stretched 2:1; set mesh.cells = [2n, n] for square ones); None: the case's "
          "own.")
      .def_property_readonly("kappa", [](const CaseSpec& s) { return s.built().problem->kappa; })
      .def_property_readonly("steps",
                             [](const CaseSpec& s) -> std::optional<int> {
                               const Problem& p = *s.built().problem;
                               if (p.step_control) return std::nullopt;  // error-controlled: not known before the run
                               return p.n_steps;
                             })
      .def_property_readonly("dt", [](const CaseSpec& s) { return s.built().problem->step(); })
      .def_property_readonly("dim", [](const CaseSpec& s) { return s.built().problem->mesh.dim(); })
      .def_property_readonly("n_nodes", [](const CaseSpec& s) { return s.built().problem->mesh.n_nodes(); })
      .def_property_readonly("n_cells", [](const CaseSpec& s) { return s.built().problem->mesh.n_cells(); })
      .def_property_readonly("final_time", [](const CaseSpec& s) { return s.built().problem->final_time; });
}

}  // namespace vpc::python
