// The linear-algebra layer (la/) on several ranks: reductions and the shared
// error, ghost updates (forward, reverse-add), gather/scatter round trip in the
// original numbering, the MPIAIJ operator's mult and restriction against the
// serial Eigen operator, and the box QP with bounds active on different ranks
// against the serial solve. Prints PASSED or FAILED (on rank 0).
#include "la/petsc.hpp"
#include "la/vector.hpp"
#include "solvers/box_qp.hpp"

#include <fmt/format.h>

#include <cmath>

namespace {

using namespace vpc;
int failures = 0;

void check(bool ok, const std::string& what, const la::Comm& comm) {
  if (!comm.all(ok)) {
    ++failures;
    if (comm.rank() == 0) fmt::print("FAILED: {}\n", what);
  }
}

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

void run() {
  const la::Comm comm = la::make_mpi_comm(PETSC_COMM_WORLD);
  const int p = comm.size(), me = comm.rank();
  // Reductions.
  check(comm.sum(static_cast<double>(me + 1)) == p * (p + 1) / 2.0, "sum", comm);
  check(comm.sum(static_cast<long long>(me)) == p * (p - 1) / 2, "sum (integers)", comm);
  check(comm.max(double(me)) == p - 1 && comm.min(double(me)) == 0, "max/min", comm);
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

  // The box QP with bounds active on different ranks (MUMPS: no halves, reduced factors).
  Eigen::VectorXd b(c.N);
  for (long long j = 0; j < c.N; ++j) b[j] = 40.0 * std::sin(6.0 * j * h) * h;
  const Eigen::VectorXd lo = Eigen::VectorXd::Zero(c.N), hi = Eigen::VectorXd::Constant(c.N, 0.6);
  SparseBoxQpOperator serial(Eigen::SparseMatrix<double>(element_matrix_sum(0, c.N, h)));
  Eigen::VectorXd x_s = Eigen::VectorXd::Zero(c.N);
  const BoxQpResult rs = solve_box_qp(serial, b, lo, hi, x_s);
  SparseBoxQpOperator dist(std::make_unique<la::PetscOperator>(comm, element_matrix_sum(c.begin, n_local_nodes, h),
                                                               l2g, c.n_owned, c.N, 1),
                           la::petsc_factor_factory(comm, {}));
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
