#include "io/run_output.hpp"

#include "adapt/adaptation_json.hpp"

#include "core/error.hpp"
#include "core/mpi_start.hpp"
#include "core/process_memory.hpp"
#include "io/atomic_file.hpp"
#include "io/build_info.hpp"
#include "io/history_columns.hpp"
#include "io/state_fields.hpp"
#include "io/vtu_writer.hpp"
#include "scheme/surface_fields.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <fstream>

namespace vpc {

namespace fs = std::filesystem;

namespace {

/// A parallel piece without the nodes no cell of its part touches (a spread pair row's masters,
/// ghosts with no cell: PartPieces::pairs_spread; their owners' pieces show them): its mesh over the
/// nodes its cells use, renumbered in order, and those nodes' point fields alone. The caller writes
/// the part's mesh as it is where the pairs are not spread (every node there is in a cell).
struct TrimmedPiece {
  Mesh mesh;
  std::vector<VtuField> point_data;
};

TrimmedPiece trimmed_piece(const Mesh& mesh, const std::vector<VtuField>& point_data) {
  const int npc = mesh.nodes_per_cell();
  std::vector<int> number(static_cast<std::size_t>(mesh.n_nodes()), -1);
  for (int c = 0; c < mesh.n_cells(); ++c)
    for (int a = 0; a < npc; ++a) number[static_cast<std::size_t>(mesh.cell(c)[a])] = 0;
  TrimmedPiece t{Mesh(mesh.dim()), {}};
  std::vector<int> kept;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (number[static_cast<std::size_t>(i)] == 0) {
      number[static_cast<std::size_t>(i)] = t.mesh.add_node(mesh.node(i));
      kept.push_back(i);
    }
  std::vector<int> nodes(static_cast<std::size_t>(npc));
  for (int c = 0; c < mesh.n_cells(); ++c) {
    for (int a = 0; a < npc; ++a) nodes[static_cast<std::size_t>(a)] = number[static_cast<std::size_t>(mesh.cell(c)[a])];
    t.mesh.add_cell(nodes.data());
  }
  for (const VtuField& f : point_data) {
    VtuField& g = t.point_data.emplace_back(VtuField{f.name, f.n_components, {}, f.integer});
    const auto w = static_cast<std::size_t>(f.n_components);
    for (const int i : kept)
      g.values.insert(g.values.end(), f.values.begin() + static_cast<std::ptrdiff_t>(i * w),
                      f.values.begin() + static_cast<std::ptrdiff_t>((i + 1) * w));
  }
  return t;
}

}  // namespace

ProbeLocation locate_point(const Mesh& mesh, const Point& x) {
  const int d = mesh.dim();
  ProbeLocation best;
  best.x = x;
  double best_min = -INFINITY;
  for (int c = 0; c < mesh.n_cells(); ++c) {
    // Barycentric coordinates from the cell's affine map.
    Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
    const Point& x0 = mesh.node(mesh.cell(c)[0]);
    for (int a = 1; a <= d; ++a)
      for (int i = 0; i < d; ++i) J(i, a - 1) = mesh.node(mesh.cell(c)[a])[i] - x0[i];
    Eigen::Vector3d r(0, 0, 0);
    for (int i = 0; i < d; ++i) r[i] = x[i] - x0[i];
    const Eigen::Vector3d l = J.topLeftCorner(d, d).inverse() * r.head(d) ;
    std::array<double, 4> lam{};
    lam[0] = 1;
    for (int a = 1; a <= d; ++a) {
      lam[a] = l[a - 1];
      lam[0] -= l[a - 1];
    }
    const double m = *std::min_element(lam.begin(), lam.begin() + d + 1);
    if (m > best_min) {
      best_min = m;
      best.cell = c;
      best.lambda = lam;
    }
  }
  require(best.cell >= 0 && best_min > -1e-9, "probe point ({}, {}, {}) lies outside the mesh", x[0], x[1], x[2]);
  return best;
}

namespace {

const char* component_name(int i) {
  static const char* n[6] = {"11", "22", "33", "23", "13", "12"};
  return n[i];
}

}  // namespace

const std::vector<std::string>& OutputOptions::field_names() {
  static const std::vector<std::string> names = vtu_field_names();
  return names;
}

std::string OutputOptions::field(const std::string& name, const std::vector<std::string>& surface) {
  if (name == "damage") return "beta";  // β's field name in earlier versions: old case files keep working
  const auto& n = field_names();
  return std::find(n.begin(), n.end(), name) != n.end() || std::ranges::find(surface, name) != surface.end()
             ? name
             : std::string();
}

void prepare_output_options(OutputOptions& o, const std::string& case_name, const std::vector<std::string>& surface) {
  if (o.directory.empty()) o.directory = fs::path("output") / case_name;
  for (auto& f : o.fields) {
    const std::string field = OutputOptions::field(f, surface);
    require(!field.empty(), "output: unknown field '{}'; expected one of: {}{}{}", f,
            fmt::join(OutputOptions::field_names(), ", "), surface.empty() ? "" : ", ", fmt::join(surface, ", "));
    f = field;
  }
  require(o.every >= 0, "output: 'every' must be >= 0 (got {})", o.every);
  if (o.started == std::chrono::system_clock::time_point{}) o.started = std::chrono::system_clock::now();
}

RunOutput::RunOutput(const TimeStepper& stepper, OutputOptions options)
    : stepper_(&stepper), options_(std::move(options)) {
  std::vector<std::string> surface;
  for (const SurfaceField& f : stepper_->state().surface) surface.push_back(f.name);
  prepare_output_options(options_, stepper_->problem().name, surface);
  for (const auto& x : options_.probes) probes_.push_back(locate_probe(x));
}

RunOutput::Probe RunOutput::locate_probe(const Point& x) const {
  // The probe belongs to the process whose cell contains it best (largest
  // smallest barycentric coordinate; ties: the lowest cell number of the mesh as
  // read): on one process, locate_point's choice.
  const la::Comm& comm = stepper_->comm();
  const MeshPart& part = stepper_->part();
  const Mesh& mesh = part.mesh();
  Probe p;
  p.where.x = x;
  double score = -INFINITY, cell = INFINITY;
  if (mesh.n_cells() > 0) {
    try {
      p.where = locate_point(mesh, x);
      score = *std::min_element(p.where.lambda.begin(), p.where.lambda.begin() + mesh.dim() + 1);
      cell = part.original_cell[p.where.cell];
    } catch (const Error&) {
    }
  }
  const double best = comm.max(score);
  if (best <= -1e-9) {  // every process alike
    const std::string what = fmt::format("probe point ({}, {}, {}) lies outside the mesh", x[0], x[1], x[2]);
    if (comm.serial()) throw Error(what);
    comm.throw_if_any(true, what);
  }
  const double winner = comm.min(score == best ? cell : INFINITY);
  p.mine = score == best && cell == winner;
  return p;
}

void RunTotals::add(const StepReport& r) {
  max_contact_residual = std::max(max_contact_residual, r.contact.residuals.max());
  max_damage_residual = std::max(max_damage_residual, r.damage.kkt_residual);
  max_contact_iterations = std::max(max_contact_iterations, r.contact.iterations);
  max_damage_iterations = std::max(max_damage_iterations, r.damage.iterations);
  all_ok = all_ok && r.ok;
  last_n_active = r.contact.n_active;
  const ContactResiduals& f = r.contact.residuals;
  max_friction_bound = std::max(max_friction_bound, f.friction_bound);
  max_stick_slip = std::max(max_stick_slip, f.stick_slip);
  max_slip_direction = std::max(max_slip_direction, f.slip_direction);
  dissipation += r.contact.dissipation;
  seconds_sources += r.seconds_sources;
  seconds_damage += r.seconds_damage;
  seconds_contact += r.seconds_contact;
  seconds_stress += r.seconds_stress;
}

long long active_contact_nodes(const RunTotals& totals, const Vector& normal_force) {
  return totals.last_n_active >= 0 ? totals.last_n_active
                                   : static_cast<long long>((normal_force.array() > 0).count());
}

std::vector<int> tensor_components(const Elasticity& e) { return e.stress_components(); }

std::string history_header(const Problem& p, const MeshPart& part, bool adaptive) {
  return fmt::format("{}\n", fmt::join(history_column_names(p, part, adaptive), ","));
}

std::string history_row(const StepReport& r) {
  std::string row;
  for (const HistoryValue& v : history_values(r)) {
    if (!row.empty()) row += ',';
    row += v.text();
  }
  return row + "\n";
}

std::string probes_header(const Elasticity& e, std::size_t n_probes) {
  const int d = e.dim();
  std::string h = "step,t";
  static const char* axis = "xyz";
  for (std::size_t p = 0; p < n_probes; ++p) {
    for (int i = 0; i < d; ++i) h += fmt::format(",p{}_u{}", p, axis[i]);
    for (int c : tensor_components(e)) h += fmt::format(",p{}_sigma{}", p, component_name(c));
    h += fmt::format(",p{}_von_mises,p{}_beta", p, p);
  }
  return h + "\n";
}

void truncate_csv(const fs::path& path, int n) {
  std::ifstream in(path);
  require(in.good(), "resume: cannot read '{}'", path.string());
  std::string content, line;
  bool header = true;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a row cut by the interruption
    if (!header && std::atoi(line.c_str()) > n) break;
    header = false;
    content += line;
    content += '\n';
  }
  write_file_atomic(path, content);
}

void RunOutput::open_csv(bool append) {
  la::on_root(stepper_->comm(), [&] {
    const auto mode = append ? std::ios::app : std::ios::trunc;
    history_.open(options_.directory / "history.csv", mode);
    require(history_.good(), "cannot write '{}'", (options_.directory / "history.csv").string());
    probe_csv_.open(options_.directory / "probes.csv", mode);
    require(probe_csv_.good(), "cannot write '{}'", (options_.directory / "probes.csv").string());
  });
}

void RunOutput::start() {
  open_csv(false);
  if (root()) {
    history_ << history_header(stepper_->problem(), stepper_->part(), adaptation_.log != nullptr);
    history_.flush();
    probe_csv_ << probes_header(stepper_->problem().elasticity, probes_.size());
  }
  write_probe_row();
  write_fields();
}

namespace {

/// A file of the solution at a step after n: a one-process VTU, a piece or a .pvtu.
bool solution_after(const std::string& f, int n) {
  return f.starts_with("solution_") && f.size() > 14 && (f.ends_with(".vtu") || f.ends_with(".pvtu")) &&
         std::atoi(f.c_str() + 9) > n;
}

/// The .pvtu file that assembles the processes' pieces.
void write_pvtu(const fs::path& path, const std::vector<VtuField>& point_data, const std::vector<VtuField>& cell_data,
                const std::vector<std::string>& pieces) {
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n";
  auto arrays = [&](const std::vector<VtuField>& fields) {
    for (const auto& f : fields)
      xml += fmt::format("      <PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n", vtk_type(f),
                         f.name, f.n_components);
  };
  arrays(point_data);
  xml += "    </PPointData>\n    <PCellData>\n";
  arrays(cell_data);
  xml += "    </PCellData>\n    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n";
  xml += "    </PPoints>\n";
  for (const auto& p : pieces) xml += fmt::format("    <Piece Source=\"{}\"/>\n", p);
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_file_atomic(path, xml);
}

}  // namespace

void RunOutput::resume(int n, std::vector<std::pair<double, std::string>> pvd, const RunTotals& totals) {
  totals_ = totals;
  pvd_ = std::move(pvd);
  la::on_root(stepper_->comm(), [&] {
    truncate_csv(options_.directory / "history.csv", n);
    truncate_csv(options_.directory / "probes.csv", n);
  });
  open_csv(true);
  la::on_root(stepper_->comm(), [&] {
    // VTU files of steps after n belong to the lost part of the run.
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(options_.directory, ec))
      if (solution_after(entry.path().filename().string(), n)) fs::remove(entry.path(), ec);
    if (options_.vtu) write_pvd(options_.directory / "solution.pvd", pvd_);
  });
}

void RunOutput::write_probe_row() {
  const State& s = stepper_->state();
  const Mesh& mesh = stepper_->mesh();
  const int d = mesh.dim();
  const auto comps = tensor_components(stepper_->problem().elasticity);
  const std::size_t per_probe = d + comps.size() + 2;
  // The owner of each probe fills its values, the others zeros: the sum is exact.
  std::vector<double> values(probes_.size() * per_probe, 0.0);
  for (std::size_t k = 0; k < probes_.size(); ++k) {
    if (!probes_[k].mine) continue;
    const ProbeLocation& p = probes_[k].where;
    const int* v = mesh.cell(p.cell);
    double* out = &values[k * per_probe];
    for (int i = 0; i < d; ++i) {
      double u = 0;
      for (int a = 0; a <= d; ++a) u += p.lambda[a] * s.u[v[a] * d + i];
      *out++ = u;
    }
    for (int c : comps) *out++ = s.sigma[p.cell][c];
    *out++ = s.sigma[p.cell].von_mises();
    double b = 0;
    for (int a = 0; a <= d; ++a) b += p.lambda[a] * s.beta[v[a]];
    *out++ = b;
  }
  stepper_->comm().sum(values.data(), static_cast<int>(values.size()));
  if (!root()) return;
  probe_csv_ << fmt::format("{},{:.17g}", s.n, s.t);
  for (double v : values) probe_csv_ << fmt::format(",{:.17g}", v);
  probe_csv_ << "\n";
  probe_csv_.flush();
}

void RunOutput::write_fields() {
  if (!options_.vtu) return;
  const State& s = stepper_->state();
  const Mesh& mesh = stepper_->mesh();
  const la::Comm& comm = stepper_->comm();
  std::vector<VtuField> point_data, cell_data;
  make_vtu_fields({s, stepper_->part(), stepper_->contact().nodes}, options_.fields, point_data, cell_data);
  const Problem& problem = stepper_->problem();
  if (!problem.materials.empty() || !problem.bodies.empty()) {  // each cell's material (Problem::material_list order)
    const std::vector<int>& m = stepper_->part().cell_material;
    cell_data.push_back({"material", 1, std::vector<double>(m.begin(), m.end()), true});
  }
  if (adaptation_.cell_fields)  // an adaptive run's level and indicator per cell
    for (VtuField& f : adaptation_.cell_fields()) cell_data.push_back(std::move(f));
  if (!problem.bodies.empty()) {  // each cell's body: 0 the case's [mesh], k the k-th [[body]] (ParaView: Threshold)
    const std::vector<int>& b = stepper_->part().cell_body;
    cell_data.push_back({"body", 1, std::vector<double>(b.begin(), b.end()), true});
  }
  const std::string stem = fmt::format("solution_{:05d}", s.n);
  std::string file = stem + ".vtu";
  if (comm.size() == 1) {
    write_vtu(options_.directory / file, mesh, point_data, cell_data, options_.encoding);
  } else {
    // Each process its piece, with the partition as a field (to look at it in ParaView).
    cell_data.push_back({"rank", 1, std::vector<double>(mesh.n_cells(), static_cast<double>(comm.rank())), true});
    la::collective(comm, [&] {
      const fs::path piece = options_.directory / fmt::format("{}_p{:04d}.vtu", stem, comm.rank());
      if (!stepper_->part().pairs_spread) {
        write_vtu(piece, mesh, point_data, cell_data, options_.encoding);
        return;
      }
      const TrimmedPiece t = trimmed_piece(mesh, point_data);
      write_vtu(piece, t.mesh, t.point_data, cell_data, options_.encoding);
    });
    file = stem + ".pvtu";
    std::vector<std::string> pieces;
    for (int r = 0; r < comm.size(); ++r) pieces.push_back(fmt::format("{}_p{:04d}.vtu", stem, r));
    la::on_root(comm, [&] { write_pvtu(options_.directory / file, point_data, cell_data, pieces); });
  }
  if (!root()) return;
  pvd_.emplace_back(s.t, file);
  write_pvd(options_.directory / "solution.pvd", pvd_);
}

void RunOutput::record(const StepReport& r) {
  const auto t0 = std::chrono::steady_clock::now();
  record_untimed(r);
  totals_.seconds_output += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void RunOutput::record_untimed(const StepReport& r) {
  if (root()) {
    history_ << history_row(r);
    history_.flush();
  }
  write_probe_row();
  totals_.add(r);
  warn_small_sliding(r);
  if (is_output_step(r.n, r.t)) write_fields();
}

/// A slave node of a `sliding = "small"` pair slid past kSmallSlideLimit of a master facet from the
/// masters it was coupled to at t = 0: the answer degrades silently from there (its rows keep those
/// masters), so say it once, at the pair's table, with the remedy.
void RunOutput::warn_small_sliding(const StepReport& r) {
  const Problem& p = stepper_->problem();
  if (warned_small_sliding_) return;
  const std::vector<PairSlide> slides = small_slides(p, stepper_->part(), stepper_->contact().nodes, stepper_->state());
  for (const PairSlide& s : slides) {
    if (!(s.ratio > kSmallSlideLimit)) continue;
    const std::size_t q = s.pair;
    warned_small_sliding_ = true;
    if (root())
      fmt::print(stderr,
                 "vpcontact: warning: {}: at step {} (t = {:.6g}) slave node {} ({:.6g}, {:.6g}, {:.6g}) of '{}' has "
                 "slid {:.6g} from the master nodes it was coupled to at t = 0, {:.3g} of the master facet there "
                 "({:.6g}); with sliding = \"small\" (the default) a slave node keeps its t = 0 masters, right only "
                 "while it slides less than {} of a master facet: set sliding = \"large\" in this [[contact.pair]]\n",
                 p.where(fmt::format("contact.pair[{}]", q)), r.n, r.t, p.node_number(s.node), s.x[0], s.x[1], s.x[2],
                 p.contact.pairs[q].slave, s.slide, s.ratio, s.facet, kSmallSlideLimit);
    break;  // once
  }
}

bool RunOutput::is_output_step(int n, double t_n) const {
  const Problem& p = stepper_->problem();
  if (stepper_->done()) return true;
  if (!options_.times.empty()) {
    // A fixed grid: the step nearest each requested time (ties: the earlier step).
    // Error-controlled steps end at the output times (StepControl::landings).
    for (double t : options_.times)
      if (p.step_control ? std::abs(t - t_n) <= 1e-12 * p.final_time : p.step_nearest(t) == n) return true;
    return false;
  }
  return options_.every > 0 && n % options_.every == 0;
}

std::string iso8601_utc(std::chrono::system_clock::time_point t) {
  const std::time_t tt = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string summary_json(const Problem& p, const RunSummary& r, const OutputOptions& options) {
  using Json = nlohmann::ordered_json;  // keys in the order written here
  const RunTotals& t = r.totals;
  auto xyz = [](const Point& x) { return Json::array({x[0], x[1], x[2]}); };
  Json j;
  j["case"] = p.name;
  if (r.ranks > 0) {
    j["engine"] = "petsc";
    j["ranks"] = r.ranks;
    j["linear_solver"] = r.linear_solver;
  }
  j["dimension"] = r.dimension;
  if (!r.contact_solver.empty()) j["contact_solver"] = r.contact_solver;
  j["mesh"] = {{"nodes", r.nodes}, {"cells", r.cells}, {"h_min", r.h_min}, {"h_max", r.h_max}};
  j["unknowns"] = {{"displacement_free", r.free_dofs}, {"damage", r.nodes}, {"contact_nodes", r.contact_nodes}};
  j["elasticity"] = p.elasticity.name();
  j["viscoplastic_law"] = p.law->describe();
  j["damage_source"] = p.source->describe();
  if (!p.materials.empty() || !p.bodies.empty()) {  // the body's material, the others, the bodies' (VTU `material`)
    j["materials"] = nlohmann::json::array();
    for (const Material& m : p.material_list())
      j["materials"].push_back({{"name", m.name},
                                {"regions", m.regions},
                                {"elasticity", m.elasticity.name()},
                                {"E", m.elasticity.young()},
                                {"nu", m.elasticity.poisson()},
                                {"viscoplastic_law", m.law->describe()},
                                {"damage_source", m.source->describe()}});
  }
  j["units"] = options.units;
  // For the figures: the symmetry planes x_i = c (a contact zone cut by one is half of
  // the real one), and the rigid obstacles where they are at the output times.
  j["symmetry_planes"] = Json::array();
  for (const auto& s : r.symmetry_planes)
    j["symmetry_planes"].push_back({{"part", s.part}, {"axis", std::string(1, "xyz"[s.axis])}, {"coordinate", s.coordinate}});
  if (!p.contact.obstacles.empty()) {
    j["obstacles"] = Json::array();
    for (const Obstacle& o : p.contact.obstacles) {
      const bool plane = o.shape == Obstacle::Shape::Plane, cylinder = o.shape == Obstacle::Shape::Cylinder;
      Json ob = {{"name", o.name}, {"shape", plane ? "plane" : cylinder ? "cylinder" : "sphere"}};
      if (plane) ob["normal"] = xyz(o.normal);
      if (cylinder) ob["axis"] = xyz(o.axis);
      if (!plane) ob["radius"] = o.radius;
      ob["positions"] = Json::array();  // [t, x, y, z]: the point of the plane / the centre, at each output time
      for (double t : r.output_times) {
        const Point x = o.position({0, 0, 0}, t);
        ob["positions"].push_back({t, x[0], x[1], x[2]});
      }
      j["obstacles"].push_back(ob);
    }
  }
  j["kappa"] = p.kappa;
  if (!p.bodies.empty()) {  // the VTU cell field `body` indexes them
    j["bodies"] = Json::array({{{"name", "body"}, {"kappa", p.kappa}}});
    for (const Body& b : p.bodies) j["bodies"].push_back({{"name", b.name}, {"kappa", b.kappa}});
  }
  // The contact laws' per-node state (SPEC §9: wear, bonding): VTU point fields on Γ3 (vpcontact plot).
  if (const auto surface = declared_surface_state(p.contact); !surface.empty()) {
    j["surface_state"] = Json::array();
    for (const SurfaceVariable& v : surface)
      j["surface_state"].push_back({{"name", v.name},
                                    {"width", v.width},
                                    {"meaning", v.meaning},
                                    {"history", v.history},
                                    {"history_mean", v.history_mean}});
  }
  j["final_time"] = p.final_time;
  j["steps"] = r.steps;
  if (p.uniform_steps()) {
    j["time_step"] = p.step();
  } else {  // the steps taken (the grid's, or those the error control chose)
    j["time_steps"] = p.describe_steps();
    if (p.step_control) j["tolerance"] = p.step_control->tolerance;
    j["time_step_range"] = {r.k_min, r.k_max};
    j["rejected_steps"] = r.rejected;
  }
  j["final"] = {{"t", r.t},
                {"total_contact_force", r.total_contact_force},
                {"active_contact_nodes", r.active_contact_nodes},
                {"max_von_mises", r.max_von_mises},
                {"beta_min", r.beta_min},
                {"beta_min_location", xyz(r.beta_min_location)},
                {"beta_max", r.beta_max}};
  j["checks"] = {{"all_steps_ok", t.all_ok},
                 {"max_contact_residual", t.max_contact_residual},
                 {"max_damage_kkt_residual", t.max_damage_residual},
                 {"max_contact_iterations", t.max_contact_iterations},
                 {"max_damage_iterations", t.max_damage_iterations}};
  if (r.n_stick >= 0)  // a frictional run (SPEC §7): the friction residuals' maxima, the final statuses
    j["friction"] = {{"max_friction_bound", t.max_friction_bound},
                     {"max_stick_slip", t.max_stick_slip},
                     {"max_slip_direction", t.max_slip_direction},
                     {"n_stick", r.n_stick},
                     {"n_slip", r.n_slip},
                     {"dissipation", t.dissipation}};
  if (!t.resume_changes.empty()) {  // the keys a --resume changed (those that may change: docs/cases.md)
    j["changed_on_resume"] = Json::array();
    for (const ResumeChange& c : t.resume_changes)
      j["changed_on_resume"].push_back({{"step", c.step}, {"key", c.key}, {"checkpoint", c.before}, {"now", c.after}});
  }
  // The small-sliding pairs' largest slide from their t = 0 masters, at the last step (RunOutput::
  // warn_small_sliding warns past the limit).
  if (!r.pair_slides.empty()) {
    j["small_sliding"] = Json::array();
    for (const PairSlide& s : r.pair_slides) {
      j["small_sliding"].push_back({{"slave", p.contact.pairs[s.pair].slave},
                                    {"slide", s.slide},
                                    {"master_facet", s.facet},
                                    {"slide_per_facet", s.ratio},
                                    {"limit", kSmallSlideLimit},
                                    {"past_limit", s.ratio > kSmallSlideLimit}});
    }
  }
  // An adaptive run's mesh changes ([adapt]; issue 51): one entry per adaptation.
  if (r.adaptive) {
    j["adaptations"] = Json::array();
    double adapt_seconds = 0, rebuild_seconds = 0;
    for (const AdaptationRecord& a : r.adaptations) {
      adapt_seconds += a.seconds_adapt;
      rebuild_seconds += a.seconds_rebuild;
      j["adaptations"].push_back(adaptation_json(a));
    }
    j["adaptation_seconds"] = {{"adapt_and_transfer", adapt_seconds}, {"rebuild", rebuild_seconds}};
  }
  j["probes"] = Json::array();
  for (const auto& x : r.probes) j["probes"].push_back(xyz(x));
  j["timing_seconds"] = {{"wall", r.wall_seconds},       {"setup", r.setup.total},     {"sources", t.seconds_sources},
                         {"damage", t.seconds_damage},   {"contact", t.seconds_contact}, {"stress", t.seconds_stress},
                         {"output", t.seconds_output}};
  if (mpi_start_seconds() > 0) j["timing_seconds"]["mpi_start"] = mpi_start_seconds();
  j["setup_seconds"] = {{"assembly", r.setup.assembly},
                        {"factor_K", r.setup.factor_K},
                        {"factor_H", r.setup.factor_H},
                        {"contact", r.setup.contact}};
  // Where the memory goes: each stage's largest rank (resident and peak so far, bytes) and each
  // rank's peak (Linux's VmRSS and VmHWM; zeros where the system does not say).
  Json memory = Json::object();
  for (const auto& [stage, m] : r.memory) memory[stage] = {{"resident", m.resident}, {"peak", m.peak}};
  memory["peak_per_rank"] = r.peak_per_rank;
  j["memory_bytes"] = memory;
  j["factorizations"] = r.factorizations;
  j["linear_iterations"] = r.linear_iterations;
  j["vpcontact"] = {{"version", version()},
                    {"git_commit", git_commit()},
                    {"command_line", options.command_line},
                    {"date", iso8601_utc(options.started)}};
  // Bytes that are not UTF-8 (a path given in another encoding) become U+FFFD
  // instead of an exception; NaN and ±inf are written as null.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

RunSummary RunOutput::summary(double wall_seconds) const {
  const MeshPart& part = stepper_->part();
  const Mesh& mesh = part.mesh();
  const la::Comm& comm = stepper_->comm();
  const State& s = stepper_->state();
  RunSummary r;
  r.dimension = mesh.dim();
  r.nodes = part.n_global_nodes;
  r.cells = part.n_global_cells;
  r.free_dofs = part.n_global_dofs;
  r.contact_nodes = part.n_contact;
  double h_min = INFINITY, h_max = 0;
  if (mesh.n_cells() > 0) std::tie(h_min, h_max) = mesh.size_range();
  r.h_min = comm.min(h_min);
  r.h_max = comm.max(h_max);
  for (const auto& x : s.sigma) r.max_von_mises = std::max(r.max_von_mises, x.von_mises());
  r.max_von_mises = comm.max(r.max_von_mises);
  // min β by the rule of the step reports (global_minimum_at, scheme/step_checks.hpp);
  // its location from the process that owns the node (the others add zeros).
  const auto n = static_cast<std::size_t>(part.n_owned_nodes);
  const MinimumAt lo = global_minimum_at(comm, {s.beta.data(), n}, {part.original_node.data(), n});
  r.beta_min = lo.value;
  const int at = lo.index;
  r.beta_max = comm.max(n ? s.beta.head(static_cast<Eigen::Index>(n)).maxCoeff() : -INFINITY);
  Point x{0, 0, 0};
  for (std::size_t i = 0; i < n; ++i)
    if (part.original_node[i] == at) x = mesh.node(static_cast<int>(i));
  comm.sum(x.data(), 3);
  r.beta_min_location = x;
  r.steps = s.n;
  r.t = s.t;
  const std::vector<double>& times = stepper_->times();
  for (std::size_t n = 1; n < times.size(); ++n) {
    const double k = times[n] - times[n - 1];
    r.k_min = n == 1 ? k : std::min(r.k_min, k);
    r.k_max = std::max(r.k_max, k);
  }
  r.rejected = static_cast<long long>(stepper_->step_control_state().rejected);
  const Vector normal = normal_forces(s);  // λ's normal force per contact node
  r.total_contact_force = normal.sum();
  r.active_contact_nodes = active_contact_nodes(totals_, normal);
  if (s.contact_block > 1) {  // contact_status is replicated, as λ
    const auto status = s.contact_status.array();
    r.n_stick = (status == static_cast<double>(ContactStatus::Stick)).count();
    r.n_slip = (status == static_cast<double>(ContactStatus::Slip)).count();
  }
  for (const auto& p : probes_) r.probes.push_back(p.where.x);
  r.totals = totals_;
  r.wall_seconds = wall_seconds;
  r.setup = stepper_->setup_timing();
  const ProcessMemory now = process_memory();
  for (const auto& [stage, m] : {std::pair{"mesh", r.setup.mesh}, {"assembly", r.setup.assembled},
                                 {"factor_K", r.setup.factored_K}, {"factor_H", r.setup.factored_H},
                                 {"contact", r.setup.contact_ready}, {"end", now}})
    r.memory.push_back({stage, {comm.max(m.resident), comm.max(m.peak)}});
  r.peak_per_rank = comm.all_gather(static_cast<long long>(now.peak));
  r.factorizations = stepper_->n_factorizations();
  r.linear_iterations = stepper_->n_linear_iterations();
  r.contact_solver = stepper_->contact_solver();
  // Each symmetry part's plane x_i = c: the axis along which its nodes (over the
  // processes) do not spread. Its nodes from the part's Dirichlet nodes (a process's
  // part mesh has no boundary parts of its own).
  const std::vector<std::string> dirichlet = dirichlet_parts(stepper_->problem());
  for (const std::string& name : stepper_->problem().symmetry) {
    const auto bit = std::uint64_t{1} << (std::find(dirichlet.begin(), dirichlet.end(), name) - dirichlet.begin());
    Point lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const auto& [node, on_parts] : part.dirichlet_nodes)
      if (on_parts & bit)
        for (int i = 0; i < mesh.dim(); ++i) {
          lo[i] = std::min(lo[i], mesh.node(node)[i]);
          hi[i] = std::max(hi[i], mesh.node(node)[i]);
        }
    double extent = 0;
    for (int i = 0; i < mesh.dim(); ++i) {
      lo[i] = comm.min(lo[i]);
      hi[i] = comm.max(hi[i]);
      extent = std::max(extent, hi[i] - lo[i]);
    }
    for (int i = 0; i < mesh.dim(); ++i)
      if (hi[i] - lo[i] <= 1e-9 * extent) {
        r.symmetry_planes.push_back({name, i, lo[i]});
        break;
      }
  }
  r.pair_slides = small_slides(stepper_->problem(), part, stepper_->contact().nodes, s);
  for (const auto& [t, file] : pvd_) r.output_times.push_back(t);
  if (r.output_times.empty() || r.output_times.back() != s.t) r.output_times.push_back(s.t);
  if (adaptation_.log) {
    r.adaptive = true;
    r.adaptations = *adaptation_.log;
  }
  if (stepper_->backend().engine() == "petsc") {  // on one rank too
    r.ranks = comm.size();
    r.linear_solver = stepper_->backend().linear_solver();
  }
  return r;
}

void RunOutput::remesh(const TimeStepper& stepper) {
  stepper_ = &stepper;
  for (Probe& p : probes_) p = locate_probe(p.where.x);
}

void RunOutput::finish(double wall_seconds) {
  const RunSummary r = summary(wall_seconds);
  la::on_root(stepper_->comm(), [&] {
    write_file_atomic(options_.directory / "summary.json", summary_json(stepper_->problem(), r, options_));
  });
}

}  // namespace vpc
