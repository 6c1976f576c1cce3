#include "io/checkpoint_file.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "io/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace vpc::checkpoint_file {

namespace {

constexpr char kMagic[8] = {'V', 'P', 'C', 'C', 'K', 'P', 'T', '\0'};
static_assert(kHeaderBytes == sizeof kMagic + 2 * sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t));

}  // namespace

Array file_array(std::string_view field) {
  for (const FileArray& a : kFileArrays)
    if (a.field == field) return a.array;
  fail("internal: the state field '{}' has no place in the checkpoint format (checkpoint_file.hpp: kFileArrays)", field);
}

// ---------------------------------------------------------------------------------
// File names: checkpoint_NNNNN.bin (the whole state, or piece 0) and
// checkpoint_NNNNN.pRRRR-of-PPPP.bin (piece r ≥ 1 of P).

fs::path main_file(const fs::path& dir, long long n) { return dir / fmt::format("checkpoint_{:05d}.bin", n); }

fs::path piece_file(const fs::path& dir, long long n, long long r, long long p) {
  if (r == 0) return main_file(dir, n);
  return dir / fmt::format("checkpoint_{:05d}.p{:04d}-of-{:04d}.bin", n, r, p);
}

namespace {

/// The step of a checkpoint file or piece; -1 for any other file.
int step_of(const fs::path& p) {
  const std::string f = p.filename().string();
  if (f.rfind("checkpoint_", 0) != 0 || !f.ends_with(".bin") || f.size() < 16 || !std::isdigit(f[11])) return -1;
  return std::atoi(f.c_str() + 11);
}

bool is_main(const fs::path& p) {
  const int n = step_of(p);
  return n >= 0 && p.filename() == main_file({}, n).filename();
}

}  // namespace

std::vector<long long> checkpoint_steps(const fs::path& dir) {
  std::vector<long long> steps;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (is_main(e.path())) steps.push_back(step_of(e.path()));
  std::sort(steps.rbegin(), steps.rend());
  return steps;
}

void remove_stale(const fs::path& dir, long long n, const std::set<fs::path>& written, int keep) {
  std::set<fs::path> names;
  for (const fs::path& p : written) names.insert(p.filename());
  std::set<long long> kept;
  for (long long s : checkpoint_steps(dir))
    if (s <= n && static_cast<int>(kept.size()) < std::max(keep, 1)) kept.insert(s);
  std::vector<fs::path> doomed;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const long long s = step_of(e.path());
    if (s > n || (s == n && !names.count(e.path().filename())) || (s >= 0 && s < n && !kept.count(s)))
      doomed.push_back(e.path());
  }
  for (const auto& p : doomed) fs::remove(p, ec);
}

// ---------------------------------------------------------------------------------
// Writing: the payload is streamed once, its size and checksum counted as it goes and
// written into the header at the end; nothing but the array at hand is in memory.

FileWriter::FileWriter(const fs::path& path, const FileContent& f) : file_(path), f_(f) {
  f_.arrays = {};
  std::ostream& out = file_.stream();
  out.write(kMagic, sizeof kMagic);
  // The header's second u32: the contact block where it is above 1, else 0, so that the
  // checkpoints of a normal law are those of earlier versions.
  const std::uint32_t version = f.head ? kPiece : kWhole;
  const auto block = static_cast<std::uint32_t>(f.contact_block == 1 ? 0 : f.contact_block) |
                     (f.surface && !f.surface->empty() ? kSurfaceFlag : 0u);
  const std::uint64_t unknown = 0;  // the payload's size and checksum: commit() writes them
  out.write(reinterpret_cast<const char*>(&version), sizeof version);
  out.write(reinterpret_cast<const char*>(&block), sizeof block);
  out.write(reinterpret_cast<const char*>(&unknown), sizeof unknown);
  out.write(reinterpret_cast<const char*>(&unknown), sizeof unknown);
  string(f.case_name);
  pod(f.fingerprint);
  string(f.problem_key);
  const bool first = f.whole_or_first();
  pod<std::uint64_t>(first && f.keys ? f.keys->size() : 0);
  if (first && f.keys)
    for (const auto& [key, value] : *f.keys) {
      string(key);
      string(value);
    }
  pod(f.n);
  pod(f.t);
  pod(f.grid.final_time);
  pod(f.grid.steps);
  if (f.head)
    for (std::uint64_t v : {f.head->count, f.head->index, f.head->node_begin, f.head->node_end, f.head->cell_begin,
                            f.head->cell_end})
      pod(v);
}

void FileWriter::array(Array a, Values v) {
  require(a == next_ && a < arrays_in_file(f_.contact_block), "internal: checkpoint array {} written where {} is due",
          static_cast<int>(a), next_);
  pod<std::uint64_t>(v.size());
  bytes(v.data(), v.size_bytes());
  ++next_;
}

PieceSum FileWriter::commit(const std::vector<PieceSum>& others) {
  require(next_ == arrays_in_file(f_.contact_block), "internal: a checkpoint file committed after {} of its {} arrays",
          next_, arrays_in_file(f_.contact_block));
  if (f_.whole_or_first()) {
    if (f_.surface && !f_.surface->empty()) {  // by name: each field's name, width and values
      pod<std::uint64_t>(f_.surface->size());
      for (const SurfaceField& s : *f_.surface) {
        string(s.name);
        pod<std::uint64_t>(static_cast<std::uint64_t>(s.width));
        pod<std::uint64_t>(static_cast<std::uint64_t>(s.values.size()));
        bytes(s.values.data(), static_cast<std::size_t>(s.values.size()) * sizeof(double));
      }
    }
    pod<std::uint64_t>(f_.pvd->size());
    for (const auto& [t, file] : *f_.pvd) {
      pod(t);
      string(file);
    }
    const RunTotals& r = *f_.totals;
    for (double v : {r.max_contact_residual, r.max_damage_residual, r.seconds_sources, r.seconds_damage,
                     r.seconds_contact, r.seconds_stress, r.seconds_output})
      pod(v);
    pod<std::int64_t>(r.max_contact_iterations);
    pod<std::int64_t>(r.max_damage_iterations);
    pod<std::uint8_t>(r.all_ok ? 1 : 0);
    pod<std::int64_t>(r.last_n_active);
    if (f_.contact_block > 1)  // friction's totals: only in a frictional run's files
      for (double v : {r.max_friction_bound, r.max_stick_slip, r.max_slip_direction, r.dissipation}) pod(v);
    pod<std::uint64_t>(r.resume_changes.size());
    for (const ResumeChange& c : r.resume_changes) {
      pod<std::int64_t>(c.step);
      string(c.key);
      string(c.before);
      string(c.after);
    }
    for (const PieceSum& s : others) {
      pod(s.size);
      pod(s.checksum);
    }
  }
  std::ostream& out = file_.stream();
  out.seekp(sizeof kMagic + 2 * sizeof(std::uint32_t));
  out.write(reinterpret_cast<const char*>(&sum_.size), sizeof sum_.size);
  out.write(reinterpret_cast<const char*>(&sum_.checksum), sizeof sum_.checksum);
  file_.commit();
  return sum_;
}

void FileWriter::string(std::string_view s) {
  pod<std::uint64_t>(s.size());
  bytes(s.data(), s.size());
}

void FileWriter::bytes(const void* p, std::size_t n) {
  if (n == 0) return;
  sum_.size += n;
  sum_.checksum = fnv1a(p, n, sum_.checksum);
  file_.stream().write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
}

PieceSum write_file(const fs::path& path, const FileContent& f) {
  FileWriter w(path, f);
  for (int a = 0; a < arrays_in_file(f.contact_block); ++a)
    w.array(static_cast<Array>(a), f.arrays[static_cast<std::size_t>(a)]);
  return w.commit(f.others);
}

// ---------------------------------------------------------------------------------
// Reading: a file's header and fields are read and its arrays located; a process
// then reads only the entries it needs.



CheckpointFile::CheckpointFile(const fs::path& file, bool verify) : path_(file), in_(file, std::ios::binary) {
  require(in_.good(), "checkpoint '{}': cannot read it", name());
  std::error_code ec;
  const std::uint64_t bytes = fs::file_size(file, ec);
  char magic[sizeof kMagic] = {};
  std::uint32_t block = 0;
  in_.read(magic, sizeof magic);
  in_.read(reinterpret_cast<char*>(&version_), sizeof version_);
  in_.read(reinterpret_cast<char*>(&block), sizeof block);
  in_.read(reinterpret_cast<char*>(&sum_.size), sizeof sum_.size);
  in_.read(reinterpret_cast<char*>(&sum_.checksum), sizeof sum_.checksum);
  require(!ec && in_.good() && bytes >= kHeaderBytes && std::memcmp(magic, kMagic, sizeof kMagic) == 0,
          "checkpoint '{}': not a vpcontact checkpoint", name());
  require(version_ == kWhole || version_ == kPiece || version_ == kWholeV4 || version_ == kPieceV5,
          "checkpoint '{}': format version {}, this program reads versions {} to {}", name(), version_, kWholeV4,
          kPiece);
  require(bytes - kHeaderBytes == sum_.size, "checkpoint '{}': {} payload bytes, the header says {} (truncated?)",
          name(), bytes - kHeaderBytes, sum_.size);
  has_surface = (block & kSurfaceFlag) != 0;
  block &= ~kSurfaceFlag;
  require(block < 1024, "checkpoint '{}': a contact block of {} numbers per contact node (damaged header?)", name(),
          block);
  contact_block_ = block == 0 ? 1 : static_cast<int>(block);
  end_ = bytes;
  if (verify) verify_checksum();
  parse();
}

void CheckpointFile::verify_checksum() {
  std::vector<char> buffer(1 << 20);
  std::uint64_t h = fnv1a(nullptr, 0), left = sum_.size;
  in_.seekg(static_cast<std::streamoff>(kHeaderBytes));
  while (left > 0 && in_.good()) {
    const auto chunk = static_cast<std::streamsize>(std::min<std::uint64_t>(left, buffer.size()));
    in_.read(buffer.data(), chunk);
    h = fnv1a(buffer.data(), static_cast<std::size_t>(in_.gcount()), h);
    left -= static_cast<std::uint64_t>(in_.gcount());
  }
  require(left == 0, "checkpoint '{}': cannot read it", name());
  require(h == sum_.checksum, "checkpoint '{}': checksum mismatch (damaged file)", name());
}

std::string CheckpointFile::string() {
  const auto n = pod<std::uint64_t>();
  need(n);
  std::string s(n, '\0');
  in_.read(s.data(), static_cast<std::streamsize>(n));
  at_ += n;
  return s;
}

void CheckpointFile::parse() {
  in_.seekg(static_cast<std::streamoff>(at_));
  case_name = string();
  fingerprint = pod<std::uint64_t>();
  problem_key = string();
  const bool pieces = version_ == kPiece || version_ == kPieceV5;
  if (has_keys()) {
    const auto count = pod<std::uint64_t>();
    need_items(count, 2 * sizeof(std::uint64_t));  // each key and value at least its length
    keys.reserve(count);
    for (std::uint64_t i = 0; i < count; ++i) {
      std::string key = string();
      keys.emplace_back(std::move(key), string());
    }
  }
  n = pod<std::int64_t>();
  t = pod<double>();
  if (has_keys()) {
    grid.final_time = pod<double>();
    grid.steps = pod<std::int64_t>();
    require(grid.steps == 0 || (grid.steps >= n && n >= 0 && std::isfinite(grid.final_time) && grid.final_time > 0),
            "checkpoint '{}': a uniform grid of {} steps over T = {} for step {} (damaged?)", name(), grid.steps,
            grid.final_time, n);
  }
  if (pieces)
    for (std::uint64_t* v : {&head_.count, &head_.index, &head_.node_begin, &head_.node_end, &head_.cell_begin,
                             &head_.cell_end})
      *v = pod<std::uint64_t>();
  for (int a = 0; a < arrays_in_file(contact_block_); ++a) {  // located, not read
    count_[a] = pod<std::uint64_t>();
    require(count_[a] <= (end_ - at_) / sizeof(double), "checkpoint '{}': truncated payload", name());
    offset_[a] = at_;
    at_ += count_[a] * sizeof(double);
    in_.seekg(static_cast<std::streamoff>(at_));
  }
  for (Array a : {kSigma, kEps, kZ})
    require(count_[a] % 6 == 0, "checkpoint '{}': a tensor array has {} values, not a multiple of 6", name(),
            count_[a]);
  if (!pieces) head_ = {0, 1, 0, count_[kBeta], 0, count_[kSigma] / 6};
  require(head_.index < head_.count && head_.count >= 1 && head_.count < (1u << 24) &&
              head_.node_begin <= head_.node_end &&
              head_.cell_begin <= head_.cell_end && count_[kBeta] == n_nodes() && count_[kSigma] == 6 * n_cells() &&
              count_[kEps] == 6 * n_cells() && count_[kZ] == 6 * n_cells() &&
              (count_[kDamageWarm] == 0 || count_[kDamageWarm] == n_nodes()) &&
              (n_nodes() == 0 ? count_[kU] == 0 : count_[kU] % n_nodes() == 0) &&
              (head_.index == 0 || count_[kLambda] + count_[kContactWarm] + count_[kTimes] + count_[kStepControl] +
                                           count_[kSlipStep] + count_[kSlip] + count_[kContactStatus] ==
                                       0) &&
              count_[kLambda] % static_cast<std::uint64_t>(contact_block_) == 0 &&
              (contact_block_ == 1 || count_[kSlip] + count_[kSlipStep] + count_[kContactStatus] == 0 ||
               (count_[kSlip] * static_cast<std::uint64_t>(contact_block_) == count_[kLambda] &&
                count_[kContactStatus] == count_[kSlip] &&
                count_[kSlipStep] == count_[kSlip] * static_cast<std::uint64_t>(contact_block_ - 1))) &&
              (head_.index != 0 || count_[kTimes] == (grid.steps > 0 ? 0 : static_cast<std::uint64_t>(n) + 1)),
          "checkpoint '{}': its arrays do not match its blocks (nodes [{}, {}), cells [{}, {}))", name(),
          head_.node_begin, head_.node_end, head_.cell_begin, head_.cell_end);
  if (head_.index == 0) {
    if (has_surface) {
      const auto n_fields = pod<std::uint64_t>();
      need_items(n_fields, 3 * sizeof(std::uint64_t));
      const std::uint64_t nodes = count_[kLambda] / static_cast<std::uint64_t>(contact_block_);
      for (std::uint64_t i = 0; i < n_fields; ++i) {
        SurfaceField f;
        f.name = string();
        const auto width = pod<std::uint64_t>(), size = pod<std::uint64_t>();
        require(width >= 1 && width < 1024 && size == width * nodes,
                "checkpoint '{}': the per-node state '{}' has {} values of width {} for {} contact nodes (damaged?)",
                name(), f.name, size, width, nodes);
        need_items(size, sizeof(double));
        f.width = static_cast<int>(width);
        f.values.resize(static_cast<Eigen::Index>(size));
        in_.read(reinterpret_cast<char*>(f.values.data()), static_cast<std::streamsize>(size * sizeof(double)));
        at_ += size * sizeof(double);
        surface.push_back(std::move(f));
      }
    }
    const auto n_pvd = pod<std::uint64_t>();
    require(n_pvd < (1u << 30), "checkpoint '{}': implausible PVD entry count", name());
    for (std::uint64_t i = 0; i < n_pvd; ++i) {
      const double time = pod<double>();
      pvd.emplace_back(time, string());
    }
    for (double* v : {&totals.max_contact_residual, &totals.max_damage_residual, &totals.seconds_sources,
                      &totals.seconds_damage, &totals.seconds_contact, &totals.seconds_stress, &totals.seconds_output})
      *v = pod<double>();
    totals.max_contact_iterations = static_cast<int>(pod<std::int64_t>());
    totals.max_damage_iterations = static_cast<int>(pod<std::int64_t>());
    totals.all_ok = pod<std::uint8_t>() != 0;
    totals.last_n_active = pod<std::int64_t>();
    if (contact_block_ > 1)
      for (double* v : {&totals.max_friction_bound, &totals.max_stick_slip, &totals.max_slip_direction,
                        &totals.dissipation})
        *v = pod<double>();
    if (has_keys()) {
      const auto count = pod<std::uint64_t>();
      need_items(count, 4 * sizeof(std::uint64_t));
      for (std::uint64_t i = 0; i < count; ++i) {
        ResumeChange c;
        c.step = pod<std::int64_t>();
        c.key = string();
        c.before = string();
        c.after = string();
        totals.resume_changes.push_back(std::move(c));
      }
    }
    if (pieces) {
      need((head_.count - 1) * 2 * sizeof(std::uint64_t));
      others.resize(head_.count - 1);
      for (PieceSum& s : others) {
        s.size = pod<std::uint64_t>();
        s.checksum = pod<std::uint64_t>();
      }
    }
  }
  require(at_ == end_, "checkpoint '{}': trailing bytes after the payload", name());
}

std::vector<double> CheckpointFile::times() {
  if (grid.steps > 0) return grid.levels(n);
  std::vector<double> v(count(kTimes));
  read(kTimes, 0, v.size(), v.data());
  return v;
}

void CheckpointFile::read(Array a, std::uint64_t first, std::uint64_t n, double* out) {
  if (n == 0) return;
  require(first + n <= count_[a], "internal: values [{}, {}) of an array of {} in '{}'", first, first + n, count_[a],
          name());
  in_.seekg(static_cast<std::streamoff>(offset_[a] + first * sizeof(double)));
  in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n * sizeof(double)));
  require(in_.good(), "checkpoint '{}': cannot read it", name());
}

CheckpointFile open_piece(const CheckpointFile& first, std::uint64_t r, bool verify) {
  const std::uint64_t p = first.head().count;
  const fs::path file = piece_file(first.path().parent_path(), first.n, static_cast<long long>(r), static_cast<long long>(p));
  std::error_code ec;
  require(fs::exists(file, ec), "checkpoint '{}': piece {} of {} ('{}') is missing", first.name(), r, p,
          file.filename().string());
  CheckpointFile f(file, verify);
  require(f.version() == first.version() && f.head().index == r && f.head().count == p && f.fingerprint == first.fingerprint &&
              f.n == first.n && f.t == first.t && f.case_name == first.case_name,
          "checkpoint '{}': not piece {} of {} of the checkpoint of step {}", f.name(), r, p, first.n);
  require(f.sum() == first.others[r - 1],
          "checkpoint '{}': not the piece that '{}' lists (its size or checksum differ: left by another write?)",
          f.name(), first.path().filename().string());
  return f;
}


}  // namespace vpc::checkpoint_file
