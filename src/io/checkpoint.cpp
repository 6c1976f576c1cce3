#include "io/checkpoint.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "io/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

namespace vpc {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'V', 'P', 'C', 'C', 'K', 'P', 'T', '\0'};
constexpr std::uint32_t kVersion = 2;  // 2: the run totals hold the last step's active count

std::uint64_t fnv1a(const char* data, std::size_t n, std::uint64_t h = 1469598103934665603ull) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(data[i])) * 1099511628211ull;
  return h;
}

/// Serializes the payload to a stream, or (without one) only measures its size
/// and checksum: the payload is written in two passes and never held in memory.
class Writer {
 public:
  explicit Writer(std::ostream* out = nullptr) : out_(out) {}
  template <typename T>
  void pod(const T& v) {
    bytes(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void string(const std::string& s) {
    pod<std::uint64_t>(s.size());
    bytes(s.data(), s.size());
  }
  void doubles(const double* p, std::size_t n) {
    pod<std::uint64_t>(n);
    bytes(reinterpret_cast<const char*>(p), n * sizeof(double));
  }
  void vector(const Vector& v) { doubles(v.data(), static_cast<std::size_t>(v.size())); }
  void tensors(const std::vector<SymTensor>& t) { doubles(t.empty() ? nullptr : t[0].c.data(), 6 * t.size()); }
  std::uint64_t size() const { return size_; }
  std::uint64_t checksum() const { return hash_; }

 private:
  void bytes(const char* p, std::size_t n) {
    if (n == 0) return;
    size_ += n;
    if (out_)
      out_->write(p, static_cast<std::streamsize>(n));
    else
      hash_ = fnv1a(p, n, hash_);
  }
  std::ostream* out_;
  std::uint64_t size_ = 0, hash_ = fnv1a(nullptr, 0);
};

class Reader {
 public:
  Reader(const std::string& data, const std::string& file) : data_(data), file_(file) {}
  template <typename T>
  T pod() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  std::string string() {
    const auto n = pod<std::uint64_t>();
    need(n);
    std::string s = data_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::vector<double> doubles() {
    const auto n = pod<std::uint64_t>();
    need(n * sizeof(double));
    std::vector<double> v(n);
    if (n) std::memcpy(v.data(), data_.data() + pos_, n * sizeof(double));
    pos_ += n * sizeof(double);
    return v;
  }
  Vector vector() {
    const auto v = doubles();
    return Eigen::Map<const Vector>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  std::vector<SymTensor> tensors() {
    const auto v = doubles();
    require(v.size() % 6 == 0, "checkpoint '{}': a tensor array has {} values, not a multiple of 6", file_, v.size());
    std::vector<SymTensor> t(v.size() / 6);
    for (std::size_t i = 0; i < t.size(); ++i) std::copy_n(v.data() + 6 * i, 6, t[i].c.data());
    return t;
  }
  bool done() const { return pos_ == data_.size(); }

 private:
  void need(std::size_t n) const {
    require(n <= data_.size() - pos_, "checkpoint '{}': truncated payload", file_);
  }
  const std::string& data_;
  const std::string& file_;
  std::size_t pos_ = 0;
};

int step_of(const fs::path& p) {
  const std::string f = p.filename().string();
  if (f.rfind("checkpoint_", 0) != 0 || !f.ends_with(".bin")) return -1;
  return std::atoi(f.c_str() + 11);
}

}  // namespace

std::uint64_t problem_fingerprint(const TimeStepper& s) {
  const Problem& p = s.problem();
  const MeshPart& part = s.part();
  std::string key =
      fmt::format("{}|{}|{}|{}|{}|{}|{}|{:.17g}|{:.17g}|{}|{}|{}", p.name, part.dofs.dim(), part.n_global_nodes,
                  part.n_global_cells, part.n_global_dofs, part.n_contact, p.n_steps, p.final_time, p.kappa,
                  p.elasticity.name(), p.law->describe(), p.source->describe());
  for (const Material& m : p.materials)  // none: the key of a one-material case is unchanged
    key += fmt::format("|{}|{:.17g}|{:.17g}|{}|{}", m.name, m.elasticity.young(), m.elasticity.poisson(),
                       m.law->describe(), m.source->describe());
  return fnv1a(key.data(), key.size());
}

namespace {

/// The part's cells as a layout (no ghosts) in the numbering of the mesh as read.
la::Layout cell_layout(const MeshPart& part) {
  const int n = part.mesh().n_cells();
  if (part.comm.serial()) return la::Layout(n);
  return la::Layout(part.comm, n, {}, {part.original_cell.begin(), part.original_cell.end()});
}

/// The owned entries of `layout`, `width` values each (values[i * width + j]), on
/// rank 0 in the original numbering, `width` values per entry. Collective.
Vector gather_blocks(const la::Layout& layout, const double* values, int width) {
  Vector global, component(layout.n_owned());
  for (int j = 0; j < width; ++j) {
    for (int i = 0; i < layout.n_owned(); ++i) component[i] = values[static_cast<std::size_t>(i) * width + j];
    const Vector g = layout.gather(component);
    global.resize(g.size() * width);  // the same size for every j: nothing lost
    for (Eigen::Index i = 0; i < g.size(); ++i) global[i * width + j] = g[i];
  }
  return global;
}

/// The inverse: `global` (rank 0) into every local entry (owned, then ghosts). Collective.
Vector scatter_blocks(const la::Layout& layout, const Vector& global, int width) {
  Vector local(static_cast<Eigen::Index>(layout.n_local()) * width), g, component;
  for (int j = 0; j < width; ++j) {
    g.resize(global.size() / width);
    for (Eigen::Index i = 0; i < g.size(); ++i) g[i] = global[i * width + j];
    layout.scatter(g, component);
    for (int i = 0; i < layout.n_local(); ++i) local[static_cast<Eigen::Index>(i) * width + j] = component[i];
  }
  return local;
}

/// σ, ε, z of each cell as 18 values (cell-major), and back.
std::vector<double> pack_cells(const State& s) {
  std::vector<double> v;
  v.reserve(s.sigma.size() * 18);
  for (std::size_t c = 0; c < s.sigma.size(); ++c)
    for (const auto* t : {&s.sigma[c], &s.eps[c], &s.z[c]}) v.insert(v.end(), t->c.begin(), t->c.end());
  return v;
}
void unpack_cells(const Vector& v, State& s) {
  const auto n = static_cast<std::size_t>(v.size() / 18);
  s.sigma.resize(n);
  s.eps.resize(n);
  s.z.resize(n);
  for (std::size_t c = 0; c < n; ++c)
    for (auto [k, t] : {std::pair{0, &s.sigma[c]}, std::pair{1, &s.eps[c]}, std::pair{2, &s.z[c]}})
      std::copy_n(v.data() + c * 18 + k * 6, 6, t->c.begin());
}

std::vector<double> to_std(const Vector& v) { return {v.data(), v.data() + v.size()}; }
Vector to_eigen(const std::vector<double>& v) {
  return Eigen::Map<const Vector>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace

Snapshot gather_snapshot(const TimeStepper& stepper) {
  const MeshPart& part = stepper.part();
  const la::Comm& comm = stepper.comm();
  const la::Layout& nodes = *part.node_layout;
  const int d = part.dofs.dim();
  const Snapshot mine = stepper.snapshot();
  const State& st = mine.state;
  Vector free(part.dofs.n_full());  // 1 at a free dof
  for (int i = 0; i < part.dofs.n_full(); ++i) free[i] = part.dofs.free_index(i) >= 0;
  Snapshot g;
  g.state.u = gather_blocks(nodes, st.u.data(), d);
  g.state.beta = nodes.gather(st.beta);
  const Vector F = gather_blocks(nodes, free.data(), d);
  const std::vector<double> cells = pack_cells(st);
  unpack_cells(gather_blocks(cell_layout(part), cells.data(), 18), g.state);
  // The damage solver's warm start: a node field (owned entries), or none.
  if (comm.any(mine.damage_warm.size() > 0)) {
    comm.throw_if_any(mine.damage_warm.size() != part.n_owned_nodes,
                      "internal: the damage solver's warm state is not a node field");
    g.damage_warm = nodes.gather(mine.damage_warm);
  }
  if (comm.rank() != 0) return {};
  g.state.n = st.n;
  g.state.t = st.t;
  g.state.lambda = st.lambda;     // every process holds all of λ
  g.contact_warm = mine.contact_warm;  // one value per contact row, the same everywhere
  // u on the free dofs in the numbering of the mesh as read (DofMap's: node-major, prescribed components dropped).
  g.u_free.resize(part.n_global_dofs);
  Eigen::Index k = 0;
  for (Eigen::Index i = 0; i < F.size(); ++i)
    if (F[i] != 0) g.u_free[k++] = g.state.u[i];
  return g;
}

void write_checkpoint(const TimeStepper& stepper, const fs::path& dir, const std::string& case_name,
                      const std::vector<std::pair<double, std::string>>& pvd, const RunTotals& totals) {
  Snapshot s = gather_snapshot(stepper);
  const std::uint64_t fingerprint = problem_fingerprint(stepper);
  la::on_root(stepper.comm(), [&] { write_checkpoint(dir, {case_name, fingerprint, std::move(s), pvd, totals}); });
}

std::optional<ResumePoint> resume_from_checkpoint(TimeStepper& stepper, const fs::path& dir,
                                                  std::vector<std::string>* skipped) {
  const MeshPart& part = stepper.part();
  const la::Comm& comm = stepper.comm();
  const la::Layout& nodes = *part.node_layout;
  const int d = part.dofs.dim();
  std::optional<Checkpoint> ck;
  la::on_root(comm, [&] {
    ck = find_checkpoint(dir, problem_fingerprint(stepper), skipped);
    if (!ck) return;
    const Snapshot& s = ck->snapshot;
    const long long n_nodes = part.n_global_nodes;
    const bool fits = s.state.u.size() == n_nodes * d && s.state.beta.size() == n_nodes &&
                      static_cast<long long>(s.state.sigma.size()) == part.n_global_cells &&
                      s.state.lambda.size() == part.n_contact &&
                      (s.damage_warm.size() == 0 || s.damage_warm.size() == n_nodes);
    require(fits, "resume: the checkpoint of step {} in '{}' does not fit this problem", s.state.n, dir.string());
  });
  // What every process needs of rank 0's checkpoint: found, n, t, whether there is a damage warm start; λ; the
  // contact warm start.
  Checkpoint none;
  const Checkpoint& c = ck ? *ck : none;
  const State& saved = c.snapshot.state;
  const auto head = la::broadcast(comm, std::vector<double>{ck ? 1.0 : 0.0, static_cast<double>(saved.n), saved.t,
                                                            c.snapshot.damage_warm.size() > 0 ? 1.0 : 0.0});
  if (head[0] == 0) return std::nullopt;
  Snapshot s;
  s.state.n = static_cast<int>(head[1]);
  s.state.t = head[2];
  s.state.lambda = to_eigen(la::broadcast(comm, to_std(saved.lambda)));
  s.contact_warm = to_eigen(la::broadcast(comm, to_std(c.snapshot.contact_warm)));
  s.state.u = scatter_blocks(nodes, saved.u, d);
  nodes.scatter(saved.beta, s.state.beta);
  unpack_cells(scatter_blocks(cell_layout(part), to_eigen(pack_cells(saved)), 18), s.state);
  s.u_free = restrict_to_free(part.dofs, s.state.u).head(part.n_owned_dofs);
  if (head[3] != 0) {
    Vector w;
    nodes.scatter(c.snapshot.damage_warm, w);
    s.damage_warm = w.head(part.n_owned_nodes);
  }
  stepper.restore(s);
  return ResumePoint{s.state.n, s.state.t, c.pvd, c.totals};
}

fs::path write_checkpoint(const fs::path& dir, const Checkpoint& c, int keep) {
  const State& s = c.snapshot.state;
  auto payload = [&](Writer& w) {
    w.string(c.case_name);
    w.pod(c.fingerprint);
    w.pod<std::int64_t>(s.n);
    w.pod(s.t);
    w.vector(s.u);
    w.vector(s.beta);
    w.vector(s.lambda);
    w.vector(c.snapshot.u_free);
    w.tensors(s.sigma);
    w.tensors(s.eps);
    w.tensors(s.z);
    w.vector(c.snapshot.contact_warm);
    w.vector(c.snapshot.damage_warm);
    w.pod<std::uint64_t>(c.pvd.size());
    for (const auto& [t, f] : c.pvd) {
      w.pod(t);
      w.string(f);
    }
    const RunTotals& r = c.totals;
    for (double v : {r.max_contact_residual, r.max_damage_residual, r.seconds_sources, r.seconds_damage,
                     r.seconds_contact, r.seconds_stress, r.seconds_output})
      w.pod(v);
    w.pod<std::int64_t>(r.max_contact_iterations);
    w.pod<std::int64_t>(r.max_damage_iterations);
    w.pod<std::uint8_t>(r.all_ok ? 1 : 0);
    w.pod<std::int64_t>(r.last_n_active);
  };
  Writer measure;
  payload(measure);
  const fs::path path = dir / fmt::format("checkpoint_{:05d}.bin", s.n);
  write_file_atomic(path, [&](std::ostream& out) {
    out.write(kMagic, sizeof kMagic);
    const std::uint32_t version = kVersion, reserved = 0;
    const std::uint64_t size = measure.size(), sum = measure.checksum();
    out.write(reinterpret_cast<const char*>(&version), sizeof version);
    out.write(reinterpret_cast<const char*>(&reserved), sizeof reserved);
    out.write(reinterpret_cast<const char*>(&size), sizeof size);
    out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
    Writer w(&out);
    payload(w);
  });
  // Keep the newest `keep` checkpoints (an older one is the fallback if the
  // newest is ever damaged). Those of later steps are damaged or from a timeline
  // that this run replaced: a later --resume must not pick them.
  std::vector<fs::path> all;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (step_of(e.path()) > s.n) fs::remove(e.path(), ec);
    else if (step_of(e.path()) >= 0) all.push_back(e.path());
  std::sort(all.begin(), all.end(), [](const fs::path& a, const fs::path& b) { return step_of(a) > step_of(b); });
  for (std::size_t i = static_cast<std::size_t>(std::max(keep, 1)); i < all.size(); ++i) fs::remove(all[i], ec);
  return path;
}

CheckpointSchedule::CheckpointSchedule(int every, double seconds) : every_(every), seconds_(seconds) {
  require(seconds > 0, "--checkpoint-seconds must be > 0 (got {})", seconds);
}

bool CheckpointSchedule::due(int n) const {
  if (every_ >= 0) return every_ > 0 && n % every_ == 0;
  return std::chrono::duration<double>(Clock::now() - last_).count() >= seconds_;
}

Checkpoint read_checkpoint(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  require(in.good(), "checkpoint '{}': cannot read it", file.string());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string raw = ss.str();
  const std::string name = file.string();
  constexpr std::size_t header = sizeof kMagic + 2 * sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t);
  require(raw.size() >= header && std::memcmp(raw.data(), kMagic, sizeof kMagic) == 0,
          "checkpoint '{}': not a vpcontact checkpoint", name);
  std::uint32_t version;
  std::uint64_t size, sum;
  std::memcpy(&version, raw.data() + 8, 4);
  std::memcpy(&size, raw.data() + 16, 8);
  std::memcpy(&sum, raw.data() + 24, 8);
  require(version == kVersion, "checkpoint '{}': format version {}, this program reads version {}", name, version,
          kVersion);
  require(raw.size() - header == size, "checkpoint '{}': {} payload bytes, the header says {} (truncated?)", name,
          raw.size() - header, size);
  const std::string payload = raw.substr(header);
  require(fnv1a(payload.data(), payload.size()) == sum, "checkpoint '{}': checksum mismatch (damaged file)", name);

  Reader r(payload, name);
  Checkpoint c;
  State& s = c.snapshot.state;
  c.case_name = r.string();
  c.fingerprint = r.pod<std::uint64_t>();
  s.n = static_cast<int>(r.pod<std::int64_t>());
  s.t = r.pod<double>();
  s.u = r.vector();
  s.beta = r.vector();
  s.lambda = r.vector();
  c.snapshot.u_free = r.vector();
  s.sigma = r.tensors();
  s.eps = r.tensors();
  s.z = r.tensors();
  c.snapshot.contact_warm = r.vector();
  c.snapshot.damage_warm = r.vector();
  const auto n_pvd = r.pod<std::uint64_t>();
  require(n_pvd < (1u << 30), "checkpoint '{}': implausible PVD entry count", name);
  for (std::uint64_t i = 0; i < n_pvd; ++i) {
    const double t = r.pod<double>();
    c.pvd.emplace_back(t, r.string());
  }
  RunTotals& t = c.totals;
  for (double* v : {&t.max_contact_residual, &t.max_damage_residual, &t.seconds_sources, &t.seconds_damage,
                    &t.seconds_contact, &t.seconds_stress, &t.seconds_output})
    *v = r.pod<double>();
  t.max_contact_iterations = static_cast<int>(r.pod<std::int64_t>());
  t.max_damage_iterations = static_cast<int>(r.pod<std::int64_t>());
  t.all_ok = r.pod<std::uint8_t>() != 0;
  t.last_n_active = r.pod<std::int64_t>();
  require(r.done(), "checkpoint '{}': trailing bytes after the payload", name);
  return c;
}

std::optional<Checkpoint> find_checkpoint(const fs::path& dir, std::uint64_t fingerprint,
                                          std::vector<std::string>* skipped) {
  std::vector<fs::path> all;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (step_of(e.path()) >= 0) all.push_back(e.path());
  std::sort(all.begin(), all.end(), [](const fs::path& a, const fs::path& b) { return step_of(a) > step_of(b); });
  for (const auto& f : all) {
    try {
      Checkpoint c = read_checkpoint(f);
      if (c.fingerprint != fingerprint) {
        if (skipped) skipped->push_back(fmt::format("{}: written for another problem (case '{}')", f.string(), c.case_name));
        continue;
      }
      return c;
    } catch (const Error& e) {
      if (skipped) skipped->push_back(e.what());
    }
  }
  return std::nullopt;
}

}  // namespace vpc
