#include "io/checkpoint.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/quote.hpp"
#include "fem/assembly.hpp"
#include "io/checkpoint_file.hpp"
#include "io/state_fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <map>
#include <memory>
#include <set>

namespace vpc {

namespace fs = std::filesystem;

using namespace checkpoint_file;

namespace {

/// Appends `more` to `v`.
void append(Vector& v, const Vector& more) {
  const Eigen::Index n = v.size();
  v.conservativeResize(n + more.size());
  v.tail(more.size()) = more;
}

std::string surface_names(const std::vector<SurfaceField>& s) {
  if (s.empty()) return "(none)";
  std::string out;
  for (const SurfaceField& f : s) out += (out.empty() ? "" : ", ") + f.name;
  return out;
}

/// The whole state of a version-4 file or of a version-5 checkpoint (piece 0 and its pieces).
Checkpoint read_whole(CheckpointFile& f) {
  require(f.head().index == 0, "checkpoint '{}': piece {} of {}, not a checkpoint's first file", f.name(),
          f.head().index, f.head().count);
  Checkpoint c;
  State& s = c.snapshot.state;
  c.case_name = f.case_name;
  c.fingerprint = f.fingerprint;
  c.problem_key = f.problem_key;
  c.case_keys = f.keys;
  s.n = static_cast<int>(f.n);
  s.t = f.t;
  s.contact_block = f.contact_block();
  c.times = f.times();
  c.grid = f.grid;
  c.step_control = f.read(kStepControl);
  c.snapshot.contact_warm = f.read(kContactWarm);
  c.pvd = f.pvd;
  c.totals = f.totals;
  s.surface = f.surface;
  // The stored fields: those of contact nodes from piece 0, those of nodes and cells
  // piece after piece.
  std::array<Vector, kArrays> field;
  for (std::uint64_t r = 0; r < f.head().count; ++r) {
    std::optional<CheckpointFile> other;
    if (r > 0) other.emplace(open_piece(f, r, true));
    CheckpointFile& piece = r == 0 ? f : *other;
    require(piece.head().node_begin == static_cast<std::uint64_t>(field[kBeta].size()) &&
                piece.head().cell_begin == static_cast<std::uint64_t>(field[kSigma].size() / 6),
            "checkpoint '{}': its blocks do not follow those of the pieces before it", piece.name());
    for (const StateField& sf : state_fields())
      if (sf.stored() && (r == 0 || sf.location != FieldLocation::contact_node))
        append(field[file_array(sf.name)], piece.read(file_array(sf.name)));
    append(c.snapshot.u_free, piece.read(kUFree));
    append(c.snapshot.damage_warm, piece.read(kDamageWarm));
  }
  for (const StateField& sf : state_fields())
    if (sf.stored()) {
      const Vector& v = field[file_array(sf.name)];
      sf.assign(s, {v.data(), static_cast<std::size_t>(v.size())});
    }
  return c;
}

// ---------------------------------------------------------------------------------
// The stepper's state in blocks of the numbering of the mesh as read.

/// The part's cells as a layout (no ghosts) in the numbering of the mesh as read.
la::Layout cell_layout(const MeshPart& part) {
  const int n = part.mesh().n_cells();
  if (part.comm.serial()) return la::Layout(n);
  return la::Layout(part.comm, n, {}, {part.original_cell.begin(), part.original_cell.end()});
}

/// The stored fields of nodes and cells: the arrays of the blocks.
template <typename F>
void for_block_fields(F&& f) {
  for (const StateField& sf : state_fields())
    if (sf.stored() && sf.location != FieldLocation::contact_node) f(sf, file_array(sf.name));
}

/// The stepper's node and cell arrays in this process's blocks of the numbering of the
/// mesh as read (PETSc's split over the processes, or all on rank 0): nodes [node_begin,
/// node_end), cells [cell_begin, cell_end). One array at a time: each is formed when asked
/// (sent from the processes that own its entries, Layout::to_blocks) into the caller's
/// storage, which the caller frees before the next, so that no process holds more than one
/// of them besides the state. On one process an array is a view of the state's own (nothing
/// copied). Each call is collective, in the same order on every process.
class StateBlocks {
 public:
  StateBlocks(const TimeStepper& stepper, bool to_root)
      : stepper_(stepper),
        cells_(cell_layout(stepper.part())),
        node_split_(split(stepper.part().n_global_nodes, to_root)),
        cell_split_(split(stepper.part().n_global_cells, to_root)) {
    const int me = stepper.comm().rank();
    node_begin = node_split_.begin(me);
    node_end = node_split_.end(me);
    cell_begin = cell_split_.begin(me);
    cell_end = cell_split_.end(me);
  }

  long long node_begin = 0, node_end = 0, cell_begin = 0, cell_end = 0;

  /// A stored field of nodes or cells, f.components values per node or cell.
  Values field(const StateField& f, Vector& storage) const {
    const int width = f.components(stepper_.state(), stepper_.part().dofs.dim());
    return block(f.location == FieldLocation::node, f.values(stepper_.state()), width, storage);
  }
  /// 1 at each free dof, 0 at each prescribed one (d per node).
  Values free_dofs(Vector& storage) const {
    const DofMap& dofs = stepper_.part().dofs;
    storage.resize(dofs.n_full());
    for (int i = 0; i < dofs.n_full(); ++i) storage[i] = dofs.free_index(i) >= 0;
    return block(true, values(storage), dofs.dim(), storage);
  }
  /// The damage solver's warm start: one value per node, or none (on every process).
  Values damage_warm(Vector& storage) const {
    const la::Comm& comm = stepper_.comm();
    storage = stepper_.damage_warm_state();
    if (!comm.any(storage.size() > 0)) return {};
    comm.throw_if_any(storage.size() != stepper_.part().n_owned_nodes,
                      "internal: the damage solver's warm state is not a node field");
    return block(true, values(storage), 1, storage);
  }

 private:
  la::BlockSplit split(long long n, bool to_root) const {
    const int p = stepper_.comm().size();
    return to_root ? la::BlockSplit::first_only(n, p) : la::BlockSplit(n, p);
  }
  /// `v` (the part's numbering: owned entries first, `width` values each) as this
  /// process's block of nodes or cells: a view of v on one process, else in `storage`
  /// (which v may be a view of: it is replaced once the block is formed).
  Values block(bool of_nodes, Values v, int width, Vector& storage) const {
    const la::Layout& layout = of_nodes ? *stepper_.part().node_layout : cells_;
    if (layout.comm().serial()) return v.first(static_cast<std::size_t>(layout.n_owned()) * width);
    storage = layout.to_blocks(Eigen::Map<const Vector>(v.data(), static_cast<Eigen::Index>(v.size())),
                               of_nodes ? node_split_ : cell_split_, width);
    return values(storage);
  }

  const TimeStepper& stepper_;
  la::Layout cells_;
  la::BlockSplit node_split_, cell_split_;
};

/// The stored field whose file array is a (a node, cell or contact-node field).
const StateField& stored_field(Array a) {
  for (const StateField& f : state_fields())
    if (f.stored() && file_array(f.name) == a) return f;
  fail("internal: the checkpoint array {} holds no stored state field", static_cast<int>(a));
}

/// u at the free dofs (`free`: 1 there, 0 at the prescribed ones), in DofMap's numbering
/// of the mesh as read: node-major, prescribed components dropped.
Vector free_values(Values u, Values free) {
  Vector out(static_cast<Eigen::Index>(std::count_if(free.begin(), free.end(), [](double f) { return f != 0; })));
  Eigen::Index k = 0;
  for (std::size_t i = 0; i < u.size(); ++i)
    if (free[i] != 0) out[k++] = u[i];
  return out;
}

/// A checkpoint file that this process writes: piece q, its nodes [n0, n1) and cells
/// [c0, c1) counted from the first of the process's blocks.
struct PieceWriter {
  int q;
  long long n0, n1, c0, c1;
  std::unique_ptr<FileWriter> file;
  Vector u_free;  // from u's block until its place in the file
};

/// Writes the stepper's arrays into this process's pieces `mine`, in the file's order. Each
/// node or cell array is formed as this process's block (collective), written into each
/// piece its part, and freed before the next; the others (λ, the contact warm state, the
/// times (none where their grid is stored), the step-size state: the same on every process)
/// go whole into piece 0.
void write_arrays(const TimeStepper& stepper, const StateBlocks& blocks, Values contact_warm, Values times,
                  Values control, std::vector<PieceWriter>& mine) {
  const State& st = stepper.state();
  const int d = stepper.part().dofs.dim();
  enum class Part { nodes, cells, first };
  auto write = [&](Array a, Values v, Part part, int width) {
    for (PieceWriter& m : mine) {
      Values of_m;
      if (part == Part::first) {
        if (m.q == 0) of_m = v;
      } else if (!v.empty()) {
        const long long b = part == Part::nodes ? m.n0 : m.c0, e = part == Part::nodes ? m.n1 : m.c1;
        of_m = v.subspan(static_cast<std::size_t>(b * width), static_cast<std::size_t>((e - b) * width));
      }
      m.file->array(a, of_m);
    }
  };
  for (int i = 0; i < arrays_in_file(st.contact_block); ++i) {
    const auto a = static_cast<Array>(i);
    Vector block;  // this array's block, freed at the end of the iteration
    if (a == kUFree) {
      for (PieceWriter& m : mine) {
        m.file->array(a, values(m.u_free));
        m.u_free = Vector();
      }
    } else if (a == kContactWarm) {
      write(a, contact_warm, Part::first, 1);
    } else if (a == kDamageWarm) {
      write(a, blocks.damage_warm(block), Part::nodes, 1);
    } else if (a == kTimes) {
      write(a, times, Part::first, 1);
    } else if (a == kStepControl) {
      write(a, control, Part::first, 1);
    } else if (const StateField& f = stored_field(a); f.location == FieldLocation::contact_node) {
      write(a, f.values(st), Part::first, 1);
    } else {
      const Values v = blocks.field(f, block);
      write(a, v, f.location == FieldLocation::node ? Part::nodes : Part::cells, f.components(st, d));
      if (a == kU) {  // u on the free dofs of each piece, written after β and λ
        Vector mask;
        const Values free = blocks.free_dofs(mask);
        for (PieceWriter& m : mine) {
          const auto at = static_cast<std::size_t>(m.n0 * d), n = static_cast<std::size_t>((m.n1 - m.n0) * d);
          m.u_free = free_values(v.subspan(at, n), free.subspan(at, n));
        }
      }
    }
  }
}

/// The first error that `work` throws on any process (the lowest rank's message),
/// "" when it succeeds everywhere; every process returns the same. Collective.
template <typename F>
std::string first_error(const la::Comm& comm, F&& work) {
  try {
    la::collective(comm, work);
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

/// The entries [b0, b1) (`width` values each) of array a over the pieces `files`
/// (contiguous blocks: `nodes` or cells), read only where they overlap.
Vector read_block(std::vector<CheckpointFile>& files, Array a, bool nodes, long long b0, long long b1, int width) {
  Vector out((b1 - b0) * width);
  for (CheckpointFile& f : files) {
    const auto s = static_cast<long long>(nodes ? f.head().node_begin : f.head().cell_begin);
    const auto e = static_cast<long long>(nodes ? f.head().node_end : f.head().cell_end);
    const long long lo = std::max(s, b0), hi = std::min(e, b1);
    if (lo < hi)
      f.read(a, static_cast<std::uint64_t>((lo - s) * width), static_cast<std::uint64_t>((hi - lo) * width),
             out.data() + (lo - b0) * width);
  }
  return out;
}

}  // namespace

std::string problem_key(const TimeStepper& s) {
  const Problem& p = s.problem();
  const MeshPart& part = s.part();
  std::string key = fmt::format("case={}|dimension={}|nodes={}|cells={}|free dofs={}|contact nodes={}|kappa={:.17g}|"
                                "elasticity={}|G={}|phi={}",
                                p.name, part.dofs.dim(), part.n_global_nodes, part.n_global_cells, part.n_global_dofs,
                                part.n_contact, p.kappa, p.elasticity.name(), p.law->describe(), p.source->describe());
  for (const Material& m : p.materials)
    key += fmt::format("|material {}=E {:.17g}, nu {:.17g}; G: {}; phi: {}", m.name, m.elasticity.young(),
                       m.elasticity.poisson(), m.law->describe(), m.source->describe());
  for (const Body& b : p.bodies) {
    const Material& m = b.material;
    key += fmt::format("|body {}=kappa {:.17g}; E {:.17g}, nu {:.17g}; G: {}; phi: {}", b.name, b.kappa,
                       m.elasticity.young(), m.elasticity.poisson(), m.law->describe(), m.source->describe());
  }
  return key;
}

std::uint64_t problem_fingerprint(const TimeStepper& s) {
  const std::string key = problem_key(s);
  return fnv1a(key.data(), key.size());
}

std::string problem_key_difference(const std::string& saved, const std::string& now) {
  // name=value fields separated by '|' (a value holding '|' only makes the list coarser)
  auto fields = [](const std::string& key) {
    std::vector<std::pair<std::string, std::string>> out;
    std::size_t at = 0;
    while (at <= key.size()) {
      const std::size_t end = std::min(key.find('|', at), key.size());
      const std::string field = key.substr(at, end - at);
      const std::size_t eq = field.find('=');
      out.emplace_back(field.substr(0, eq), eq == std::string::npos ? "" : field.substr(eq + 1));
      at = end + 1;
    }
    return out;
  };
  const auto a = fields(saved), b = fields(now);
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  for (const auto& [name, value] : a) {
    const auto it = std::find_if(b.begin(), b.end(), [&](const auto& f) { return f.first == name; });
    if (it == b.end())
      add(fmt::format("{} = {} in the checkpoint, none in this case", name, value));
    else if (it->second != value)
      add(fmt::format("{} = {} in the checkpoint, {} in this case", name, value, it->second));
  }
  for (const auto& [name, value] : b)
    if (std::none_of(a.begin(), a.end(), [&](const auto& f) { return f.first == name; }))
      add(fmt::format("{} = {} in this case, none in the checkpoint", name, value));
  return out.empty() ? "a problem written by another version of vpcontact" : out;
}

std::vector<double> UniformGrid::levels(std::int64_t n) const {
  Problem grid;  // Problem::time_at, the one formula of a uniform grid's levels
  grid.final_time = final_time;
  grid.n_steps = static_cast<int>(steps);
  std::vector<double> t(static_cast<std::size_t>(n) + 1);
  for (std::int64_t i = 0; i <= n; ++i) t[static_cast<std::size_t>(i)] = grid.time_at(static_cast<int>(i));
  return t;
}

UniformGrid UniformGrid::of(const Problem& p, const std::vector<double>& times) {
  if (!p.uniform_steps() || times.size() > static_cast<std::size_t>(p.n_steps) + 1) return {};
  for (std::size_t i = 0; i < times.size(); ++i)
    if (times[i] != p.time_at(static_cast<int>(i))) return {};  // bit for bit, or the levels are stored
  return {p.final_time, p.n_steps};
}

bool may_change_on_resume(std::string_view key) {
  if (key == "output.probes" || key.starts_with("output.probes[")) return false;  // probes.csv's columns
  for (std::string_view section : {"time.", "output.", "solver."})
    if (key.starts_with(section)) return true;
  return key == "case.description";
}

std::vector<ResumeChange> case_changes(const CaseKeys& checkpoint, const CaseKeys& now) {
  std::map<std::string, std::pair<std::string, std::string>> both;  // key → (checkpoint's, this case's)
  for (const auto& [key, value] : checkpoint) both[key].first = value;
  for (const auto& [key, value] : now) both[key].second = value;
  std::vector<ResumeChange> out;
  for (const auto& [key, values] : both)
    if (values.first != values.second) out.push_back({0, key, values.first, values.second});
  return out;
}

std::string describe_change(const ResumeChange& c) {
  auto value = [](const std::string& v) { return v.empty() ? std::string("(not given)") : printable(v, 200); };
  return fmt::format("{}: {} → {}", printable(c.key, 200), value(c.before), value(c.after));
}

namespace {

/// Why the checkpoint `f` (its first file) cannot be continued by the case `keys`: a key that
/// may not change on resume differs (each named, with its value then and now), or the file
/// does not record its case; empty when it can. `changes`: the keys that changed and may.
std::string case_refusal(const CheckpointFile& f, const CaseKeys& keys, std::vector<ResumeChange>& changes) {
  changes.clear();
  if (!f.has_keys())
    return fmt::format("--resume: checkpoint '{}' is of format version {}, written by an earlier vpcontact that did "
                       "not record its case: it cannot be compared with this case, so it is not continued (run the "
                       "case afresh, or resume it with the vpcontact that wrote it)",
                       f.name(), f.version());
  std::string refused;
  for (ResumeChange& c : case_changes(f.keys, keys)) {
    if (may_change_on_resume(c.key))
      changes.push_back(std::move(c));
    else
      refused += (refused.empty() ? "" : "; ") + describe_change(c);
  }
  if (refused.empty()) return {};
  return fmt::format("--resume: checkpoint '{}' was written for another case: {}. Only T and the steps after the "
                     "checkpoint ([time]), the output settings ([output], but its probes), the solver settings "
                     "([solver]) and case.description may change on resume (docs/cases.md, \"Continuing a run\"): "
                     "give the checkpoint's values, or run the changed case afresh in another directory",
                     f.name(), refused);
}

}  // namespace

std::string time_levels_difference(const Problem& p, const std::vector<double>& times) {
  const int n = static_cast<int>(times.size()) - 1;
  const double t = times.back();
  if (t > p.final_time)
    return fmt::format("its step {} ends at t = {}, after this case's T = {}", n, t, p.final_time);
  if (p.step_control) return {};  // error-controlled steps go on from wherever the checkpoint is
  if (n > p.n_steps) return fmt::format("its step {} is beyond this case's N = {} steps", n, p.n_steps);
  for (int i = 1; i <= n; ++i)
    if (times[i] != p.time_at(i))
      return fmt::format("the steps differ from step {} on: t = {:.17g} in the checkpoint, {:.17g} in this case", i,
                         times[i], p.time_at(i));
  return {};
}

Snapshot gather_snapshot(const TimeStepper& stepper) {
  const StateBlocks blocks(stepper, true);
  const Vector contact_warm = stepper.contact_warm_state();  // collective: one value per contact row, the same everywhere
  const State& st = stepper.state();
  const bool root = stepper.comm().rank() == 0;
  Snapshot g;
  g.state.contact_block = st.contact_block;
  // One array at a time: each gathered, kept on rank 0, and its exchange's buffers freed.
  for_block_fields([&](const StateField& f, Array) {
    Vector block;
    const Values v = blocks.field(f, block);
    if (root) f.assign(g.state, v);
  });
  {
    Vector block;
    const Values free = blocks.free_dofs(block);
    if (root) g.u_free = free_values(values(g.state.u), free);
  }
  {
    Vector block;
    const Values warm = blocks.damage_warm(block);
    if (root) g.damage_warm = Eigen::Map<const Vector>(warm.data(), static_cast<Eigen::Index>(warm.size()));
  }
  if (!root) return {};
  g.state.n = st.n;
  g.state.t = st.t;
  for (const StateField& f : state_fields())
    if (f.stored() && f.location == FieldLocation::contact_node)  // every process holds all of them
      f.assign(g.state, f.values(st));
  g.state.surface = st.surface;  // replicated too
  g.contact_warm = contact_warm;
  return g;
}

void write_checkpoint(const TimeStepper& stepper, const fs::path& dir, const std::string& case_name,
                      const std::vector<std::pair<double, std::string>>& pvd, const RunTotals& totals, int pieces,
                      int keep, const CaseKeys& keys) {
  const la::Comm& comm = stepper.comm();
  const int p = comm.size(), me = comm.rank();
  pieces = pieces > 0 ? pieces : p;
  require(p == 1 || pieces == p, "internal: {} checkpoint pieces from {} processes", pieces, p);
  const State& st = stepper.state();
  const StateBlocks blocks(stepper, false);
  const Vector contact_warm = stepper.contact_warm_state();  // collective
  const std::string key = problem_key(stepper);
  const std::uint64_t fingerprint = fnv1a(key.data(), key.size());
  const Vector control = stepper.step_control_state().values();
  const UniformGrid grid = UniformGrid::of(stepper.problem(), stepper.times());
  // Piece q of `pieces`: this process's blocks (several processes), or a part of them (one
  // process, which writes all the pieces). Each file is opened, then written array by array.
  const la::BlockSplit node_split(stepper.part().n_global_nodes, pieces),
      cell_split(stepper.part().n_global_cells, pieces);
  std::vector<PieceWriter> mine;
  for (int q = p == 1 ? 0 : me; q < (p == 1 ? pieces : me + 1); ++q) {
    FileContent f;
    f.case_name = case_name;
    f.fingerprint = fingerprint;
    f.problem_key = key;
    f.keys = &keys;
    f.n = st.n;
    f.t = st.t;
    f.grid = grid;
    f.contact_block = st.contact_block;
    f.surface = &st.surface;
    if (pieces > 1)
      f.head = PieceHead{static_cast<std::uint64_t>(q), static_cast<std::uint64_t>(pieces),
                         static_cast<std::uint64_t>(node_split.begin(q)), static_cast<std::uint64_t>(node_split.end(q)),
                         static_cast<std::uint64_t>(cell_split.begin(q)), static_cast<std::uint64_t>(cell_split.end(q))};
    if (q == 0) {  // the run's data, rank 0's
      f.pvd = &pvd;
      f.totals = &totals;
    }
    mine.push_back({q, node_split.begin(q) - blocks.node_begin, node_split.end(q) - blocks.node_begin,
                    cell_split.begin(q) - blocks.cell_begin, cell_split.end(q) - blocks.cell_begin,
                    std::make_unique<FileWriter>(piece_file(dir, st.n, q, pieces), f), Vector()});
  }
  write_arrays(stepper, blocks, values(contact_warm), grid.steps > 0 ? Values() : Values(stepper.times()),
               values(control), mine);
  // Pieces 1 … P − 1 in place first, then piece 0, which lists them: a checkpoint whose
  // piece 0 is in place has all its pieces.
  std::vector<PieceSum> sums(static_cast<std::size_t>(pieces));
  la::collective(comm, [&] {
    for (PieceWriter& m : mine)
      if (m.q > 0) sums[m.q] = m.file->commit();
  });
  if (p > 1) {
    const std::vector<long long> size = comm.all_gather(std::bit_cast<long long>(sums[me].size));
    const std::vector<long long> checksum = comm.all_gather(std::bit_cast<long long>(sums[me].checksum));
    for (int q = 0; q < p; ++q) sums[q] = {std::bit_cast<std::uint64_t>(size[q]), std::bit_cast<std::uint64_t>(checksum[q])};
  }
  la::on_root(comm, [&] {
    mine.front().file->commit({sums.begin() + 1, sums.end()});
    std::set<fs::path> written;
    for (int q = 0; q < pieces; ++q) written.insert(piece_file(dir, st.n, q, pieces));
    remove_stale(dir, st.n, written, keep);
  });
}

std::optional<ResumePoint> resume_from_checkpoint(TimeStepper& stepper, const fs::path& dir,
                                                  std::vector<std::string>* skipped, const CaseKeys& keys) {
  const MeshPart& part = stepper.part();
  const la::Comm& comm = stepper.comm();
  const int p = comm.size(), me = comm.rank();
  const std::string key = problem_key(stepper);
  const std::uint64_t fingerprint = fnv1a(key.data(), key.size());
  const State& now = stepper.state();
  const int block = now.contact_block, d = part.dofs.dim();
  // Whether a piece's node and cell fields have this problem's widths.
  auto fields_fit = [&](const CheckpointFile& piece, std::uint64_t n_nodes, std::uint64_t n_cells) {
    bool fit = true;
    for_block_fields([&](const StateField& f, Array a) {
      const auto width = static_cast<std::uint64_t>(f.components(now, d));
      fit = fit && piece.count(a) == width * (f.location == FieldLocation::node ? n_nodes : n_cells);
    });
    return fit;
  };
  const la::BlockSplit node_split(part.n_global_nodes, p), cell_split(part.n_global_cells, p);
  const long long n0 = node_split.begin(me), n1 = node_split.end(me), c0 = cell_split.begin(me),
                  c1 = cell_split.end(me);
  std::vector<long long> steps;
  la::on_root(comm, [&] { steps = checkpoint_steps(dir); });
  steps = la::broadcast(comm, steps);
  // Newest first, each checkpoint checked by every process: rank 0 its first file
  // (checksum included), each process the checksums of every p-th other piece and the
  // fields of the pieces it reads. The first error anywhere passes it over.
  std::optional<CheckpointFile> first;
  std::vector<CheckpointFile> mine;  // the pieces that overlap this process's blocks
  std::vector<double> times;         // its time levels, checked against the problem's
  std::string refusal;               // rank 0: why the newest intact checkpoint's case is not this one
  std::vector<ResumeChange> changed;  // rank 0: the keys that changed and may
  bool found = false;
  for (long long n : steps) {
    first.reset();
    mine.clear();
    refusal.clear();
    const std::string why = first_error(comm, [&] {
      first.emplace(main_file(dir, n), me == 0);
      const CheckpointFile& f = *first;
      require(f.head().index == 0, "checkpoint '{}': piece {} of {}, not a checkpoint's first file", f.name(),
              f.head().index, f.head().count);
      // The case, key by key, before the problem's sizes: a change is named by its key. (Rank 0
      // has checked the file's checksum.)
      if (me == 0) refusal = case_refusal(f, keys, changed);
      if (!refusal.empty()) return;
      require(f.fingerprint == fingerprint, "{}: written for another problem ({})", f.name(),
              problem_key_difference(f.problem_key, key));
      times = first->times();
      const std::string times_differ = time_levels_difference(stepper.problem(), times);
      require(times_differ.empty(), "{}: {}", f.name(), times_differ);
      require(f.contact_block() == block,
              "checkpoint '{}': written by a run with {} contact unknowns per contact node, this problem has {} "
              "(another contact law): it cannot continue it",
              f.name(), f.contact_block(), block);
      require(same_fields(f.surface, now.surface),
              "checkpoint '{}': written by a run whose contact laws keep the per-node state {}, this problem's keep "
              "{} (other contact laws): it cannot continue it",
              f.name(), surface_names(f.surface), surface_names(now.surface));
      require(static_cast<long long>(f.count(kLambda)) == part.n_contact * block,
              "checkpoint '{}': does not fit this problem ({} contact forces for {} contact nodes)", f.name(),
              f.count(kLambda), part.n_contact * block);
      const std::uint64_t pieces = f.head().count;
      const la::BlockSplit nodes_then(part.n_global_nodes, static_cast<int>(pieces)),
          cells_then(part.n_global_cells, static_cast<int>(pieces));
      const bool damage_warm = f.count(kDamageWarm) > 0;  // then in every piece: piece 0 holds nodes
      for (std::uint64_t r = 0; r < pieces; ++r) {
        const auto q = static_cast<int>(r);
        const bool overlaps = std::max(n0, nodes_then.begin(q)) < std::min(n1, nodes_then.end(q)) ||
                              std::max(c0, cells_then.begin(q)) < std::min(c1, cells_then.end(q));
        const bool verify = r > 0 && static_cast<int>(r % static_cast<std::uint64_t>(p)) == me;
        if (!overlaps && !verify) continue;
        CheckpointFile piece = r == 0 ? CheckpointFile(f.path(), false) : open_piece(f, r, verify);
        const PieceHead& h = piece.head();
        const auto nodes = static_cast<std::uint64_t>(nodes_then.size(q));
        require(h.node_begin == static_cast<std::uint64_t>(nodes_then.begin(q)) && h.node_end - h.node_begin == nodes &&
                    h.cell_begin == static_cast<std::uint64_t>(cells_then.begin(q)) &&
                    h.cell_end - h.cell_begin == static_cast<std::uint64_t>(cells_then.size(q)) &&
                    fields_fit(piece, nodes, h.cell_end - h.cell_begin) &&
                    piece.count(kDamageWarm) == (damage_warm ? nodes : 0),
                "checkpoint '{}': does not fit this problem (its blocks are not those of {} nodes and {} cells in {} "
                "pieces)",
                piece.name(), part.n_global_nodes, part.n_global_cells, pieces);
        if (overlaps) mine.push_back(std::move(piece));
      }
    });
    // The newest checkpoint of the directory whose first file is intact is the run's: older
    // ones are of the same case, and a changed case is refused, not passed over.
    la::on_root(comm, [&] { require(refusal.empty(), "{}", refusal); });
    if (why.empty()) {
      found = true;
      break;
    }
    if (skipped && me == 0) skipped->push_back(why);
  }
  if (!found) return std::nullopt;
  // Each process reads its blocks, one array at a time; one exchange hands each value
  // to the processes that own or ghost its node or cell.
  const la::Layout& nodes = *part.node_layout;
  const la::Layout cells = cell_layout(part);
  auto read = [&](Array a, bool of_nodes, int width) {
    Vector block;
    la::collective(comm, [&] {
      block = of_nodes ? read_block(mine, a, true, n0, n1, width) : read_block(mine, a, false, c0, c1, width);
    });
    return block;
  };
  Snapshot s;
  s.state.n = static_cast<int>(first->n);
  s.state.t = first->t;
  s.state.contact_block = block;
  for_block_fields([&](const StateField& f, Array a) {
    const int width = f.components(now, d);
    Vector local;
    if (f.location == FieldLocation::node)
      nodes.from_blocks(read(a, true, width), node_split, local, width);
    else
      cells.from_blocks(read(a, false, width), cell_split, local, width);
    f.assign(s.state, values(local));
  });
  s.u_free = restrict_to_free(part.dofs, s.state.u).head(part.n_owned_dofs);
  if (first->count(kDamageWarm) > 0) {
    Vector w;
    nodes.from_blocks(read(kDamageWarm, true, 1), node_split, w);
    s.damage_warm = w.head(part.n_owned_nodes);
  }
  // The contact nodes' fields (λ) and the contact warm state (one value per contact row)
  // from rank 0, the PVD entries and totals on rank 0.
  ResumePoint at{s.state.n, s.state.t, {}, {}, {}};
  // The time levels: every process read them to check the checkpoint.
  auto from_root = [&](Array a) {
    std::vector<double> v;
    la::on_root(comm, [&] {
      v.resize(first->count(a));
      first->read(a, 0, v.size(), v.data());
    });
    return la::broadcast(comm, std::move(v));
  };
  for (const StateField& f : state_fields())
    if (f.stored() && f.location == FieldLocation::contact_node) f.assign(s.state, from_root(file_array(f.name)));
  s.state.surface = first->surface;  // every process read piece 0's
  const std::vector<double> contact_warm = from_root(kContactWarm), control = from_root(kStepControl);
  la::on_root(comm, [&] {
    at.pvd = first->pvd;
    at.totals = first->totals;
    for (ResumeChange& c : changed) c.step = at.n;
    at.totals.resume_changes.insert(at.totals.resume_changes.end(), changed.begin(), changed.end());
    at.changed = std::move(changed);
  });
  s.contact_warm = Eigen::Map<const Vector>(contact_warm.data(), static_cast<Eigen::Index>(contact_warm.size()));
  stepper.restore(s);
  stepper.set_step_history(std::move(times), StepControlState::from_values(
                                                  Eigen::Map<const Vector>(control.data(), static_cast<Eigen::Index>(control.size()))));
  return at;
}

void write_state_file(const fs::path& path, const Checkpoint& c) {
  const State& s = c.snapshot.state;
  FileContent f;
  f.case_name = c.case_name;
  f.fingerprint = c.fingerprint;
  f.problem_key = c.problem_key;
  f.keys = &c.case_keys;
  f.n = s.n;
  f.t = s.t;
  f.grid = c.grid;
  f.contact_block = s.contact_block;
  f.surface = &s.surface;
  for (const StateField& sf : state_fields())
    if (sf.stored()) f.arrays[file_array(sf.name)] = sf.values(s);
  f.arrays[kUFree] = values(c.snapshot.u_free);
  f.arrays[kContactWarm] = values(c.snapshot.contact_warm);
  f.arrays[kDamageWarm] = values(c.snapshot.damage_warm);
  if (c.grid.steps == 0) f.arrays[kTimes] = c.times;
  f.arrays[kStepControl] = values(c.step_control);
  f.pvd = &c.pvd;
  f.totals = &c.totals;
  write_file(path, f);
}

fs::path write_checkpoint(const fs::path& dir, const Checkpoint& c, int keep) {
  const fs::path path = main_file(dir, c.snapshot.state.n);
  write_state_file(path, c);
  remove_stale(dir, c.snapshot.state.n, {path}, keep);
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
  CheckpointFile f(file, true);
  return read_whole(f);
}

std::optional<Checkpoint> find_checkpoint(const fs::path& dir, std::uint64_t fingerprint,
                                          std::vector<std::string>* skipped) {
  for (long long n : checkpoint_steps(dir)) {
    const fs::path f = main_file(dir, n);
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
