// [output] (directory, every or times, fields, probes, VTU encoding) and [solver] (the contact and
// damage solvers, the residual tolerance).
#include "io/case_readers.hpp"

#include "io/run_output.hpp"
#include "scheme/solver_choice.hpp"
#include "core/error.hpp"
#include "core/quote.hpp"
#include "io/state_fields.hpp"
#include "scheme/surface_fields.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <set>

namespace vpc::case_file {

namespace {

/// The names of the contact laws' per-node state (SurfaceVariable), each checked not to be one of the
/// state's own fields (a VTU array or a stored field of io/state_fields.hpp), located at [contact].
std::vector<std::string> surface_names(const Problem& p) {
  std::vector<std::string> names;
  for (const SurfaceVariable& v : declared_surface_state(p.contact)) {
    const bool taken = std::ranges::any_of(state_fields(), [&](const StateField& f) {
      return f.name == v.name || f.vtu == v.name || f.python == v.name;
    });
    if (taken || v.name == "damage")
      fail("{}: a contact law declares the per-node state '{}', the name of one of the state's own fields; a law's "
           "state needs a name of its own",
           p.where("contact"), v.name);
    names.push_back(v.name);
  }
  return names;
}

std::vector<std::string> read_fields(Section& out, const std::vector<std::string>& surface) {
  std::vector<std::string> fields = out.strings("fields");
  for (auto& f : fields) {
    const std::string field = OutputOptions::field(f, surface);  // "damage": the old name of "beta"
    if (field.empty()) {
      std::vector<std::string> names = OutputOptions::field_names();
      names.insert(names.end(), surface.begin(), surface.end());
      fail("{}: unknown field {}; expected some of: {}{}", out.where("fields"), quote(f), fmt::join(names, ", "),
           did_you_mean(f, std::set<std::string>(names.begin(), names.end())));
    }
    f = field;
  }
  return fields;
}

/// [output] fields may name only fields the case's VTU files can have: a field its files would never
/// hold (VTU files with no array) is refused, located at the key. gap: cases with contact pairs;
/// friction's fields (StateField::friction): a friction law or wear somewhere; contact_lambda: more than
/// one contact unknown per node.
void check_fields_written(Section& out, const std::vector<std::string>& fields, const Problem& p) {
  const bool frictional = p.contact.tangential();  // wear keeps the slip fields too
  for (const std::string& f : fields) {
    const auto field = std::ranges::find(state_fields(), f, &StateField::vtu);
    if (f == "gap" && p.contact.pairs.empty())
      fail("{}: the field \"gap\" is written only for cases with contact pairs ([[contact.pair]]); this case has none",
           out.where("fields"));
    if (field != state_fields().end() && field->friction && !frictional)
      fail("{}: the field {} is written only for frictional cases (a friction law or wear in [contact], a "
           "[[contact.part]] or a [[contact.pair]]); this case is frictionless",
           out.where("fields"), quote(f));
    if (f == "contact_lambda" && p.contact.block_size(p.mesh.dim()) == 1)
      fail("{}: the field \"contact_lambda\" is written only where λ has more than one number per contact node "
           "(frictional cases); this case has one, the normal force (see contact_force and contact_pressure)",
           out.where("fields"));
  }
}

std::vector<Point> read_probes(Section& out, int d) {
  std::vector<Point> probes;
  for (const auto& pt : out.array("probes", "an array of points, e.g. [[0.25], [1.0]]")) {
    if (!pt.is_array() || static_cast<int>(pt.as_array()->size()) != d)
      fail("{}: expected each probe to be an array of {} numbers", out.where("probes"), d);
    Point x{0, 0, 0};
    for (int i = 0; i < d; ++i) {
      const toml::node& v = (*pt.as_array())[i];
      if (!v.is_number() || !std::isfinite(number_value(v)))
        fail("{}: expected finite numbers in probe coordinates", out.where("probes"));
      x[i] = number_value(v);
    }
    probes.push_back(x);
  }
  return probes;
}

/// With error-controlled steps, VTU `every` steps of the fixed grid that a tolerance
/// override replaced (the file's steps or dt): the times that grid writes at, so that
/// the run writes as many files as the fixed run. Without such a grid (the file's own
/// steps are error-controlled) the number of steps, and so of files, is not known
/// before the run: refused.
std::vector<double> every_as_times(Section& out, const Problem& p, int every) {
  const Origins& origins = out.origins();
  if (origins.replaced_grid.empty())
    fail("{}: counts the steps of a fixed grid, but [time] tolerance chooses the steps during the run (their number, "
         "and the files', is not known before it): give times = [...] (the steps end at them), or every = 0 (the "
         "final state only)",
         out.where("every"));
  toml::table time = origins.replaced_grid;
  time.insert_or_assign("T", p.final_time);
  if (time.contains("dt") && !p.step_control->landings.empty()) {
    toml::array breakpoints;
    for (double b : p.step_control->landings) breakpoints.push_back(b);
    time.insert_or_assign("breakpoints", breakpoints);
  }
  Problem grid;
  try {
    read_time(Section(&time, "time", origins), grid, origins.file);
  } catch (const Error& e) {
    fail("{}: counts the steps of the fixed grid that {} replaced, which is not valid: {}", out.where("every"),
         origins.of("time.tolerance"), e.what());
  }
  std::vector<double> times;
  for (int n = every; n <= grid.n_steps; n += every) times.push_back(grid.time_at(n));
  return times;
}

}  // namespace

/// [output]; by default every tenth of the run.
OutputOptions read_output(Section out, Problem& p) {
  OutputOptions o;
  o.directory = out.string("directory", "");
  if (out.has("every") && out.has("times")) fail("{}: give either every or times, not both", out.where_section());
  // By default every tenth of the run: every N/10 steps, or (error-controlled steps) at t = T/10, 2T/10, …
  const bool controlled = p.step_control.has_value();
  o.every = out.integer("every", controlled ? 0 : std::max(1, p.n_steps / 10));
  if (o.every < 0) fail("{}: expected every >= 0", out.where("every"));
  if (out.has("times")) {
    o.times = out.numbers("times", 0);
    for (double t : o.times)
      if (t < 0 || t > p.final_time) fail("{}: output time {} is outside [0, T = {}]", out.where("times"), t, p.final_time);
  } else if (controlled && !out.has("every")) {
    for (int i = 1; i <= 10; ++i) o.times.push_back(p.final_time * i / 10);
  } else if (controlled && o.every > 0) {
    o.times = every_as_times(out, p, o.every);
    o.every = 0;
  }
  // Error-controlled steps end exactly at the output times.
  if (controlled) p.step_control->landings.insert(p.step_control->landings.end(), o.times.begin(), o.times.end());
  o.vtu = out.boolean("vtu", true);
  const std::vector<std::string> surface = surface_names(p);
  if (out.has("fields")) o.fields = read_fields(out, surface);
  check_fields_written(out, o.fields, p);
  o.encoding.compression = vtu_compression(out.choice("compression", {"zlib", "none"}, "zlib"));
  if (out.has("probes")) o.probes = read_probes(out, p.mesh.dim());
  // A probe must lie in the body (on a rank without the mesh: rank 0 checks it; on a block: all ranks
  // together, validate_blocks).
  for (std::size_t i = 0; i < o.probes.size() && p.mesh.n_cells() > 0; ++i) {
    const std::string where = fmt::format("{}[{}]", out.where("probes"), i);
    if (p.block)
      p.block->probes.emplace_back(o.probes[i], where);
    else
      located(where, [&] { (void)locate_point(p.mesh, o.probes[i]); });
  }
  out.finish();
  return o;
}

SolverChoice read_solver(Section sv) {
  SolverChoice s;
  s.contact = sv.choice("contact", kContactSolverNames, kContactSolverNames.front());
  s.damage = sv.choice("damage", {"active-set", "penalty-duality"}, "active-set");
  s.residual_tolerance = sv.positive("tolerance", 1e-8);
  sv.finish();
  return s;
}

}  // namespace vpc::case_file
