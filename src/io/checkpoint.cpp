#include "io/checkpoint.hpp"

#include "core/error.hpp"
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
  const std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}|{:.17g}|{:.17g}|{}|{}|{}", p.name, p.mesh.dim(),
                                      p.mesh.n_nodes(), p.mesh.n_cells(), s.dofs().n_free(), s.contact_nodes().size(),
                                      p.n_steps, p.final_time, p.kappa, p.elasticity.name(), p.law->describe(),
                                      p.source->describe());
  return fnv1a(key.data(), key.size());
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
