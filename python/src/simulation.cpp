// Simulation: the library's run loop (run/run_case.hpp: set_up_serial, then RunLoop)
// stepped from Python, as `vpcontact run` runs it: the same set-up, steps, output files
// and checkpoints. What Python sees of it: the step reports as history.csv's numbers
// (io/history_columns.hpp), read-only numpy views of the state's fields (io/state_fields.hpp:
// never copies, they follow the steps) and the mesh, copies of the output fields, and the
// constant matrices. Every call enters the Simulation's CallLock (call_lock.hpp): one caller
// at a time.
#include "bindings.hpp"
#include "call_lock.hpp"

#include "core/error.hpp"
#include "io/history_columns.hpp"
#include "io/state_fields.hpp"
#include "la/operator.hpp"
#include "run/run_case.hpp"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <type_traits>

namespace vpc::python {

namespace {

struct SimulationOptions {
  std::optional<std::string> output;  // the output directory; none: no files, no checkpoints
  bool resume = false;                // continue from the newest good checkpoint in `output`
  bool quiet = true;                  // the command line's header, set-up stages and progress bar
  int checkpoint_every = -1;          // RunOptions
  double checkpoint_seconds = 60;
  int halvings = 0;
};

/// The arrays of one mesh of a run, the base (numpy's `.base`) of the views taken of it: the live
/// stepper's while it runs (the engine kept alive through it, as the views keep it), then, once an
/// adaptation replaces that mesh ([adapt]), its state moved here unchanged (the same addresses) and
/// `stale` set. So a view never dangles: it shows the mesh and step it was taken of until it goes.
struct MeshGeneration {
  int version = 0;                   // the meshes replaced before this one (Simulation.mesh_version)
  std::shared_ptr<Run> engine;       // while live
  std::shared_ptr<const Mesh> mesh;  // the mesh views' arrays
  std::unique_ptr<State> state;      // once retired
  bool stale = false;
};

class Simulation {
 public:
  Simulation(const CaseSpec& spec, const SimulationOptions& so) {
    RunOptions o;
    o.quiet = so.quiet;
    const Case& info = spec.built();
    o.header = fmt::format("vpcontact: {} — {}", spec.source.builtin ? spec.given : info.name, info.description);
    output_ = so.output;
    if (so.output) o.output_directory = *so.output;
    o.files = so.output.has_value();
    if (so.resume) {
      require(so.output.has_value(), "resume=True needs the output directory of the run to resume (output=...)");
      o.resume = *so.output;
    }
    require(so.checkpoint_every >= -1,
            "checkpoint_every must be a number of steps >= 0 (0: checkpoints at the start and the end only) or "
            "-1 (by wall time: checkpoint_seconds) (got {})",
            so.checkpoint_every);
    require(std::isfinite(so.checkpoint_seconds) && so.checkpoint_seconds > 0,
            "checkpoint_seconds must be a finite number of seconds > 0 (got {})", so.checkpoint_seconds);
    o.checkpoint_every = so.checkpoint_every;
    o.checkpoint_seconds = so.checkpoint_seconds;
    require(so.halvings >= 0 && so.halvings <= 20, "halvings must be in [0, 20] (got {})", so.halvings);
    o.halvings = so.halvings;
    o.argv = {"python3", "vpcontact.Simulation", spec.given};
    for (const std::string& s : spec.overrides.sets) o.argv.insert(o.argv.end(), {"--set", s});
    const auto started = std::chrono::system_clock::now();
    CaseLoader load = [spec, outdir = o.output_directory, argv = o.argv, started](const MeshRequest&) {
      Case c = spec.load();  // as vpcontact run's load_case
      c.output.directory = outdir;
      c.output.command_line = argv;
      c.output.started = started;
      return c;
    };
    py::gil_scoped_release release;
    engine_ = set_up_serial(load, o);
    require(engine_->stepper() != nullptr, "internal error: the engine has no stepper");
    // An adaptation retires the mesh the views were taken of: its state moves to their generation.
    engine_->on_retire([this](TimeStepper& old) {
      ++mesh_version_;
      if (current_ == nullptr || current_->stale) return;
      current_->state = std::make_unique<State>(old.take_state());
      current_->stale = true;
    });
    loop_.emplace(*engine_, o);
    columns_ = history_column_names(stepper().problem(), stepper().part(), spec.built().adapt.has_value());
    fields_ = field_addresses();
  }
  ~Simulation() {
    if (engine_) engine_->on_retire({});  // a live generation keeps the engine; nothing retires after this
  }
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// The current stepper (an adaptive run's changes at each adaptation).
  const TimeStepper& stepper() const { return *engine_->stepper(); }
  const State& state() const { return stepper().state(); }
  int mesh_version() const { return mesh_version_; }
  /// The base of views taken now: the current mesh's generation (made anew after an adaptation).
  py::object generation() {
    if (current_ == nullptr || current_->stale) {
      auto g = std::make_unique<MeshGeneration>();
      g->version = mesh_version_;
      g->engine = engine_;
      g->mesh = stepper().part().mesh_ptr;
      generation_ = py::cast(std::move(g));
      current_ = generation_.cast<MeshGeneration*>();
    }
    return generation_;
  }
  bool done() const { return loop_->done(); }
  bool finished() const { return loop_->finished(); }

  /// One step of the run loop: recorded, checkpointed as due; history.csv's numbers of it.
  void step() {
    require(!loop_->finished(), "the simulation is finished (finish() was called or a step failed)");
    require(!loop_->done(), "the simulation is at its final time (step {}, t = T = {})", state().n,
            stepper().problem().final_time);
    StepReport r;
    const int version_at_step = mesh_version_;
    {
      py::gil_scoped_release release;
      r = loop_->step();
    }
    // The views point into the state: a step must never move it (same-size assignments), but where an
    // adaptation replaced the mesh (the views taken before keep theirs: MeshGeneration).
    const auto now = field_addresses();
    const bool remeshed = mesh_version_ != version_at_step;
    for (std::size_t i = 0; i < now.size() && !remeshed; ++i)
      if (now[i].second != fields_[i].second)
        throw std::logic_error(fmt::format("vpcontact: the state's {} was reallocated by a step: views taken before "
                                           "it are stale",
                                           fields_[i].first));
    fields_ = now;
    rows_.push_back(history_values(r));
  }

  void checkpoint() {
    require(output_.has_value(), "checkpoint() needs an output directory: Simulation(case, output=...)");
    require(!loop_->finished(), "the simulation is finished: no checkpoint");
    py::gil_scoped_release release;
    loop_->checkpoint();
  }
  void finish() {
    py::gil_scoped_release release;
    loop_->finish();
  }

  const std::vector<std::string>& history_columns() const { return columns_; }
  /// The reports so far: one list of numbers per step (ints where history.csv writes
  /// integers), history_columns' order.
  const std::vector<std::vector<HistoryValue>>& rows() const { return rows_; }
  const RunLoop& loop() const { return *loop_; }
  /// The output directory; None: a run without files.
  const std::optional<std::string>& output() const { return output_; }
  /// The lock every call of the binding enters (a lock is state of its own, not the simulation's).
  CallLock& calls() const { return calls_; }

 private:
  /// Where each stored field's numbers are (the views point there).
  std::vector<std::pair<std::string_view, const double*>> field_addresses() const {
    std::vector<std::pair<std::string_view, const double*>> a;
    for (const StateField& f : state_fields())
      if (f.stored()) a.emplace_back(f.name, f.values(state()).data());
    return a;
  }

  std::shared_ptr<Run> engine_;
  int mesh_version_ = 0;
  py::object generation_;              // the current mesh's MeshGeneration (none before a view)
  MeshGeneration* current_ = nullptr;  // its object
  std::optional<RunLoop> loop_;
  std::vector<std::pair<std::string_view, const double*>> fields_;
  std::vector<std::string> columns_;
  std::vector<std::vector<HistoryValue>> rows_;
  std::optional<std::string> output_;
  mutable CallLock calls_;
};

/// A matrix as the arrays of scipy.sparse.csc_matrix((data, indices, indptr), shape).
py::tuple csc(SparseMatrix A) {
  A.makeCompressed();
  const auto nnz = static_cast<py::ssize_t>(A.nonZeros());
  py::array_t<double> data(nnz, A.valuePtr());
  py::array_t<int> indices(nnz, A.innerIndexPtr());
  py::array_t<int> indptr(static_cast<py::ssize_t>(A.outerSize()) + 1, A.outerIndexPtr());
  return py::make_tuple(data, indices, indptr, py::make_tuple(A.rows(), A.cols()));
}

template <typename T>
py::array copy(const std::vector<T>& v) {
  return py::array_t<T>(static_cast<py::ssize_t>(v.size()), v.data());
}

/// A report's numbers as Python numbers: ints where history.csv writes integers.
py::list numbers(const std::vector<HistoryValue>& row) {
  py::list out;
  for (const HistoryValue& v : row)
    if (v.format == ColumnFormat::integer)
      out.append(py::int_(static_cast<long long>(v.value)));
    else
      out.append(py::float_(v.value));
  return out;
}

/// The shape of a field's array: one axis for a field of one number per entity whatever
/// the dimension (beta, lambda of a normal law), else (entities, components).
std::vector<py::ssize_t> shape(const StateField& f, const State& s, int d, std::size_t values) {
  const int c = f.components(s, d);
  const bool scalar = f.components(s, 1) == 1 && f.components(s, 3) == 1;
  if (scalar || c == 0) return {static_cast<py::ssize_t>(values)};  // c = 0: friction's fields without friction
  return {static_cast<py::ssize_t>(values / static_cast<std::size_t>(c)), c};
}

/// The table of the state's fields (io/state_fields.hpp) for the Python package.
py::list field_table() {
  py::list out;
  for (const StateField& f : state_fields()) {
    py::dict e;
    e["name"] = std::string(f.name);
    e["python"] = std::string(f.python);
    e["vtu"] = std::string(f.vtu);
    e["location"] = location_name(f.location);
    e["stored"] = f.stored();
    e["meaning"] = std::string(f.meaning);
    e["friction"] = f.friction;
    out.append(e);
  }
  return out;
}

/// The table of history.csv's fixed columns (io/history_columns.hpp), then those of a
/// frictional run (friction: True).
py::list column_table() {
  py::list out;
  auto add = [&](std::span<const HistoryColumn> columns, bool friction) {
    for (const HistoryColumn& c : columns) {
      py::dict e;
      e["name"] = std::string(c.name);
      e["format"] = c.format == ColumnFormat::integer ? "integer" : c.format == ColumnFormat::exact ? "exact" : "residual";
      e["meaning"] = std::string(c.meaning);
      e["friction"] = friction;
      out.append(e);
    }
  };
  add(history_columns(), false);
  add(friction_columns(), true);
  return out;
}

/// The binding of `f` (given the Simulation, or its Python object where a view needs it as
/// its base) as the Simulation's `call`: `f` runs inside the call lock (call_lock.hpp).
template <typename F>
auto locked(CallLock::Access access, std::string call, F f) {
  return [access, call = "Simulation." + std::move(call), f](py::handle self) {
    Simulation& s = self.cast<Simulation&>();
    const CallLock::Entered entered = s.calls().enter(call, access);
    if constexpr (std::is_invocable_v<F, Simulation&>)
      return std::invoke(f, s);
    else
      return std::invoke(f, self);
  };
}
template <typename F>
auto reads(std::string call, F f) {
  return locked(CallLock::Access::read, std::move(call), f);
}
template <typename F>
auto writes(std::string call, F f) {
  return locked(CallLock::Access::write, std::move(call), f);
}

}  // namespace

void bind_simulation(py::module_& m) {
  using S = Simulation;
  auto sim = [](py::handle self) -> S& { return self.cast<S&>(); };

  py::class_<S>(m, "Simulation")
      .def(py::init([](const CaseSpec& spec, std::optional<std::string> output, bool resume, bool quiet,
                       int checkpoint_every, double checkpoint_seconds, int halvings) {
             return std::make_unique<S>(
                 spec, SimulationOptions{output, resume, quiet, checkpoint_every, checkpoint_seconds, halvings});
           }),
           py::arg("case"), py::arg("output") = py::none(), py::arg("resume") = false, py::arg("quiet") = true,
           py::arg("checkpoint_every") = -1, py::arg("checkpoint_seconds") = 60.0, py::arg("halvings") = 0)
      .def("_hold", [sim](py::handle self, std::string call) { return hold(self, sim(self).calls(), std::move(call)); },
           "A context manager holding the call lock for `call` (a write) while its block runs.")
      .def("_step", writes("_step()", &S::step))
      .def("checkpoint", writes("checkpoint()", &S::checkpoint),
           "Writes a checkpoint of the state now (output directory needed).")
      .def("finish", writes("finish()", &S::finish), "Ends the run: writes summary.json (once); no step after it.")
      .def_property_readonly("done", reads("done", &S::done), "Whether the last step is reached.")
      .def_property_readonly("finished", reads("finished", &S::finished))
      .def_property_readonly("output", reads("output", &S::output), "The output directory (None: no files).")
      .def_property_readonly("n", reads("n", [](const S& s) { return s.state().n; }), "The step reached.")
      .def_property_readonly("t", reads("t", [](const S& s) { return s.state().t; }), "Its time t_n.")
      .def_property_readonly("n_steps",
                             reads("n_steps",
                                   [](const S& s) -> std::optional<int> {
                                     const Problem& p = s.stepper().problem();
                                     if (p.step_control) return std::nullopt;
                                     return p.n_steps;
                                   }),
                             "N of a fixed grid; None with error-controlled steps (their number is known only "
                             "at the end: sim.n is the number taken so far).")
      .def_property_readonly("final_time",
                             reads("final_time", [](const S& s) { return s.stepper().problem().final_time; }))
      .def_property_readonly("kappa", reads("kappa", [](const S& s) { return s.stepper().problem().kappa; }))
      .def_property_readonly("last_checkpoint",
                             reads("last_checkpoint", [](const S& s) { return s.loop().last_checkpoint(); }))
      .def_property_readonly("wall_seconds",
                             reads("wall_seconds", [](const S& s) { return s.loop().result().wall_seconds; }),
                             "The run's wall time, set by finish().")
      .def_property_readonly("setup_seconds",
                             reads("setup_seconds", [](const S& s) { return s.stepper().setup_seconds(); }))
      .def_property_readonly("contact_solver",
                             reads("contact_solver", [](const S& s) { return s.stepper().contact_solver(); }))
      .def_property_readonly("frictional", reads("frictional", [](const S& s) { return s.state().contact_block > 1; }),
                             "Whether the run has friction (contact_force then holds lambda_nu and the "
                             "tangential forces per node; the friction fields and history columns exist).")
      .def_property_readonly("_history_columns", reads("history_columns", &S::history_columns))
      .def_property_readonly("_rows", reads("history()",
                                            [](const S& s) {
                                              py::list rows;
                                              for (const auto& r : s.rows()) rows.append(numbers(r));
                                              return rows;
                                            }))
      .def_property_readonly("_last_row", reads("report",
                                                [](const S& s) -> py::object {
                                                  if (s.rows().empty()) return py::none();
                                                  return numbers(s.rows().back());
                                                }))
      // The mesh (the whole mesh: one process).
      .def_property_readonly("dim", reads("dim", [](const S& s) { return s.stepper().mesh().dim(); }))
      .def_property_readonly("points",
                             reads("points",
                                   [sim](py::handle self) {
                                     const Mesh& mesh = sim(self).stepper().mesh();
                                     return view(mesh.nodes().front().data(), {mesh.n_nodes(), 3}, sim(self).generation());
                                   }),
                             "The nodes' coordinates, (n_nodes, 3) (unused coordinates 0).")
      .def_property_readonly("cells",
                             reads("cells",
                                   [sim](py::handle self) {
                                     const Mesh& mesh = sim(self).stepper().mesh();
                                     return view(mesh.cell_array().data(),
                                                 {mesh.n_cells(), mesh.nodes_per_cell()}, sim(self).generation());
                                   }),
                             "The cells' nodes, (n_cells, d + 1).")
      .def_property_readonly("facets",
                             reads("facets",
                                   [sim](py::handle self) {
                                     const Mesh& mesh = sim(self).stepper().mesh();
                                     return view(mesh.n_facets() ? mesh.facet(0) : nullptr,
                                                 {mesh.n_facets(), mesh.nodes_per_facet()}, sim(self).generation());
                                   }),
                             "The boundary facets' nodes, (n_facets, d).")
      .def_property_readonly("facet_parts",
                             reads("facet_parts",
                                   [](const S& s) {
                                     const Mesh& mesh = s.stepper().mesh();
                                     std::vector<int> part(mesh.n_facets());
                                     for (int f = 0; f < mesh.n_facets(); ++f) part[f] = mesh.facet_part(f);
                                     return copy(part);
                                   }),
                             "Each facet's part (an index into part_names; -1: none), a copy.")
      .def_property_readonly("part_names",
                             reads("part_names", [](const S& s) { return s.stepper().mesh().part_names(); }))
      // The state's fields are added from their table below.
      .def_property_readonly("contact_nodes",
                             reads("contact_nodes",
                                   [](const S& s) {
                                     const std::vector<PartContactNode>& nodes = s.stepper().contact().nodes;
                                     std::vector<int> node(nodes.size());
                                     for (const PartContactNode& c : nodes) node.at(c.row) = c.local_node;
                                     return copy(node);
                                   }),
                             "The node of each contact row (of N and contact_force), a copy.")
      .def_property_readonly("contact_directions",
                             reads("contact_directions",
                                   [](const S& s) {
                                     const std::vector<PartContactNode>& nodes = s.stepper().contact().nodes;
                                     py::array_t<double> a({static_cast<py::ssize_t>(nodes.size()), py::ssize_t{3}});
                                     auto w = a.mutable_unchecked<2>();
                                     for (const PartContactNode& c : nodes)
                                       for (int i = 0; i < 3; ++i) w(c.row, i) = c.direction[i];
                                     return a;
                                   }),
                             "The contact direction nu at each contact node, (n_contact, 3), a copy.")
      .def_property_readonly("free_dofs",
                             reads("free_dofs",
                                   [](const S& s) {
                                     const DofMap& dofs = s.stepper().dofs();
                                     std::vector<int> full;
                                     for (int i = 0; i < dofs.n_full(); ++i)
                                       if (dofs.free_index(i) >= 0) full.push_back(i);
                                     return copy(full);
                                   }),
                             "The index in u.ravel() of each free dof (the rows of K and the columns of N).")
      .def("_matrices", reads("matrices()", [](const S& s) {
             const TimeStepper& ts = s.stepper();
             const SparseMatrix* K = ts.stiffness_operator().whole_matrix();
             require(K != nullptr, "K is not an Eigen sparse matrix (not the serial engine)");
             py::dict d;
             d["K"] = csc(*K);
             d["M"] = csc(ts.mass_matrix());
             d["A"] = csc(ts.laplacian_matrix());
             d["N"] = csc(ts.contact_rows());
             return d;
           }));
  // The state's fields (io/state_fields.hpp): views of the stored ones, copies of the
  // output fields made as the VTU files make them.
  auto cls = py::reinterpret_borrow<py::class_<S>>(m.attr("Simulation"));
  for (const StateField& f : state_fields()) {
    if (f.python.empty()) continue;
    const std::string doc = fmt::format("{} (per {}{})", f.meaning, location_name(f.location),
                                        f.stored() ? ", a read-only view" : ", a copy");
    const std::string name(f.python);
    if (f.stored())
      cls.def_property_readonly(name.c_str(), reads(name, [&f, sim](py::handle self) {
        S& s = sim(self);
        const std::span<const double> v = f.values(s.state());
        return view(v.data(), shape(f, s.state(), s.stepper().mesh().dim(), v.size()), s.generation());
      }), doc.c_str());
    else
      cls.def_property_readonly(name.c_str(), reads(name, [&f](const S& s) {
        const VtuField a = f.vtu_field({s.state(), s.stepper().part(), s.stepper().contact().nodes});
        py::array_t<double> out(shape(f, s.state(), s.stepper().mesh().dim(), a.values.size()));
        std::copy(a.values.begin(), a.values.end(), out.mutable_data());
        return out;
      }), doc.c_str());
  }
  // The contact laws' per-node state (State::surface, contact/surface_state.hpp): one read-only view
  // per declared variable, by name, in the rows' order (width > 1: one row per contact node).
  cls.def_property_readonly("surface", reads("surface", [sim](py::handle self) {
    S& s = sim(self);
    const py::object base = s.generation();
    py::dict d;
    for (const SurfaceField& f : s.state().surface) {
      const auto nodes = static_cast<py::ssize_t>(f.values.size() / f.width);
      d[py::str(f.name)] = view(f.values.data(),
                                f.width == 1 ? std::vector<py::ssize_t>{nodes} : std::vector<py::ssize_t>{nodes, f.width},
                                base);
    }
    return d;
  }), "The contact laws' per-node state (a law that keeps some declares it; empty otherwise): a dict of read-only "
      "views by name, one value (or row of values) per contact node in the rows' order, as contact_force");
  cls.def_property_readonly("mesh_version", reads("mesh_version", &S::mesh_version),
                            "The meshes an adaptation ([adapt]) has replaced so far: views taken before one keep "
                            "their mesh's arrays (their .base.stale is then True).");
  py::class_<MeshGeneration>(m, "MeshGeneration",
                             "The arrays of one mesh of a Simulation: the base of the views taken of it.")
      .def_property_readonly("mesh_version", [](const MeshGeneration& g) { return g.version; },
                             "The Simulation's mesh_version when the views were taken.")
      .def_property_readonly("stale", [](const MeshGeneration& g) { return g.stale; },
                             "True once an adaptation replaced this mesh: the views show it as it was then.");
  m.def("_state_fields", &field_table, "The table of the state's fields (io/state_fields.hpp).");
  m.def("_history_column_table", &column_table, "The table of history.csv's columns (io/history_columns.hpp).");
}

}  // namespace vpc::python
