// The linear-algebra layer (la/) on several ranks: reductions, broadcasts and the shared
// error, ghost updates (forward, reverse-add), gather/scatter round trip in the
// original numbering, the MPIAIJ operator's mult, restriction and fixed rows against the
// serial Eigen operator, the box QP with bounds active on different ranks
// against the serial solve, and the solvers written once over la/ (contact: active
// set with W = K⁻¹Nᵀ kept or two solves, penalty–duality; damage: active set and
// penalty–duality) on a problem whose rows and bounds are split over the ranks,
// against the one-process solve (CHOLMOD) of the same global problem; multigrid within fields
// (the couplings between fields dropped for GAMG's transfers).
// Prints PASSED or FAILED (on rank 0).
#include "la/mumps_schur.hpp"
#include "la/petsc.hpp"
#include "la/petsc_segregated.hpp"
#include "la/vector.hpp"
#include "mpi_check.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/damage_solver.hpp"

#include <fmt/format.h>

#include <cmath>

namespace {

using namespace vpc;
using test::check;
using test::failures;

/// The 1D chain of N nodes, cut into contiguous owned ranges; each rank ghosts
/// the node after its range (the element between them is its own).
struct Chain {
  long long N, begin;
  int n_owned;
  std::vector<long long> ghosts;
  Chain(const la::Comm& c, long long n) : N(n) {
    const long long p = c.size(), r = c.rank();
    begin = N * r / p;
    n_owned = static_cast<int>(N * (r + 1) / p - begin);
    if (r + 1 < p) ghosts.push_back(begin + n_owned);
  }
  /// Original numbering: the chain read backwards.
  std::vector<long long> original() const {
    std::vector<long long> o;
    for (int i = 0; i < n_owned; ++i) o.push_back(N - 1 - (begin + i));
    return o;
  }
};

/// H = M + A on the chain (P1 mass and stiffness, h = 1/(N−1)): each rank adds
/// its elements (local nodes: owned then the ghost), as a FEM assembly does.
Eigen::SparseMatrix<double> element_matrix_sum(long long first, long long n_nodes, double h) {
  std::vector<Eigen::Triplet<double>> t;
  for (long long e = first; e + 1 < first + n_nodes; ++e) {
    const int a = static_cast<int>(e - first);
    const double m = h / 6, k = 1 / h;
    t.emplace_back(a, a, 2 * m + k);
    t.emplace_back(a + 1, a + 1, 2 * m + k);
    t.emplace_back(a, a + 1, m - k);
    t.emplace_back(a + 1, a, m - k);
  }
  Eigen::SparseMatrix<double> A(n_nodes, n_nodes);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

/// ‖a − b‖∞ ≤ tol ‖b‖∞ on every rank (b: the one-process solution's entries).
bool close(const la::Comm& comm, const Eigen::VectorXd& a, const Eigen::VectorXd& b, double tol) {
  const double err = comm.max(a.size() ? (a - b).lpNorm<Eigen::Infinity>() : 0.0);
  const double scale = comm.max(b.size() ? b.lpNorm<Eigen::Infinity>() : 0.0);
  return a.size() == b.size() && err <= tol * scale;
}

/// The contact and damage solvers on the chain (H: its matrix, as the stiffness K
/// of one dof per node and as the damage matrix), distributed by contiguous node
/// ranges, against one process.
void check_solvers(const la::Comm& comm, const Chain& c, const Eigen::SparseMatrix<double>& local,
                   const std::vector<PetscInt>& l2g, double h, bool dual_only = false) {
  const auto seg = [&](const Eigen::VectorXd& a) { return Eigen::VectorXd(a.segment(c.begin, c.n_owned)); };
  const Eigen::SparseMatrix<double> K_serial = element_matrix_sum(0, c.N, h);
  auto make_op = [&] { return std::make_unique<la::PetscOperator>(comm, local, l2g, c.n_owned, c.N, 1); };
  const la::LinearSolverFactory factory = la::factor_factory(la::make_petsc_backend(comm, {}));

  // Contact (3.9): u_j ≤ g_j at every third node (rows numbered in node order, each
  // on the rank owning its node), an upward load, a gap growing along the chain:
  // the left part touches.
  std::vector<Eigen::Triplet<double>> t_all, t_own;
  std::vector<int> rows;
  std::vector<double> gap_all, gap_own;
  for (long long j = 1, r = 0; j < c.N; j += 3, ++r) {
    const double g = 20.0 + 20.0 * j * h;  // the free solution is about 30
    t_all.emplace_back(static_cast<int>(r), static_cast<int>(j), 1.0);
    gap_all.push_back(g);
    if (j < c.begin || j >= c.begin + c.n_owned) continue;
    t_own.emplace_back(static_cast<int>(rows.size()), static_cast<int>(j - c.begin), 1.0);
    rows.push_back(static_cast<int>(r));
    gap_own.push_back(g);
  }
  const int m = static_cast<int>(gap_all.size());
  Eigen::SparseMatrix<double> N_all(m, c.N), N_own(static_cast<Eigen::Index>(rows.size()), c.n_owned);
  N_all.setFromTriplets(t_all.begin(), t_all.end());
  N_own.setFromTriplets(t_own.begin(), t_own.end());
  const Eigen::VectorXd g_all = Eigen::Map<Eigen::VectorXd>(gap_all.data(), m);
  const Eigen::VectorXd F = Eigen::VectorXd::Constant(c.N, 30.0 * h);
  ContactSolverOptions two_solves;
  two_solves.max_cached_share = 0;
  struct Variant {
    const char* name;
    ContactSolverOptions opt;
    const char* says;
  };
  // Beyond one block of right-hand sides (64) MUMPS forms S as its Schur complement of [K Nᵀ; N 0].
  const bool schur = m > 64;
  const Variant variants[] = {
      {"active-set", {}, schur ? "two solves per step (S by MUMPS' Schur complement)" : "one solve per step (K⁻¹Nᵀ kept)"},
      {"active-set", two_solves, schur ? "two solves per step (S by MUMPS' Schur complement)" : "two solves per step"},
      {"penalty-duality", {}, nullptr},
      {"primal-active-set", {}, nullptr}};
  for (const Variant& v : variants) {
    if (dual_only && std::string(v.name) != "active-set") continue;
    auto serial = make_contact_solver(v.name, K_serial, N_all, g_all, v.opt);
    Eigen::VectorXd u_s, l_s;
    const ContactReport rs = serial->solve(F, u_s, l_s);
    std::shared_ptr<const la::SpdOperator> K = make_op();
    std::shared_ptr<la::LinearSolver> K_factor = factory("K");
    K_factor->factorize(*K, "chain stiffness");
    ContactConstraints cc;
    cc.m = m;
    cc.rows = rows;
    cc.N = N_own;
    cc.gap = Eigen::Map<Eigen::VectorXd>(gap_own.data(), N_own.rows());
    auto dist = make_contact_solver(v.name, K, K_factor, cc, factory, v.opt);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(c.n_owned), lambda;
    const ContactReport r = dist->solve(seg(F), u, lambda);
    const std::string what = fmt::format("contact {} ({})", v.name, dist->describe());
    check(rs.converged && r.converged && rs.n_active > 0 && rs.n_active < m, fmt::format("{}: converged, a free boundary ({} of {} active)", what, rs.n_active, m),
          comm);
    check(r.n_active == rs.n_active && std::abs(r.total_force - rs.total_force) <= 1e-10 * rs.total_force,
          fmt::format("{}: {} active, force {} (one process: {}, {})", what, r.n_active, r.total_force, rs.n_active,
                      rs.total_force),
          comm);
    check(close(comm, u, seg(u_s), 1e-10) && close(comm, lambda, l_s, 1e-10), what + ": u and lambda", comm);
    check(r.residuals.max() <= 1e-10 && std::abs(r.residuals.max() - rs.residuals.max()) <= 1e-10,
          fmt::format("{}: residuals {} (one process: {})", what, r.residuals.max(), rs.residuals.max()), comm);
    check(!v.says || dist->describe() == v.says, what + ": the path taken", comm);
    check(close(comm, dist->warm_state(), serial->warm_state(), 1e-10), what + ": warm state (m numbers)", comm);
    // A second solve from the warm state gives the same solution again.
    auto again = make_contact_solver(v.name, K, K_factor, cc, factory, v.opt);
    again->set_warm_state(dist->warm_state());
    Eigen::VectorXd u2 = u, l2 = lambda;
    const ContactReport r2 = again->solve(seg(F), u2, l2);
    check(r2.converged && close(comm, u2, seg(u_s), 1e-10) && r2.iterations <= std::max(1, r.iterations),
          what + ": warm restart", comm);
  }

  // Damage (3.8): 0 ≤ β ≤ 1 with both bounds active on different ranks.
  if (dual_only) return;
  Eigen::VectorXd b(c.N);
  for (long long j = 0; j < c.N; ++j) b[j] = 80.0 * std::sin(6.0 * j * h) * h;
  for (const char* name : {"active-set", "penalty-duality"}) {
    auto serial = make_damage_solver(name, K_serial);
    Eigen::VectorXd beta_s = Eigen::VectorXd::Ones(c.N);
    const DamageReport rs = serial->solve(b, beta_s);
    auto dist = make_damage_solver(name, make_op(), factory);
    Eigen::VectorXd beta = Eigen::VectorXd::Ones(c.n_owned);
    const DamageReport r = dist->solve(seg(b), beta);
    const std::string what = fmt::format("damage {}", name);
    check(rs.converged && r.converged && rs.n_lower > 0 && rs.n_upper > 0, what + ": converged, both bounds", comm);
    check(r.n_lower == rs.n_lower && r.n_upper == rs.n_upper,
          fmt::format("{}: bounds {} {} (one process: {} {})", what, r.n_lower, r.n_upper, rs.n_lower, rs.n_upper),
          comm);
    check(close(comm, beta, seg(beta_s), 1e-10) && r.kkt_residual <= 1e-10, what + ": beta", comm);
    check(comm.any(c.n_owned > 0 && (beta.array() == 0).any()) && comm.any((beta.array() == 1).any()),
          what + ": bounds active", comm);
    const Eigen::VectorXd w = dist->warm_state(), w_s = serial->warm_state();
    check(close(comm, w, w_s.size() ? seg(w_s) : w_s, 1e-10), what + ": warm state (owned entries)", comm);
  }
}

/// check_solvers' dual contact solver on a chain of n nodes (each rank its elements and the ghost after its range).
void check_solvers_on_chain(const la::Comm& comm, long long n) {
  const Chain c(comm, n);
  const double h = 1.0 / (c.N - 1);
  const long long n_local = c.n_owned + static_cast<long long>(c.ghosts.size());
  std::vector<PetscInt> l2g;
  for (long long i = 0; i < n_local; ++i) l2g.push_back(static_cast<PetscInt>(c.begin + i));
  check_solvers(comm, c, element_matrix_sum(c.begin, n_local, h), l2g, h, true);
}

/// la::mumps_schur_complement: S = B K⁻¹Bᵀ for rows B of two entries each (of either sign, a row's
/// entries on two ranks' nodes where it straddles a cut: its owner gives only its own), against
/// one process's dense K⁻¹.
void check_schur_complement(const la::Comm& comm) {
  const Chain c(comm, 60);
  const double h = 1.0 / (c.N - 1);
  const long long n_local = c.n_owned + static_cast<long long>(c.ghosts.size());
  std::vector<PetscInt> l2g;
  for (long long i = 0; i < n_local; ++i) l2g.push_back(static_cast<PetscInt>(c.begin + i));
  const la::PetscOperator K(comm, element_matrix_sum(c.begin, n_local, h), l2g, c.n_owned, c.N, 1);
  const Eigen::SparseMatrix<double> K_serial = element_matrix_sum(0, c.N, h);
  // Row r: 1.5 u_{2r} − 0.7 u_{2r+1}, rows numbered backwards (not in node order).
  const int m = static_cast<int>(c.N / 2);
  Eigen::SparseMatrix<double> B_all(m, c.N);
  std::vector<Eigen::Triplet<double>> t_all, t_own;
  std::vector<int> rows;
  for (int r = 0; r < m; ++r) {
    const int row = m - 1 - r;
    t_all.emplace_back(row, 2 * r, 1.5);
    t_all.emplace_back(row, 2 * r + 1, -0.7);
    if (2 * r < c.begin || 2 * r + 1 >= c.begin + c.n_owned) continue;  // both nodes owned here
    t_own.emplace_back(static_cast<int>(rows.size()), static_cast<int>(2 * r - c.begin), 1.5);
    t_own.emplace_back(static_cast<int>(rows.size()), static_cast<int>(2 * r + 1 - c.begin), -0.7);
    rows.push_back(row);
  }
  // Rows straddling a cut are on no rank here: they leave B (and S's row and column) zero.
  std::vector<char> owned(static_cast<std::size_t>(m), 0);
  for (const int r : rows) owned[static_cast<std::size_t>(r)] = 1;
  std::vector<double> flags(owned.begin(), owned.end());
  comm.sum(flags.data(), m);
  std::vector<Eigen::Triplet<double>> t_kept;
  for (const auto& t : t_all)
    if (flags[static_cast<std::size_t>(t.row())] > 0) t_kept.push_back(t);
  B_all.setFromTriplets(t_kept.begin(), t_kept.end());
  Eigen::SparseMatrix<double> B_own(static_cast<Eigen::Index>(rows.size()), c.n_owned);
  B_own.setFromTriplets(t_own.begin(), t_own.end());
  const Eigen::MatrixXd K_inv = Eigen::MatrixXd(K_serial).inverse();
  const Eigen::MatrixXd expected = B_all * K_inv * B_all.transpose();
  const Eigen::MatrixXd S = la::mumps_schur_complement(PETSC_COMM_WORLD, K.mat(), B_own, rows, m, "test matrix");
  const double err = (S - expected).cwiseAbs().maxCoeff(), scale = expected.cwiseAbs().maxCoeff();
  check(err <= 1e-12 * scale && (S - S.transpose()).cwiseAbs().maxCoeff() == 0,
        fmt::format("MUMPS' Schur complement B K^-1 B^T: largest difference {:.2e} of {:.2e}", err, scale), comm);
}

void run() {
  const la::Comm comm = la::make_mpi_comm(PETSC_COMM_WORLD);
  const int p = comm.size(), me = comm.rank();
  // Reductions.
  check(comm.sum(static_cast<double>(me + 1)) == p * (p + 1) / 2.0, "sum", comm);
  check(comm.sum(static_cast<long long>(me)) == p * (p - 1) / 2, "sum (integers)", comm);
  check(comm.max(double(me)) == p - 1 && comm.min(double(me)) == 0, "max/min", comm);
  {  // rank 0's values everywhere, bit for bit; an empty vector too
    std::vector<double> v(100001);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = me == 0 ? std::sin(static_cast<double>(i)) : -1.0;
    const std::vector<double> b = la::broadcast(comm, v);
    bool same = b.size() == v.size();
    for (std::size_t i = 0; same && i < b.size(); ++i) same = b[i] == std::sin(static_cast<double>(i));
    check(same, "broadcast", comm);
    check(la::broadcast(comm, me == 0 ? std::vector<long long>{} : std::vector<long long>{7}).empty(),
          "broadcast of nothing", comm);
  }
  check(comm.all(true) && !comm.all(me != 0) && comm.any(me == p - 1) && !comm.any(false), "all/any", comm);
  try {
    comm.throw_if_any(me == p - 1, fmt::format("bad input on rank {}", me));
    check(false, "throw_if_any threw nowhere", comm);
  } catch (const Error& e) {
    check(e.what() == fmt::format("bad input on rank {}", p - 1), "throw_if_any: the same message", comm);
  }

  // Ghost updates.
  const Chain c(comm, 23);
  auto layout = std::make_shared<const la::Layout>(comm, c.n_owned, c.ghosts, c.original());
  check(layout->n_global() == c.N && layout->begin() == c.begin, "layout ranges", comm);
  // A rank's ghost is the next rank's first node: that rank owns it.
  bool owners = true;
  for (int k = 0; k < layout->n_ghosts(); ++k) owners = owners && layout->ghost_owner(k) == comm.rank() + 1;
  check(owners, "each ghost's owner", comm);
  la::Vector v(layout);
  for (int i = 0; i < c.n_owned; ++i) v.local()[i] = 1.5 * (c.begin + i);
  v.update_ghosts();
  bool ok = true;
  for (int k = 0; k < layout->n_ghosts(); ++k) ok = ok && v.local()[c.n_owned + k] == 1.5 * c.ghosts[k];
  check(ok, "forward ghost update", comm);
  v.local().setOnes();
  v.add_ghosts_to_owners();
  ok = true;  // a rank's first node is the previous rank's ghost
  for (int i = 0; i < c.n_owned; ++i) ok = ok && v.local()[i] == ((i == 0 && me > 0) ? 2.0 : 1.0);
  check(ok, "reverse-add ghost update", comm);

  // Gather / scatter in the original numbering.
  for (int i = 0; i < c.n_owned; ++i) v.local()[i] = static_cast<double>(c.begin + i);
  const Eigen::VectorXd g = layout->gather(v.local());
  ok = true;
  if (me == 0)
    for (long long j = 0; j < c.N; ++j) ok = ok && g[j] == static_cast<double>(c.N - 1 - j);
  check(ok && (me == 0 ? g.size() == c.N : g.size() == 0), "gather in the original numbering", comm);
  Eigen::VectorXd back;
  layout->scatter(g, back);
  ok = back.size() == layout->n_local();
  for (int i = 0; ok && i < layout->n_local(); ++i)
    ok = back[i] == static_cast<double>(i < c.n_owned ? c.begin + i : c.ghosts[i - c.n_owned]);
  check(ok, "scatter round trip (owned and ghosts)", comm);

  // Blocks of the original numbering (checkpoint pieces): PETSc's split over the
  // ranks, 2 values per entry; back into the owned entries and the ghosts.
  const la::BlockSplit split(c.N, p);
  Eigen::VectorXd two(2 * c.n_owned);
  for (int i = 0; i < c.n_owned; ++i) {
    two[2 * i] = static_cast<double>(c.begin + i);
    two[2 * i + 1] = -static_cast<double>(c.begin + i);
  }
  const Eigen::VectorXd block = layout->to_blocks(two, split, 2);
  ok = block.size() == 2 * split.size(me);
  for (long long j = split.begin(me); ok && j < split.end(me); ++j) {  // original j is global N − 1 − j
    const Eigen::Index k = 2 * (j - split.begin(me));
    ok = block[k] == static_cast<double>(c.N - 1 - j) && block[k + 1] == -static_cast<double>(c.N - 1 - j);
  }
  check(ok, "to_blocks: each rank its block of the original numbering", comm);
  layout->from_blocks(block, split, back, 2);
  ok = back.size() == 2 * layout->n_local();
  for (int i = 0; ok && i < layout->n_local(); ++i) {
    const auto global = static_cast<double>(i < c.n_owned ? c.begin + i : c.ghosts[i - c.n_owned]);
    ok = back[2 * i] == global && back[2 * i + 1] == -global;
  }
  check(ok, "from_blocks round trip (owned and ghosts)", comm);
  {  // A chain large enough that to_blocks sends its values in several rounds (2¹⁸ values a rank
     // a round: 2 or 3 here), into PETSc's split and all to rank 0.
    const Chain big(comm, 300007 + 1000 * p);
    const la::Layout large(comm, big.n_owned, {}, big.original());
    Eigen::VectorXd three(3 * big.n_owned);
    for (int i = 0; i < big.n_owned; ++i)
      for (int k = 0; k < 3; ++k) three[3 * i + k] = static_cast<double>(big.begin + i) + 0.25 * k;
    for (const la::BlockSplit& to : {la::BlockSplit(big.N, p), la::BlockSplit::first_only(big.N, p)}) {
      const Eigen::VectorXd b = large.to_blocks(three, to, 3);
      ok = b.size() == 3 * to.size(me);
      for (long long j = to.begin(me); ok && j < to.end(me); ++j)  // original j is global N − 1 − j
        for (int k = 0; k < 3; ++k)
          ok = ok && b[3 * (j - to.begin(me)) + k] == static_cast<double>(big.N - 1 - j) + 0.25 * k;
      check(ok, fmt::format("to_blocks in rounds ({})", to.size(0) == big.N ? "all on rank 0" : "PETSc's split"), comm);
    }
  }

  // Operator: the ranks' elements summed, against the serial matrix.
  const double h = 1.0 / (c.N - 1);
  const long long n_local_nodes = c.n_owned + layout->n_ghosts();
  std::vector<PetscInt> l2g;
  for (long long i = 0; i < n_local_nodes; ++i) l2g.push_back(static_cast<PetscInt>(c.begin + i));
  const la::PetscOperator H(comm, element_matrix_sum(c.begin, n_local_nodes, h), l2g, c.n_owned, c.N, 1);
  const la::SparseOperator Hs(element_matrix_sum(0, c.N, h));
  const Eigen::VectorXd xs = Eigen::VectorXd::LinSpaced(c.N, -1.0, 2.0);
  Eigen::VectorXd ys, y;
  Hs.mult(xs, ys);
  H.mult(xs.segment(c.begin, c.n_owned), y);
  check((y - ys.segment(c.begin, c.n_owned)).lpNorm<Eigen::Infinity>() <= 1e-12, "operator mult", comm);
  check(H.diagonal() == Hs.diagonal().segment(c.begin, c.n_owned), "operator diagonal", comm);
  std::vector<char> fixed_s(c.N);
  for (long long j = 0; j < c.N; ++j) fixed_s[j] = j % 3 == 0;
  const std::vector<char> fixed(fixed_s.begin() + c.begin, fixed_s.begin() + c.begin + c.n_owned);
  const auto HFF = H.restrict_to_free(fixed);
  const auto HFFs = Hs.restrict_to_free(fixed_s);
  Eigen::VectorXd xf_s = Eigen::VectorXd::LinSpaced(HFFs->n_owned(), 0.5, 1.0), yf_s, yf;
  long long before = 0;  // free entries on the lower ranks
  for (long long j = 0; j < c.begin; ++j) before += !fixed_s[j];
  HFFs->mult(xf_s, yf_s);
  HFF->mult(xf_s.segment(before, HFF->n_owned()), yf);
  check((yf - yf_s.segment(before, HFF->n_owned())).lpNorm<Eigen::Infinity>() <= 1e-12, "restriction", comm);
  // Fixed rows (the primal contact solver's active rows): A_jj e_j on those rows and columns.
  const auto Hfix = H.with_fixed(fixed);
  const auto Hfix_s = Hs.with_fixed(fixed_s);
  Hfix_s->mult(xs, ys);
  Hfix->mult(xs.segment(c.begin, c.n_owned), y);
  check((y - ys.segment(c.begin, c.n_owned)).lpNorm<Eigen::Infinity>() <= 1e-12 &&
            Hfix->diagonal() == Hs.diagonal().segment(c.begin, c.n_owned) && Hfix->nonzeros() == H.nonzeros(),
        "fixed rows (same pattern, A's diagonal kept)", comm);
  {  // The same made in place with a block added (the primal friction solver's springs): B on the
     // owned diagonal and the owned (j, j+1) pairs, inside H's pattern; against (Hs + Bs) fixed.
    std::vector<Eigen::Triplet<double>> t, ts;
    for (long long j = 0; j < c.N; ++j) {
      const bool owned = j >= c.begin && j < c.begin + c.n_owned, next_owned = j + 1 < c.begin + c.n_owned;
      ts.emplace_back(j, j, 2.0 + j % 3);
      if (owned) t.emplace_back(j - c.begin, j - c.begin, 2.0 + j % 3);
      if (owned && next_owned) {
        for (const auto& [a, b] : {std::pair{j, j + 1}, std::pair{j + 1, j}}) {
          ts.emplace_back(a, b, -0.5);
          t.emplace_back(a - c.begin, b - c.begin, -0.5);
        }
      }
    }
    Eigen::SparseMatrix<double> B(c.n_owned, c.n_owned), Bs(c.N, c.N);
    B.setFromTriplets(t.begin(), t.end());
    Bs.setFromTriplets(ts.begin(), ts.end());
    const auto want = Hs.plus(Bs)->with_fixed(fixed_s);
    const std::unique_ptr<la::SpdOperator> A = H.with_fixed(std::vector<char>(fixed.size(), 0));
    const bool in_place = A->assign_with_fixed(H, fixed, &B);
    want->mult(xs, ys);
    A->mult(xs.segment(c.begin, c.n_owned), y);
    check(in_place && (y - ys.segment(c.begin, c.n_owned)).lpNorm<Eigen::Infinity>() <= 1e-12 &&
              A->diagonal() == want->diagonal().segment(c.begin, c.n_owned) && A->nonzeros() == H.nonzeros(),
          "fixed rows and a block, in place", comm);
    // An operator of another pattern (an entry (j, j+2) added) is not assigned in place.
    std::vector<Eigen::Triplet<double>> far;
    if (c.n_owned >= 3) far.emplace_back(0, 2, 1.0), far.emplace_back(2, 0, 1.0);
    Eigen::SparseMatrix<double> F(c.n_owned, c.n_owned);
    F.setFromTriplets(far.begin(), far.end());
    const std::unique_ptr<la::SpdOperator> other = H.plus(F);
    check(!other->assign_with_fixed(H, fixed, &B) || !comm.any(c.n_owned >= 3), "another pattern: not in place", comm);
  }
  // A few rows' product (the primal friction solver's coupling): every rank's rows j ≡ 1 (mod 4),
  // then rank 0's first row only (the other ranks ask for none and still take part).
  Hs.mult(xs, ys);
  for (const bool everywhere : {true, false}) {
    std::vector<int> rows;
    for (int i = 0; i < c.n_owned; ++i)
      if (everywhere ? (c.begin + i) % 4 == 1 : me == 0 && i == 0) rows.push_back(i);
    Eigen::VectorXd yr;
    H.rows(rows)(xs.segment(c.begin, c.n_owned), yr);
    ok = yr.size() == static_cast<Eigen::Index>(rows.size());
    for (size_t k = 0; ok && k < rows.size(); ++k) ok = std::abs(yr[k] - ys[c.begin + rows[k]]) <= 1e-12;
    check(ok, everywhere ? "row product (rows on every rank)" : "row product (rows on rank 0 only)", comm);
  }

  // GMRES on H + C, preconditioned by MUMPS' factor and by CG + GAMG's multigrid of H
  // (solve_perturbed): C scales H's rows j ≡ 2 (mod 5) by 0.3 (nonsymmetric, as Coulomb's coupling
  // adds a multiple of K's normal row to a tangent row), so (H + C) x = b is H x = b with those
  // b_j divided by 1.3: the serial solve's answer.
  for (const char* kind : {"mumps", "cg-gamg"}) {
    PetscSolverOptions o;
    o.kind = kind;
    const auto f = la::factor_factory(la::make_petsc_backend(comm, o))("H");
    f->factorize(H, "chain matrix");
    const la::Perturbation C = [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) {
      H.mult(x, out);
      for (int i = 0; i < c.n_owned; ++i) out[i] *= (c.begin + i) % 5 == 2 ? 0.3 : 0.0;
    };
    Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(c.N, -1.0, 2.0), scaled = rhs;
    for (long long j = 0; j < c.N; ++j) scaled[j] /= j % 5 == 2 ? 1.3 : 1.0;
    Eigen::VectorXd expected;
    auto fs = la::make_cholmod_factor();
    fs->factorize(Hs, "chain matrix");
    fs->solve(scaled, expected);
    Eigen::VectorXd x;
    f->solve_perturbed(H, C, rhs.segment(c.begin, c.n_owned), x, 1e-12, "chain matrix");
    check(close(comm, x, expected.segment(c.begin, c.n_owned), 1e-9), fmt::format("GMRES on H + C ({})", kind), comm);
  }

  // Multigrid within fields (la/petsc_segregated.hpp): the chain cut in two fields at its middle
  // node. within_fields drops exactly the couplings across the cut (against the serial matrix
  // without them), and CG + GAMG given those fields solves H x = b itself.
  {
    const long long cut = c.N / 2;
    std::vector<int> field(static_cast<std::size_t>(c.n_owned));
    for (int i = 0; i < c.n_owned; ++i) field[static_cast<std::size_t>(i)] = c.begin + i >= cut ? 1 : 0;
    check(la::several_fields(PETSC_COMM_WORLD, field), "several fields", comm);
    check(!la::several_fields(PETSC_COMM_WORLD, std::vector<int>(static_cast<std::size_t>(c.n_owned), 3)),
          "one field", comm);
    const la::PetscOperator W(comm, la::within_fields(H.mat(), field));
    Eigen::SparseMatrix<double> Ws = element_matrix_sum(0, c.N, h);
    Ws.prune([&](Eigen::Index i, Eigen::Index j, double) { return (i >= cut) == (j >= cut); });
    Eigen::VectorXd yw, yws = Ws * xs;
    W.mult(xs.segment(c.begin, c.n_owned), yw);
    const long long nonzeros = W.nonzeros(), all = H.nonzeros();  // collective: not inside a condition
    check((yw - yws.segment(c.begin, c.n_owned)).lpNorm<Eigen::Infinity>() <= 1e-12 && nonzeros == Ws.nonZeros() &&
              nonzeros == all - 2,
          "within_fields: the couplings across fields dropped, no other", comm);
    PetscSolverOptions o;
    o.kind = "cg-gamg";
    const auto f = la::factor_factory(la::make_petsc_backend(comm, o))("H");
    f->set_fields(field);
    f->factorize(H, "chain matrix");
    Eigen::VectorXd x, expected;
    auto fs = la::make_cholmod_factor();
    fs->factorize(Hs, "chain matrix");
    fs->solve(xs, expected);
    f->solve(xs.segment(c.begin, c.n_owned), x);
    check(close(comm, x, expected.segment(c.begin, c.n_owned), 1e-9), "CG + GAMG within fields", comm);
  }

  // The box QP with bounds active on different ranks (MUMPS: no halves, reduced factors).
  Eigen::VectorXd b(c.N);
  for (long long j = 0; j < c.N; ++j) b[j] = 40.0 * std::sin(6.0 * j * h) * h;
  const Eigen::VectorXd lo = Eigen::VectorXd::Zero(c.N), hi = Eigen::VectorXd::Constant(c.N, 0.6);
  SparseBoxQpOperator serial(Eigen::SparseMatrix<double>(element_matrix_sum(0, c.N, h)));
  Eigen::VectorXd x_s = Eigen::VectorXd::Zero(c.N);
  const BoxQpResult rs = solve_box_qp(serial, b, lo, hi, x_s);
  SparseBoxQpOperator dist(std::make_unique<la::PetscOperator>(comm, element_matrix_sum(c.begin, n_local_nodes, h),
                                                               l2g, c.n_owned, c.N, 1),
                           la::factor_factory(la::make_petsc_backend(comm, {})));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(c.n_owned);
  const auto seg = [&](const Eigen::VectorXd& a) { return Eigen::VectorXd(a.segment(c.begin, c.n_owned)); };
  const BoxQpResult r = solve_box_qp(dist, seg(b), seg(lo), seg(hi), x);
  check(rs.converged && r.converged && rs.n_lower > 0 && rs.n_upper > 0, "box QP converged, both bounds active",
        comm);
  check(r.n_lower == rs.n_lower && r.n_upper == rs.n_upper && r.iterations == rs.iterations,
        fmt::format("box QP: same active sets and iterations ({} {} {} vs {} {} {})", r.n_lower, r.n_upper,
                    r.iterations, rs.n_lower, rs.n_upper, rs.iterations),
        comm);
  check((x - seg(x_s)).lpNorm<Eigen::Infinity>() <= 1e-12 && r.kkt_residual <= 1e-12, "box QP solution", comm);
  check(comm.any(c.n_owned > 0 && (x.array() == 0).any()) && comm.any((x.array() == 0.6).any()),
        "box QP: bounds active", comm);

  check_solvers(comm, c, element_matrix_sum(c.begin, n_local_nodes, h), l2g, h);
  check_solvers_on_chain(comm, 400);  // 133 contact rows: S by MUMPS' Schur complement
  check_schur_complement(comm);
}

}  // namespace

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 3;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  try {
    run();
  } catch (const std::exception& e) {
    fmt::print("FAILED: rank {}: {}\n", rank, e.what());
    MPI_Abort(PETSC_COMM_WORLD, 1);
  }
  if (rank == 0) fmt::print("{}\n", failures == 0 ? "la on several ranks: PASSED" : "FAILED");
  PetscFinalize();
  return failures == 0 ? 0 : 1;
}
