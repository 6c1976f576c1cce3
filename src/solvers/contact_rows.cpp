// A rank's constraint rows and its pieces of other ranks' rows (ContactConstraints::remote): the
// dual's B = [N; T] over both, and the products N u, T u and Nᵀλ that read them, with the pieces'
// sums over the ranks taken only where some rank holds pieces (RemoteRows::spread).
#include "solvers/contact_solver.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <iterator>

namespace vpc {

namespace {

/// B's entries of rows (N, and T's tangents) from B's row `first` on, node by node: b rows a node.
void add_block_entries(const SparseMatrix& N, const SparseMatrix& T, int first, int b,
                       std::vector<Eigen::Triplet<double>>& e) {
  const int t = b - 1;
  for (int k = 0; k < N.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(N, k); it; ++it)
      e.emplace_back(first + static_cast<int>(it.row()) * b, static_cast<int>(it.col()), it.value());
  for (int k = 0; k < T.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(T, k); it; ++it) {
      const auto r = static_cast<int>(it.row());
      e.emplace_back(first + r / t * b + 1 + r % t, static_cast<int>(it.col()), it.value());
    }
}

/// The pieces' rows: increasing, within 0..m−1, none of this rank's own, N (and T) over its columns.
void check_pieces(const ContactConstraints& c) {
  const RemoteRows& r = c.remote;
  const auto n = static_cast<Eigen::Index>(r.rows.size()), t = static_cast<Eigen::Index>(c.block - 1);
  std::vector<int> both;
  std::ranges::set_intersection(c.rows, r.rows, std::back_inserter(both));
  require(std::ranges::is_sorted(r.rows) && std::ranges::adjacent_find(r.rows) == r.rows.end() && both.empty() &&
              (n == 0 || (r.rows.front() >= 0 && r.rows.back() < c.m)),
          "internal: remote pieces of contact rows must be increasing rows of 0..{} other than this rank's", c.m - 1);
  require(n == 0 || (r.N.rows() == n && r.N.cols() == c.N.cols() &&
                     (t == 0 ? r.T.size() == 0 : r.T.rows() == n * t && r.T.cols() == c.N.cols())),
          "internal: remote pieces N {} x {}, T {} x {} for {} rows of {} tangents over {} dofs", r.N.rows(), r.N.cols(),
          r.T.rows(), r.T.cols(), n, t, c.N.cols());
}

}  // namespace

SparseMatrix block_rows(const ContactConstraints& c, std::vector<int>& places) {
  const int b = c.block, t = b - 1;
  const auto n_rows = static_cast<Eigen::Index>(c.rows.size());
  require(!c.frictional() ||
              (c.T.rows() == n_rows * t && c.T.cols() == c.N.cols() && c.mu.size() == n_rows && c.tresca.size() == n_rows &&
               c.shift.size() == n_rows * t && c.tangent_dof.size() == static_cast<std::size_t>(n_rows * t)),
          "internal: friction's tangents ({} x {}), {} mu, {} bounds, {} shifts, {} tangent dofs for {} contact rows "
          "of {} tangents (set_tangents)",
          c.T.rows(), c.T.cols(), c.mu.size(), c.tresca.size(), c.shift.size(), c.tangent_dof.size(), n_rows, t);
  check_pieces(c);
  std::vector<Eigen::Triplet<double>> e;
  add_block_entries(c.N, c.T, 0, b, e);
  add_block_entries(c.remote.N, c.remote.T, static_cast<int>(n_rows) * b, b, e);
  SparseMatrix B((n_rows + static_cast<Eigen::Index>(c.remote.rows.size())) * b, c.N.cols());
  B.setFromTriplets(e.begin(), e.end());
  places.clear();
  for (const std::vector<int>* rows : {&c.rows, &c.remote.rows})
    for (const int row : *rows)
      for (int j = 0; j < b; ++j) places.push_back(row * b + j);
  return B;
}

Vector block_offsets(const ContactConstraints& c) {
  const int b = c.block, t = b - 1;
  Vector o = Vector::Zero((c.gap.size() + static_cast<Eigen::Index>(c.remote.rows.size())) * b);
  for (Eigen::Index k = 0; k < c.gap.size(); ++k) {
    o[k * b] = c.gap[k];
    for (int j = 0; j < t; ++j) o[k * b + 1 + j] = c.shift[k * t + j];
  }
  return o;
}

namespace {

/// This rank's rows' values `own` (rows × width) plus the pieces' values of each row (`pieces`: remote
/// rows × width), summed over the ranks at the rows' places (m × width); `own` alone where nothing is
/// spread. A piece's row is never its own rank's, so each place gets one value a rank.
Vector with_pieces(const la::Comm& comm, const ContactConstraints& c, Vector own, const Vector& pieces, int width) {
  require(c.remote.spread || c.remote.rows.empty(), "internal: remote pieces of contact rows not marked spread (RemoteRows::spread)");
  if (!c.remote.spread) return own;
  Vector all = Vector::Zero(static_cast<Eigen::Index>(c.m) * width);
  for (std::size_t k = 0; k < c.remote.rows.size(); ++k)
    all.segment(c.remote.rows[k] * width, width) = pieces.segment(static_cast<Eigen::Index>(k) * width, width);
  comm.sum(all.data(), all.size());
  for (std::size_t k = 0; k < c.rows.size(); ++k)
    own.segment(static_cast<Eigen::Index>(k) * width, width) += all.segment(c.rows[k] * width, width);
  return own;
}

/// A · u over A's columns (a 0 × 0 matrix: a set without tangents or without pieces covers no dofs).
Vector times(const SparseMatrix& A, const Vector& u) { return A * u.head(A.cols()); }

}  // namespace

// (g − N u in one expression, as Eigen evaluates it: the gap less each entry's term in turn.)
Vector gap_left(const la::Comm& comm, const ContactConstraints& c, const Vector& u) {
  return with_pieces(comm, c, c.gap - c.N * u, -times(c.remote.N, u), 1);
}

// (T covers N's columns; a set without tangents may leave it unset, 0 × 0: the products below then
// cover no dofs, as 0 × n would.)
Vector slip_increment(const ContactConstraints& c, const Vector& u) {
  require(!c.remote.spread && c.remote.rows.empty(), "internal: slip increments of spread rows need their pieces");
  return times(c.T, u) - c.shift;
}

Vector slip_increment(const la::Comm& comm, const ContactConstraints& c, const Vector& u) {
  if (!c.remote.spread) return slip_increment(c, u);
  return with_pieces(comm, c, times(c.T, u), times(c.remote.T, u), c.block - 1) - c.shift;
}

void add_piece_loads(const ContactConstraints& c, const Vector& lambda, Vector& y) {
  const RemoteRows& r = c.remote;
  if (r.rows.empty()) return;
  const int b = c.block, t = b - 1;
  const auto n = static_cast<Eigen::Index>(r.rows.size());
  Vector normal(n), tangential(n * t);
  for (Eigen::Index k = 0; k < n; ++k) {
    const int place = r.rows[static_cast<std::size_t>(k)] * b;
    normal[k] = lambda[place];
    for (int j = 0; j < t; ++j) tangential[k * t + j] = lambda[place + 1 + j];
  }
  y.head(r.N.cols()) += r.N.transpose() * normal;
  y.head(r.T.cols()) += r.T.transpose() * tangential;
}

}  // namespace vpc
