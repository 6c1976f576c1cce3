#include "parallel/parallel_output.hpp"

#include "parallel/collective.hpp"

#include "io/atomic_file.hpp"
#include "io/vtu_writer.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>

namespace vpc {

namespace fs = std::filesystem;

namespace {

/// The .pvtu file that assembles the ranks' pieces.
void write_pvtu(const fs::path& path, const std::vector<VtuField>& point_data, const std::vector<VtuField>& cell_data,
                const std::vector<std::string>& pieces) {
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n";
  for (const auto& f : point_data)
    xml += fmt::format("      <PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n", f.name,
                       f.n_components);
  xml += "    </PPointData>\n    <PCellData>\n";
  for (const auto& f : cell_data)
    xml += fmt::format("      <PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n", f.name,
                       f.n_components);
  xml += "    </PCellData>\n    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n";
  xml += "    </PPoints>\n";
  for (const auto& p : pieces) xml += fmt::format("    <Piece Source=\"{}\"/>\n", p);
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_file_atomic(path, xml);
}

}  // namespace

void ParallelOutput::resume(int n, std::vector<std::pair<double, std::string>> pvd, const RunTotals& totals) {
  totals_ = totals;
  on_root(comm_, [&] {
    truncate_csv(options_.directory / "history.csv", n);
    truncate_csv(options_.directory / "probes.csv", n);
    history_.open(options_.directory / "history.csv", std::ios::app);
    probe_csv_.open(options_.directory / "probes.csv", std::ios::app);
    require(history_.good() && probe_csv_.good(), "cannot append to the CSV files in '{}'",
            options_.directory.string());
    // VTU files (serial, pieces, .pvtu) of steps after n belong to the lost part of the run.
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(options_.directory, ec)) {
      const std::string f = entry.path().filename().string();
      if (f.rfind("solution_", 0) == 0 && f.size() > 14 && (f.ends_with(".vtu") || f.ends_with(".pvtu")) &&
          std::atoi(f.c_str() + 9) > n)
        fs::remove(entry.path(), ec);
    }
    pvd_ = std::move(pvd);
    if (options_.vtu) write_pvd(options_.directory / "solution.pvd", pvd_);
  });
}

ParallelOutput::ParallelOutput(const DistributedTimeStepper& stepper, OutputOptions options, std::string linear_solver)
    : stepper_(stepper), options_(std::move(options)), linear_solver_(std::move(linear_solver)),
      comm_(stepper.part().comm), rank_(comm_rank(comm_)), size_(comm_size(comm_)) {
  prepare_output_options(options_, stepper_.problem().name);
  on_root(comm_, [&] {
    std::error_code ec;
    fs::create_directories(options_.directory, ec);
    require(!ec && fs::is_directory(options_.directory), "cannot create output directory '{}'",
            options_.directory.string());
  });
  // A probe belongs to the rank whose cell contains it best (largest smallest
  // barycentric coordinate; ties: the lowest cell number of the mesh as read, as
  // the serial locate_point chooses).
  const Mesh& mesh = stepper_.part().mesh;
  for (const auto& x : options_.probes) {
    Probe p{x, false, {}};
    double score = -INFINITY;
    int cell = std::numeric_limits<int>::max();
    if (mesh.n_cells() > 0) {
      try {
        p.where = locate_point(mesh, x);
        score = *std::min_element(p.where.lambda.begin(), p.where.lambda.begin() + mesh.dim() + 1);
        cell = stepper_.part().original_cell[p.where.cell];
      } catch (const Error&) {
      }
    }
    const double best = allreduce_max(comm_, score);
    if (best <= -1e-9)  // every rank alike
      throw CollectiveError(fmt::format("probe point ({}, {}, {}) lies outside the mesh", x[0], x[1], x[2]));
    int mine = score == best ? cell : std::numeric_limits<int>::max(), winner = 0;
    MPI_Allreduce(&mine, &winner, 1, MPI_INT, MPI_MIN, comm_);
    p.mine = score == best && cell == winner;
    probes_.push_back(p);
  }
}

void ParallelOutput::start() {
  on_root(comm_, [&] {
    history_.open(options_.directory / "history.csv", std::ios::trunc);
    probe_csv_.open(options_.directory / "probes.csv", std::ios::trunc);
    require(history_.good() && probe_csv_.good(), "cannot write history.csv and probes.csv in '{}'",
            options_.directory.string());
  });
  if (rank_ == 0) {
    history_ << history_header();
    history_.flush();
    probe_csv_ << probes_header(stepper_.problem().elasticity, probes_.size());
  }
  write_probe_row();
  write_fields();
}

void ParallelOutput::write_probe_row() {
  const auto& part = stepper_.part();
  const Mesh& mesh = part.mesh;
  const int d = mesh.dim();
  const auto comps = tensor_components(stepper_.problem().elasticity);
  const int per_probe = d + static_cast<int>(comps.size()) + 2;
  // The owner of each probe fills its values, the others zeros: the sum is exact.
  std::vector<double> values(probes_.size() * per_probe, 0.0);
  const Vector u = stepper_.local_u(), beta = stepper_.local_beta();
  const auto& sigma = stepper_.state().sigma;
  for (size_t k = 0; k < probes_.size(); ++k) {
    if (!probes_[k].mine) continue;
    const auto& p = probes_[k].where;
    const int* v = mesh.cell(p.cell);
    double* out = &values[k * per_probe];
    for (int i = 0; i < d; ++i) {
      double s = 0;
      for (int a = 0; a <= d; ++a) s += p.lambda[a] * u[v[a] * d + i];
      *out++ = s;
    }
    for (int c : comps) *out++ = sigma[p.cell][c];
    *out++ = sigma[p.cell].von_mises();
    double b = 0;
    for (int a = 0; a <= d; ++a) b += p.lambda[a] * beta[v[a]];
    *out++ = b;
  }
  if (rank_ == 0)
    MPI_Reduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, 0, comm_);
  else
    MPI_Reduce(values.data(), nullptr, static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, 0, comm_);
  if (rank_ != 0) return;
  const auto& s = stepper_.state();
  probe_csv_ << fmt::format("{},{:.17g}", s.n, s.t);
  for (double v : values) probe_csv_ << fmt::format(",{:.17g}", v);
  probe_csv_ << "\n";
  probe_csv_.flush();
}

void ParallelOutput::write_fields() {
  if (!options_.vtu) return;
  const auto& part = stepper_.part();
  const Mesh& mesh = part.mesh;
  const auto& s = stepper_.state();
  const int d = mesh.dim(), n_nodes = mesh.n_nodes();
  const Vector u_local = stepper_.local_u(), beta_local = stepper_.local_beta();
  VtuField u{"displacement", 3, std::vector<double>(static_cast<size_t>(n_nodes) * 3, 0.0)};
  for (int i = 0; i < n_nodes; ++i)
    for (int c = 0; c < d; ++c) u.values[i * 3 + c] = u_local[i * d + c];
  VtuField beta{"beta", 1, std::vector<double>(beta_local.data(), beta_local.data() + n_nodes)};
  // Contact force on Γ3: the nodal force the foundation exerts, −λ ν at each
  // contact node; the pressure: λ over the node's tributary measure.
  VtuField force{"contact_force", 3, std::vector<double>(static_cast<size_t>(n_nodes) * 3, 0.0)};
  VtuField pressure{"contact_pressure", 1, std::vector<double>(static_cast<size_t>(n_nodes), 0.0)};
  for (const auto& c : part.contact) {
    for (int j = 0; j < 3; ++j) force.values[c.local_node * 3 + j] = -s.lambda[c.row] * c.direction[j];
    pressure.values[c.local_node] = s.lambda[c.row] / c.measure;
  }
  VtuField vm{"von_mises", 1, {}};
  for (const auto& t : s.sigma) vm.values.push_back(t.von_mises());
  VtuField rank{"rank", 1, std::vector<double>(mesh.n_cells(), static_cast<double>(rank_))};
  std::vector<VtuField> point_data, cell_data;
  for (auto* f : {&u, &beta, &force, &pressure})
    if (wants(f->name)) point_data.push_back(std::move(*f));
  if (wants("stress")) cell_data.push_back(tensor_field("stress", s.sigma));
  if (wants("strain")) cell_data.push_back(tensor_field("strain", s.eps));
  if (wants("von_mises")) cell_data.push_back(std::move(vm));
  if (wants("history_z")) cell_data.push_back(tensor_field("history_z", s.z));
  cell_data.push_back(std::move(rank));  // the partition, for a look at the distribution in ParaView
  const std::string stem = fmt::format("solution_{:05d}", s.n);
  collective(comm_, [&] {
    write_vtu(options_.directory / fmt::format("{}_p{:04d}.vtu", stem, rank_), mesh, point_data, cell_data,
              options_.encoding);
  });
  if (rank_ == 0) {
    std::vector<std::string> pieces;
    for (int r = 0; r < size_; ++r) pieces.push_back(fmt::format("{}_p{:04d}.vtu", stem, r));
    write_pvtu(options_.directory / (stem + ".pvtu"), point_data, cell_data, pieces);
    pvd_.emplace_back(s.t, stem + ".pvtu");
    write_pvd(options_.directory / "solution.pvd", pvd_);
  }
}

void ParallelOutput::record(const StepReport& r) {
  const auto t0 = std::chrono::steady_clock::now();
  if (rank_ == 0) {
    history_ << history_row(r);
    history_.flush();
  }
  write_probe_row();
  totals_.add(r);
  if (is_output_step(r.n)) write_fields();
  totals_.seconds_output += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool ParallelOutput::wants(const std::string& field) const {
  return options_.fields.empty() ||
         std::find(options_.fields.begin(), options_.fields.end(), field) != options_.fields.end();
}

bool ParallelOutput::is_output_step(int n) const {
  const Problem& p = stepper_.problem();
  if (n == p.n_steps) return true;
  if (!options_.times.empty()) {
    const double k = p.step();
    for (double t : options_.times)
      if (std::clamp(static_cast<int>(std::lround(t / k - 1e-9)), 0, p.n_steps) == n) return true;
    return false;
  }
  return options_.every > 0 && n % options_.every == 0;
}

void ParallelOutput::finish(double wall_seconds) {
  const auto& part = stepper_.part();
  const Mesh& mesh = part.mesh;
  const Problem& p = stepper_.problem();
  const auto& s = stepper_.state();
  double hmin = INFINITY, hmax = 0;
  if (mesh.n_cells() > 0) std::tie(hmin, hmax) = mesh.size_range();
  hmin = allreduce_min(comm_, hmin);
  hmax = allreduce_max(comm_, hmax);
  double max_vm = 0;
  for (const auto& x : s.sigma) max_vm = std::max(max_vm, x.von_mises());
  max_vm = allreduce_max(comm_, max_vm);
  // min β by the serial engine's rule (minimum_at); its location from the rank that owns the node.
  const MinimumAt lo = stepper_.beta_minimum();
  const Vector beta = stepper_.local_beta();
  double bmax = -INFINITY;
  Point xb{0, 0, 0};
  int owner = size_;
  for (int i = 0; i < part.n_owned_nodes; ++i) {
    bmax = std::max(bmax, beta[i]);
    if (part.original_node[i] == lo.index) {
      owner = rank_;
      xb = mesh.node(i);
    }
  }
  bmax = allreduce_max(comm_, bmax);
  owner = static_cast<int>(allreduce_min(comm_, owner));
  if (owner < size_) MPI_Bcast(xb.data(), 3, MPI_DOUBLE, owner, comm_);
  const int n_factorizations = stepper_.n_factorizations();
  if (rank_ != 0) return;
  RunSummary r;
  r.dimension = mesh.dim();
  r.nodes = part.n_global_nodes;
  r.cells = part.n_global_cells;
  r.h_min = hmin;
  r.h_max = hmax;
  r.free_dofs = part.n_global_dofs;
  r.contact_nodes = part.n_contact;
  r.steps = s.n;
  r.t = s.t;
  r.total_contact_force = s.lambda.sum();
  r.active_contact_nodes = active_contact_nodes(totals_, s.lambda);
  r.max_von_mises = max_vm;
  r.beta_min = lo.value;
  r.beta_min_location = xb;
  r.beta_max = bmax;
  for (const auto& pr : probes_) r.probes.push_back(pr.x);
  r.totals = totals_;
  r.wall_seconds = wall_seconds;
  r.setup = stepper_.setup_timing();
  r.factorizations = n_factorizations;
  r.ranks = size_;
  r.linear_solver = linear_solver_;
  write_file_atomic(options_.directory / "summary.json", summary_json(p, r, options_));
}

}  // namespace vpc
