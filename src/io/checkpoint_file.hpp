#pragma once
// The checkpoint files (io/checkpoint.hpp says what they hold): their names, the
// writer of one file (streamed array by array, atomic, checksummed) and the reader
// that locates its arrays, so that a process reads only the entries it needs. Format
// versions 6 (the whole state in one file) and 7 (one piece of a checkpoint written by P
// processes); 4 and 5, the same before the case's keys and the time grid, are read too;
// docs/reliability.md. Used by io/checkpoint.cpp only.
#include "core/hash.hpp"
#include "core/sym_tensor.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/run_output.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vpc::checkpoint_file {

namespace fs = std::filesystem;

// 6: the whole state in one file; 7: one piece of a checkpoint written by several processes.
// 4 and 5: the same without the case's keys, the time grid and the changes on resume (read,
// for tools; a resume refuses them: it cannot compare their case with its own). 2 and 3:
// before the problem key, the time levels and the step-size state.
constexpr std::uint32_t kWhole = 6, kPiece = 7, kWholeV4 = 4, kPieceV5 = 5;
constexpr std::size_t kHeaderBytes = 8 + 2 * sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t);
/// In the header's contact-block word: the file (piece 0) holds the contact laws' per-node state
/// (State::surface) after its arrays; files of a run without such state are those of before.
constexpr std::uint32_t kSurfaceFlag = 1u << 16;

// File names: checkpoint_NNNNN.bin (the whole state, or piece 0) and
// checkpoint_NNNNN.pRRRR-of-PPPP.bin (piece r ≥ 1 of P).
fs::path main_file(const fs::path& dir, long long n);
fs::path piece_file(const fs::path& dir, long long n, long long r, long long p);
/// The steps of the checkpoints (their checkpoint_NNNNN.bin) in `dir`, newest first.
std::vector<long long> checkpoint_steps(const fs::path& dir);
/// After the checkpoint of step n (its files `written`): removes the files of later
/// steps (damaged, or of a timeline this run replaced: a later --resume must not pick
/// them), step n's pieces that this write did not make (another rank count), and the
/// checkpoints older than the newest `keep` (an older one is the fallback if the newest
/// is ever damaged).
void remove_stale(const fs::path& dir, long long n, const std::set<fs::path>& written, int keep);

using Values = std::span<const double>;
inline Values values(const Eigen::VectorXd& v) { return {v.data(), static_cast<std::size_t>(v.size())}; }
inline Values values(const std::vector<SymTensor>& t) { return {t.empty() ? nullptr : t[0].c.data(), 6 * t.size()}; }

/// Which piece of how many a file is, and the blocks of the numbering of the mesh
/// as read that it holds.
struct PieceHead {
  std::uint64_t index = 0, count = 1;
  std::uint64_t node_begin = 0, node_end = 0, cell_begin = 0, cell_end = 0;
};

/// A piece's payload size and checksum (piece 0 lists the others').
struct PieceSum {
  std::uint64_t size = 0, checksum = 0;
  bool operator==(const PieceSum&) const = default;
};

/// The arrays of a file, in their order: the state's stored fields (io/state_fields.hpp)
/// where kFileArrays places them, u on the free dofs, the solvers' warm states, and
/// kTimes: t_0 … t_n (empty where the file gives their uniform grid); kStepControl: StepControlState::values (both in piece 0 only); then,
/// only in the files of a frictional run (contact block > 1, in the header), friction's
/// fields of the contact nodes (piece 0 only): files without friction are those of before.
enum Array {
  kU, kBeta, kLambda, kUFree, kSigma, kEps, kZ, kContactWarm, kDamageWarm, kTimes, kStepControl,
  kSlipStep, kSlip, kContactStatus, kArrays
};
/// The arrays a file of this contact block has: all, or those before friction's.
constexpr int arrays_in_file(int contact_block) { return contact_block > 1 ? kArrays : kSlipStep; }

/// Where the format (versions 4 and 5) has each stored state field (StateField::name). A
/// stored field added to the table needs its place here, in a new format version
/// (tests/unit/io/test_state_fields.cpp checks that every one has one).
struct FileArray {
  std::string_view field;
  Array array;
};
constexpr FileArray kFileArrays[] = {{"u", kU},         {"beta", kBeta},  {"lambda", kLambda},
                                     {"sigma", kSigma},   {"eps", kEps},    {"z", kZ},
                                     {"slip_step", kSlipStep}, {"slip", kSlip}, {"contact_status", kContactStatus}};
/// The file's array of a stored state field; throws vpc::Error when the format has none.
Array file_array(std::string_view field);

/// What one file holds, as views (nothing copied). Without a head: version 6, the
/// whole state. With one: version 7, piece head->index, its state arrays its blocks.
struct FileContent {
  std::string_view case_name;
  std::uint64_t fingerprint = 0;
  std::string_view problem_key;  // what the fingerprint is made of (problem_key)
  const CaseKeys* keys = nullptr;  // the case's keys (written in version 6 and piece 0)
  std::int64_t n = 0;
  double t = 0;
  UniformGrid grid;  // steps > 0: the time levels are this grid's, and kTimes is empty
  std::optional<PieceHead> head;
  int contact_block = 1;  // State::contact_block: λ's numbers per contact node
  std::array<Values, kArrays> arrays;
  /// The contact laws' per-node state (State::surface; written in version 6 and piece 0, flagged in
  /// every piece's header); null or empty: none.
  const std::vector<SurfaceField>* surface = nullptr;
  const std::vector<std::pair<double, std::string>>* pvd = nullptr;  // version 6 and piece 0
  const RunTotals* totals = nullptr;
  std::vector<PieceSum> others;  // piece 0: pieces 1 … P − 1
  bool whole_or_first() const { return !head || head->index == 0; }
};

/// Writes one file atomically; returns its payload's size and checksum.
PieceSum write_file(const fs::path& path, const FileContent& f);

/// One file written array by array as the caller forms them (a process forms one array's
/// block, writes it and frees it before the next: it never holds its whole state twice),
/// atomically (AtomicFile). The payload is written once: its size and checksum are counted
/// as it goes and written into the header by commit(), the bytes those of write_file. A
/// failure to open or write the file waits for commit(), so that the caller's collective
/// steps between the arrays go on with the other processes.
class FileWriter {
 public:
  /// The header and the fields before the arrays, from f (whose arrays it does not read;
  /// its pvd and totals must outlive the writer).
  FileWriter(const fs::path& path, const FileContent& f);
  /// The next array: a, in the format's order from kU to arrays_in_file(contact block).
  void array(Array a, Values v);
  /// After the last array: the fields after them (version 6 and piece 0: the PVD entries,
  /// the totals and `others`, the sizes and checksums of pieces 1 … P − 1), the header's
  /// size and checksum, and the file renamed into place. Throws vpc::Error.
  PieceSum commit(const std::vector<PieceSum>& others = {});

 private:
  template <typename T>
  void pod(const T& v) {
    bytes(&v, sizeof v);
  }
  void string(std::string_view s);
  void bytes(const void* p, std::size_t n);

  AtomicFile file_;
  FileContent f_;  // its fields but the arrays
  int next_ = 0;   // the next array
  PieceSum sum_{0, kFnv1aOffset};
};

/// One checkpoint file opened for reading. The constructor checks the header, the
/// payload size and (with `verify`) the checksum, streaming the payload, then reads
/// the fields and finds where each array starts. Throws vpc::Error naming the file.
class CheckpointFile {
 public:
  CheckpointFile(const fs::path& file, bool verify);

  const fs::path& path() const { return path_; }
  std::string name() const { return path_.string(); }
  std::uint32_t version() const { return version_; }
  PieceSum sum() const { return sum_; }
  /// The whole state's file: piece 0 of 1 whose blocks are the whole arrays.
  const PieceHead& head() const { return head_; }
  std::uint64_t n_nodes() const { return head_.node_end - head_.node_begin; }
  std::uint64_t n_cells() const { return head_.cell_end - head_.cell_begin; }
  std::uint64_t count(Array a) const { return count_[a]; }
  /// λ's numbers per contact node (State::contact_block) of the run that wrote it.
  int contact_block() const { return contact_block_; }
  /// Values [first, first + n) of array a into out.
  void read(Array a, std::uint64_t first, std::uint64_t n, double* out);
  Vector read(Array a) {
    Vector v(static_cast<Eigen::Index>(count(a)));
    read(a, 0, count(a), v.data());
    return v;
  }

  std::string case_name;
  std::uint64_t fingerprint = 0;
  std::string problem_key;
  /// Whether the file records its case's keys (versions 6 and 7; 4 and 5 do not).
  bool has_keys() const { return version_ == kWhole || version_ == kPiece; }
  CaseKeys keys;  // piece 0's
  std::int64_t n = 0;
  double t = 0;
  UniformGrid grid;  // steps > 0: kTimes is empty, the levels are the grid's
  std::vector<std::pair<double, std::string>> pvd;  // the whole state's file or piece 0
  RunTotals totals;
  std::vector<PieceSum> others;  // piece 0 of several
  /// Whether the run kept the contact laws' per-node state (kSurfaceFlag), and piece 0's copy of it.
  bool has_surface = false;
  std::vector<SurfaceField> surface;

  /// t_0 … t_n: kTimes, or the grid's levels (UniformGrid::levels). Piece 0 only.
  std::vector<double> times();

 private:
  void verify_checksum();
  void parse();
  void need(std::uint64_t bytes) const { require(bytes <= end_ - at_, "checkpoint '{}': truncated payload", name()); }
  /// `count` items of at least `bytes` each (a damaged count cannot overflow the product).
  void need_items(std::uint64_t count, std::uint64_t bytes) const {
    require(count <= (end_ - at_) / bytes, "checkpoint '{}': truncated payload", name());
  }
  template <typename T>
  T pod() {
    need(sizeof(T));
    T v;
    in_.read(reinterpret_cast<char*>(&v), sizeof v);
    at_ += sizeof v;
    return v;
  }
  std::string string();

  fs::path path_;
  std::ifstream in_;
  std::uint32_t version_ = 0;
  int contact_block_ = 1;
  PieceSum sum_;
  std::uint64_t at_ = kHeaderBytes, end_ = kHeaderBytes;  // file offsets: the next field, the payload's end
  PieceHead head_;
  std::array<std::uint64_t, kArrays> count_{}, offset_{};
};

/// Piece r of the checkpoint whose piece 0 is `first`: opened (with `verify`, its
/// checksum checked) and matched against what piece 0 lists. Throws vpc::Error.
CheckpointFile open_piece(const CheckpointFile& first, std::uint64_t r, bool verify);

}  // namespace vpc::checkpoint_file
