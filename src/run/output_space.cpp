#include "run/output_space.hpp"

#include "core/error.hpp"
#include "io/history_columns.hpp"
#include "io/state_fields.hpp"
#include "la/memory_estimate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <system_error>

namespace vpc {

namespace fs = std::filesystem;

namespace {

/// The text of a number in a CSV row, with its comma: a residual ("{:.3e}": "1.234e-05"), an
/// exact number at its usual length ("{:.17g}": "-7.4370486818454324"; 0 and 1 are shorter,
/// "-1.2345678901234567e-05" longer).
constexpr double kResidualChars = 10, kExactChars = 20;

double digits(long long n) { return n < 10 ? 1 : 1 + std::floor(std::log10(static_cast<double>(n))); }

/// Bytes of one history.csv row: each column by how it is written (io/history_columns.hpp): the
/// step with the digits of the last, the other whole numbers (counts of nodes) with those of the
/// nodes; the per-case totals (forces, reactions) are exact numbers.
double history_row_bytes(const TimeStepper& s, long long last_step) {
  const MeshPart& part = s.part();
  auto width = [&](std::string_view name) {
    for (const auto table : {history_columns(), friction_columns(), open_friction_columns()})
      for (const HistoryColumn& c : table)
        if (c.name == name) {
          if (c.format == ColumnFormat::integer) return digits(name == "step" ? last_step : part.n_global_nodes) + 1;
          return c.format == ColumnFormat::residual ? kResidualChars : kExactChars;
        }
    return kExactChars;  // a per-case total
  };
  double row = 0;
  for (const std::string& name : history_column_names(s.problem(), part)) row += width(name);
  return row;
}

/// The VTU files written from step `from` on (step 0's with a fresh run; the last step's always).
long long vtu_files(const Problem& p, const OutputOptions& o, int from, long long last_step) {
  if (!o.vtu) return 0;
  const long long first = from == 0 ? 1 : 0;
  if (!o.times.empty()) return first + static_cast<long long>(o.times.size()) + 1;
  if (o.every > 0 && !p.step_control)
    return first + last_step / o.every - from / o.every + (last_step % o.every == 0 ? 0 : 1);
  if (o.every > 0) return first + 10;  // error-controlled: the default times T/10, …, T
  return first + 1;
}

/// Bytes of one VTU file's data, uncompressed (every process's piece together): the mesh and the
/// fields `o` asks for.
double vtu_bytes(const TimeStepper& s, const OutputOptions& o) {
  const MeshPart& part = s.part();
  const auto nodes = static_cast<double>(part.n_global_nodes), cells = static_cast<double>(part.n_global_cells);
  const int d = part.dofs.dim();
  double bytes = 4096 + nodes * 3 * 8 + cells * ((d + 1) * 8 + 8 + 1);  // XML, points, connectivity, offsets, types
  for (const StateField& f : state_fields()) {
    if (f.vtu.empty() || (f.in_vtu && !f.in_vtu(s.state()))) continue;
    const bool wanted = o.fields.empty() || std::any_of(o.fields.begin(), o.fields.end(), [&](const std::string& n) {
                          return OutputOptions::field(n) == f.vtu;
                        });
    if (wanted) bytes += 8.0 * f.components(s.state(), d) * (f.point_data() ? nodes : cells);
  }
  const Problem& p = s.problem();
  bytes += 4 * cells * ((!p.materials.empty() || !p.bodies.empty() ? 1 : 0) + (p.bodies.empty() ? 0 : 1));
  return bytes;
}

/// Bytes of one checkpoint: the stored fields, u on the free dofs, the solvers' warm states, the
/// time levels where they are stored (a grid that is not uniform), the run's data.
double checkpoint_bytes(const TimeStepper& s, long long last_step, long long files) {
  const MeshPart& part = s.part();
  const auto nodes = static_cast<double>(part.n_global_nodes), cells = static_cast<double>(part.n_global_cells),
             contact = static_cast<double>(part.n_contact);
  const int d = part.dofs.dim();
  double bytes = 8192;  // the header, the case's keys, the totals
  for (const StateField& f : state_fields())
    if (f.stored())
      bytes += 8.0 * f.components(s.state(), d) *
               (f.location == FieldLocation::node ? nodes : f.location == FieldLocation::cell ? cells : contact);
  bytes += 8 * (static_cast<double>(part.n_global_dofs) + nodes + contact * s.state().contact_block);
  if (!s.problem().uniform_steps()) bytes += 8 * static_cast<double>(last_step + 1);
  return bytes + 40 * static_cast<double>(files);  // the PVD entries
}

}  // namespace

OutputEstimate estimate_output(const TimeStepper& s, const OutputOptions& o, int from) {
  const Problem& p = s.problem();
  OutputEstimate e;
  e.steps_estimated = p.step_control.has_value();
  const long long last = p.expected_steps();
  e.steps = std::max<long long>(0, last - from);
  e.history_row = history_row_bytes(s, last);
  e.history = static_cast<double>(e.steps) * e.history_row + (from == 0 ? e.history_row * 2 : 0);  // + the header
  // A probes.csv row: n, t, then u, σ's components, |σ|_VM and β at each probe.
  const auto per_probe = static_cast<double>(s.part().dofs.dim() + tensor_components(p.elasticity).size() + 2);
  const double probe = digits(last) + 1 + kExactChars + static_cast<double>(o.probes.size()) * per_probe * kExactChars;
  e.probes = static_cast<double>(e.steps) * probe;
  e.vtu_files = vtu_files(p, o, from, last);
  // zlib keeps 41–60 % of a VTU file's data (docs/cases.md, [output] compression): counted as 60 %.
  const double kept = o.encoding.compression == VtuCompression::zlib ? 0.6 : 1.0;
  e.vtu = static_cast<double>(e.vtu_files) * vtu_bytes(s, o) * kept;
  e.checkpoints = 3 * checkpoint_bytes(s, last, e.vtu_files);  // the newest two and the one being written
  return e;
}

std::string OutputEstimate::describe() const {
  return fmt::format("about {} (history.csv {}: {}{} steps of {}; probes.csv {}; {} VTU file{} {}; checkpoints {})",
                     format_bytes(total()), format_bytes(history), steps_estimated ? "an estimated " : "", steps,
                     format_bytes(history_row), format_bytes(probes), vtu_files, vtu_files == 1 ? "" : "s",
                     format_bytes(vtu), format_bytes(checkpoints));
}

double free_space(const fs::path& dir) {
  std::error_code ec;
  fs::path at = fs::absolute(dir, ec);
  if (ec) return INFINITY;
  while (!fs::exists(at, ec) && at.has_parent_path() && at.parent_path() != at) at = at.parent_path();
  const fs::space_info info = fs::space(at, ec);
  return ec ? INFINITY : static_cast<double>(info.available);
}

std::string require_output_space(const OutputEstimate& e, double available, const fs::path& dir) {
  require(e.total() <= available,
          "the output would take {}, more than the {} free where '{}' is: use fewer steps (--steps, --dt, [time] "
          "steps or dt), fewer or smaller output files (--every, [output] every, times, fields or probes, --no-vtu) "
          "or an output directory with more free space (-o)",
          e.describe(), format_bytes(available), dir.string());
  if (e.total() <= available / 2) return {};
  return fmt::format("the output will take {}, more than half of the {} free where '{}' is", e.describe(),
                     format_bytes(available), dir.string());
}

}  // namespace vpc
