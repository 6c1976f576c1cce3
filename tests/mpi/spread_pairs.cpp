// Contact pairs spread over the ranks (--spread-pairs: distribute_mesh's spread_pairs): each
// pair row goes with its slave node's owner, which holds the row's master nodes it
// does not own as cell-less ghosts, and sends the row's entries at them to their owners as remote
// pieces (ContactSet::constraints, remote_pieces).
//   mpirun -np P vpcontact_mpi_spread_pairs CASE [--set KEY=VALUE ...]
// Checks, against the same case partitioned with each pair's nodes owned together:
// - some rank owns a pair row with a ghost master, and some rank holds remote pieces (so the
//   comparison below is not of rows that were never spread);
// - every row of N (and of T with friction) is the same row: its owner's entries plus the other
//   ranks' pieces, keyed by (row, node as read, component), bit for bit;
// - the only nodes of a part with no cell of its own are ghost masters, or nodes of its pieces of
//   the large-sliding pairs' surfaces (MeshPart::sliding);
// - with a large-sliding pair, some rank owns rows of it whose master side it holds in part as
//   ghosts (its piece of the surfaces), and every rank that owns one of its rows holds a piece.
// Prints each rank's rows, rows with ghost masters and pieces, then PASSED or FAILED (rank 0).
#include "cases/builtin_cases.hpp"
#include "la/petsc.hpp"
#include "mpi_check.hpp"
#include "parallel/distributed_mesh.hpp"
#include "parallel/petsc_engine.hpp"
#include "part/contact_set.hpp"
#include "petsc_main.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

namespace {

using namespace vpc;
using test::check;

/// (row, tangent slot (0: N), node as read, component, value): an entry of a row of N or T.
using Entry = std::tuple<int, int, int, int, double>;

/// The (node as read, component) of each owned free dof of the part.
std::vector<std::pair<int, int>> owned_dof_nodes(const MeshPart& part) {
  std::vector<std::pair<int, int>> at(static_cast<std::size_t>(part.n_owned_dofs));
  const int d = part.mesh().dim();
  for (int i = 0; i < part.n_owned_nodes; ++i)
    for (int c = 0; c < d; ++c)
      if (const int k = part.dofs.free_index(part.dofs.full_index(i, c)); k >= 0)
        at[static_cast<std::size_t>(k)] = {part.original_node[static_cast<std::size_t>(i)], c};
  return at;
}

/// A's entries (rows `rows`, `per_row` rows of A each; slot 0 for N, tangent + 1 for T).
void add_entries(const SparseMatrix& A, const std::vector<int>& rows, int per_row, bool tangents,
                 const std::vector<std::pair<int, int>>& at, std::vector<Entry>& out) {
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it) {
      const auto r = static_cast<int>(it.row());
      const auto [node, c] = at[static_cast<std::size_t>(k)];
      out.emplace_back(rows[static_cast<std::size_t>(r / per_row)], tangents ? 1 + r % per_row : 0, node, c, it.value());
    }
}

/// Every rank's entries of the constraints' rows and pieces, on rank 0, sorted (empty elsewhere).
std::vector<Entry> whole_rows(const la::Comm& comm, const MeshPart& part, const ContactConstraints& c) {
  const auto at = owned_dof_nodes(part);
  std::vector<Entry> mine;
  const int t = c.block - 1;
  add_entries(c.N, c.rows, 1, false, at, mine);
  add_entries(c.remote.N, c.remote.rows, 1, false, at, mine);
  if (t > 0) {
    add_entries(c.T, c.rows, t, true, at, mine);
    add_entries(c.remote.T, c.remote.rows, t, true, at, mine);
  }
  std::vector<std::vector<long long>> ints(static_cast<std::size_t>(comm.size()));
  std::vector<std::vector<double>> values(static_cast<std::size_t>(comm.size()));
  for (const auto& [row, slot, node, comp, v] : mine) {
    ints[0].insert(ints[0].end(), {row, slot, node, comp});
    values[0].push_back(v);
  }
  const auto got_ints = comm.exchange(ints);
  const auto got = comm.exchange(values);
  std::vector<Entry> all;
  for (std::size_t r = 0; r < got.size(); ++r)
    for (std::size_t e = 0; e < got[r].size(); ++e) {
      const long long* x = got_ints[r].data() + 4 * e;
      all.emplace_back(static_cast<int>(x[0]), static_cast<int>(x[1]), static_cast<int>(x[2]), static_cast<int>(x[3]),
                       got[r][e]);
    }
  std::ranges::sort(all);
  return all;
}

/// The part's pair rows whose masters include a ghost; its nodes with no cell of the part, and how
/// many of those are neither such a ghost master nor on a sliding piece (the band adds none else);
/// its rows of large-sliding pairs, and those of them without the part's piece of their pair.
struct GhostMasters {
  int rows = 0, cell_less = 0, cell_less_other = 0, sliding_rows = 0, sliding_rows_without_piece = 0;
};

GhostMasters ghost_masters(const Problem& p, const MeshPart& part) {
  std::vector<char> in_cell(static_cast<std::size_t>(part.n_local_nodes()), 0), master(in_cell.size(), 0);
  const Mesh& mesh = part.mesh();
  for (int c = 0; c < mesh.n_cells(); ++c)
    for (int a = 0; a < mesh.nodes_per_cell(); ++a) in_cell[static_cast<std::size_t>(mesh.cell(c)[a])] = 1;
  GhostMasters g;
  for (const PartContactNode& node : part.contact) {
    bool ghost = false;
    for (const auto& [k, w] : node.masters)
      if (k >= part.n_owned_nodes) {
        ghost = true;
        master[static_cast<std::size_t>(k)] = 1;
      }
    g.rows += ghost ? 1 : 0;
  }
  for (const SlidingPairPiece& s : part.sliding)
    for (const SlidingSurface* side : {&s.slave, &s.master})
      for (const std::vector<int>* nodes : {&side->nodes, &side->cell_nodes})
        for (const int l : *nodes) master[static_cast<std::size_t>(l)] = 1;
  for (const PartContactNode& node : part.contact)
    if (const int q = node.pair; node.owned && q >= 0 && p.contact.pairs[static_cast<std::size_t>(q)].large_sliding) {
      ++g.sliding_rows;
      g.sliding_rows_without_piece += std::ranges::none_of(part.sliding, [&](const SlidingPairPiece& s) { return s.pair == q; });
    }
  for (std::size_t i = 0; i < in_cell.size(); ++i)
    if (!in_cell[i]) {
      ++g.cell_less;
      g.cell_less_other += master[i] ? 0 : 1;
    }
  return g;
}

ContactConstraints constraints_of(const Problem& p, const MeshPart& part) {
  const ContactSet set(p, part, part.contact);
  return set.constraints(p, part, Vector::Zero(static_cast<Eigen::Index>(set.owned_row_numbers().size())));
}

int run(int argc, char** argv) {
  const la::Comm comm = la::make_mpi_comm(PETSC_COMM_WORLD);
  require(argc >= 2, "usage: vpcontact_mpi_spread_pairs CASE [--set KEY=VALUE ...]");
  CaseOverrides overrides;
  for (int i = 2; i + 1 < argc; i += 2)
    if (std::string(argv[i]) == "--set") overrides.sets.emplace_back(argv[i + 1]);
  const std::string file = argv[1];
  Case c = load_case_everywhere([&](const MeshRequest& r) { return load_case(file, overrides, r); }, comm);
  const Problem& p = *c.problem;
  const MeshPart spread = distribute_mesh(PETSC_COMM_WORLD, p, {}, c.contact_rows, true);
  const MeshPart together = distribute_mesh(PETSC_COMM_WORLD, p, {}, c.contact_rows, false);
  const ContactConstraints cs = constraints_of(p, spread), ct = constraints_of(p, together);

  const GhostMasters g = ghost_masters(p, spread);
  fmt::print("rank {}: {} nodes owned, {} ghosts ({} with no cell here); {} rows owned, {} with ghost masters; {} remote "
             "pieces\n",
             comm.rank(), spread.n_owned_nodes, spread.n_local_nodes() - spread.n_owned_nodes, g.cell_less,
             cs.rows.size(), g.rows, cs.remote.rows.size());
  std::fflush(stdout);
  check(spread.pairs_spread && !together.pairs_spread, "the parts say whether their pairs are spread", comm);
  check(comm.any(g.rows > 0), "some rank owns a pair row with a ghost master", comm);
  check(comm.any(!cs.remote.rows.empty()) && cs.remote.spread, "some rank holds remote pieces, marked spread", comm);
  check(g.cell_less_other == 0 && comm.any(g.cell_less > 0),
        "the nodes with no cell of their part are ghost masters or on its sliding pieces (and some rank has them)", comm);
  if (!p.contact.sliding_pairs(true).empty()) {
    const bool ghost_band = std::ranges::any_of(spread.sliding, [&](const SlidingPairPiece& s) {
      return std::ranges::any_of(s.master.nodes, [&](int l) { return l >= spread.n_owned_nodes; });
    });
    check(comm.any(g.sliding_rows > 0 && ghost_band),
          "some rank owns rows of a large-sliding pair and holds its master side in part as ghosts", comm);
    check(comm.sum(static_cast<long long>(g.sliding_rows_without_piece)) == 0,
          "every rank that owns a large-sliding pair's row holds a piece of its surfaces", comm);
  }
  const GhostMasters h = ghost_masters(p, together);
  check(h.rows == 0 && h.cell_less == 0 && ct.remote.rows.empty() && !ct.remote.spread,
        "owned together: no ghost master, no cell-less node, no piece", comm);
  check(cs.m == ct.m && comm.sum(static_cast<long long>(cs.rows.size())) == cs.m, "every row owned once", comm);
  const std::vector<Entry> a = whole_rows(comm, spread, cs), b = whole_rows(comm, together, ct);
  check(comm.all(a == b), fmt::format("the rows with their pieces are the rows owned together ({} entries, {} tangential)",
                                      b.size(), std::ranges::count_if(b, [](const Entry& e) { return std::get<1>(e) > 0; })),
        comm);
  if (comm.rank() == 0) fmt::print("{}\n", test::failures == 0 ? "PASSED" : "FAILED");
  return test::failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return vpc::test::petsc_main(argc, argv, "vpcontact_mpi_spread_pairs", run); }
