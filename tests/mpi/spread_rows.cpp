// Contact rows spread over the ranks (ContactConstraints::remote): a row lives on the rank that owns
// its slave node, over that rank's owned dofs, and its entries at master dofs other ranks own are
// those ranks' remote pieces of it. The dual (active-set: W kept, two solves, MUMPS' Schur
// complement; frictionless and Coulomb's, block 2) solved with rows so split, against the one-process
// solve (CHOLMOD) of the same global problem with whole rows: λ, u, the reported residuals and
// friction's counts agree to 1e-12. The primal and penalty–duality refuse such rows; auto takes the dual.
// Prints PASSED or FAILED (on rank 0).
#include "la/petsc.hpp"
#include "mpi_check.hpp"
#include "petsc_main.hpp"
#include "solvers/contact_capabilities.hpp"
#include "solvers/contact_solver.hpp"

#include <fmt/format.h>

#include <cmath>

namespace {

using namespace vpc;
using test::check;
using test::failures;

/// ‖a − b‖∞ ≤ tol ‖b‖∞ over the ranks (b: the one-process solution's entries).
bool close(const la::Comm& comm, const Vector& a, const Vector& b, double tol) {
  const double err = comm.max(a.size() == b.size() && a.size() ? (a - b).lpNorm<Eigen::Infinity>() : 0.0);
  const double scale = comm.max(b.size() ? b.lpNorm<Eigen::Infinity>() : 0.0);
  return comm.all(a.size() == b.size()) && err <= tol * scale;
}

/// A chain of 3R nodes, two dofs a node (x: tangential, y: normal; dof 2i + k), each rank a contiguous
/// range of nodes. Row r's slave is node 3r + 1; its masters are nodes 3k and 3k + 2 (weights 0.6,
/// 0.4) with k = r + R/2 (mod R), "far": on another rank mostly, or k = min(r + 1, R − 1), "near": on
/// the slave's rank or the next, so that rank 0 holds no pieces. Normal row: u_y at the slave less the
/// masters' mean; tangent row: the same of u_x.
struct SplitChain {
  int R, N, p, me;
  bool far;
  SplitChain(const la::Comm& comm, int rows, bool far_masters)
      : R(rows), N(3 * rows), p(comm.size()), me(comm.rank()), far(far_masters) {}
  int begin(int rank) const { return static_cast<int>(static_cast<long long>(N) * rank / p); }
  int n_owned() const { return begin(me + 1) - begin(me); }
  int owner(int node) const {
    int r = 0;
    while (begin(r + 1) <= node) ++r;
    return r;
  }
  /// Row r's entries (node, weight): the slave first.
  std::vector<std::pair<int, double>> row(int r) const {
    const int k = far ? (r + R / 2) % R : std::min(r + 1, R - 1);
    return {{3 * r + 1, 1.0}, {3 * k, -0.6}, {3 * k + 2, -0.4}};
  }
  /// K: per element (i, i+1) a spring [1 −1; −1 1] plus a mass [1 0.5; 0.5 1], its dofs coupled x–y
  /// by [1 0.3; 0.3 2] (SPD and well conditioned: eigenvalues within [1, 11]), over the nodes
  /// first .. first + n − 1.
  SparseMatrix elements(int first, int n) const {
    const double C[2][2] = {{1, 0.3}, {0.3, 2}};
    const double E[2][2] = {{2, -0.5}, {-0.5, 2}};
    std::vector<Eigen::Triplet<double>> t;
    for (int e = first; e + 1 < first + n; ++e)
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j)
              t.emplace_back(2 * (e - first + a) + i, 2 * (e - first + b) + j, E[a][b] * C[i][j]);
    SparseMatrix K(2 * n, 2 * n);
    K.setFromTriplets(t.begin(), t.end());
    return K;
  }
  /// F: up at the slaves, down elsewhere, and sideways along the chain.
  Vector load() const {
    Vector F(2 * N);
    for (int i = 0; i < N; ++i) {
      F[2 * i] = 0.8 * std::sin(0.37 * i);
      F[2 * i + 1] = i % 3 == 1 ? 2.0 : -1.0;
    }
    return F;
  }
  double gap(int r) const { return 0.05 + 0.5 * r / R; }
  double shift(int r) const { return 0.05 * std::cos(0.9 * r); }
};

/// The constraints of the chain's rows: `whole` all rows with all their entries (one process), else
/// this rank's rows over its owned dofs and its pieces of other ranks' rows. `block` 2: Coulomb's μ.
ContactConstraints constraints(const SplitChain& s, bool whole, int block) {
  ContactConstraints c;
  c.m = s.R;
  c.block = block;
  const int first = whole ? 0 : s.begin(s.me), n = whole ? s.N : s.n_owned();
  std::vector<Eigen::Triplet<double>> n_own, t_own, n_rem, t_rem;
  std::vector<double> gap, shift;
  for (int r = 0; r < s.R; ++r) {
    const auto entries = s.row(r);
    const bool own = whole || s.owner(entries.front().first) == s.me;
    bool piece = false;
    for (const auto& [node, w] : entries) piece = piece || (!own && s.owner(node) == s.me);
    if (!own && !piece) continue;
    auto& nt = own ? n_own : n_rem;
    auto& tt = own ? t_own : t_rem;
    const int k = static_cast<int>(own ? c.rows.size() : c.remote.rows.size());
    (own ? c.rows : c.remote.rows).push_back(r);
    for (const auto& [node, w] : entries) {
      if (node < first || node >= first + n) continue;
      nt.emplace_back(k, 2 * (node - first) + 1, w);
      tt.emplace_back(k, 2 * (node - first), w);
    }
    if (!own) continue;
    gap.push_back(s.gap(r));
    shift.push_back(s.shift(r));
    c.tangent_dof.push_back(2 * (entries.front().first - first));
  }
  auto matrix = [&](const std::vector<Eigen::Triplet<double>>& t, std::size_t rows) {
    SparseMatrix A(static_cast<Eigen::Index>(rows), 2 * n);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  };
  c.N = matrix(n_own, c.rows.size());
  c.remote.N = matrix(n_rem, c.remote.rows.size());
  c.remote.spread = !whole;  // on every rank, as where the constraints are made (ContactSet::constraints)
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  c.gap = Eigen::Map<const Vector>(gap.data(), rows);
  if (block == 1) {
    c.tangent_dof.clear();
    return c;
  }
  c.T = matrix(t_own, c.rows.size());
  c.remote.T = matrix(t_rem, c.remote.rows.size());
  c.mu = Vector::Constant(rows, 0.3);
  c.tresca = Vector::Zero(rows);
  c.shift = Eigen::Map<const Vector>(shift.data(), rows);
  return c;
}

std::shared_ptr<la::LinearSolver> factored(const la::LinearSolverFactory& make, const la::SpdOperator& K) {
  std::shared_ptr<la::LinearSolver> f = make("K");
  f->factorize(K, "chain stiffness");
  return f;
}

/// The dual on the split rows against one process's whole rows.
void check_dual(const la::Comm& comm, int R, bool far, int block) {
  const SplitChain s(comm, R, far);
  const std::string what0 = fmt::format("R = {} ({} masters), block {}", R, far ? "far" : "near", block);
  auto K_serial = std::make_shared<const la::SparseOperator>(s.elements(0, s.N));
  const la::LinearSolverFactory serial = la::factor_factory(la::serial_backend());
  const ContactConstraints whole = constraints(s, true, block);
  auto one = make_contact_solver("active-set", K_serial, factored(serial, *K_serial), whole, serial);
  const Vector F = s.load();
  Vector u_s, l_s;
  const ContactReport rs = one->solve(F, u_s, l_s);
  check(rs.converged && rs.n_active > 0 && rs.n_active < R && (block == 1 || (rs.n_stick > 0 && rs.n_slip > 0)),
        fmt::format("{}: one process converged, {} of {} active, {} stick, {} slip", what0, rs.n_active, R, rs.n_stick,
                    rs.n_slip),
        comm);

  // Local nodes: the owned range and the node after it (the element between is this rank's).
  const int first = s.begin(s.me), n_local = s.n_owned() + (s.me + 1 < s.p ? 1 : 0);
  std::vector<PetscInt> l2g;
  for (int i = 0; i < 2 * n_local; ++i) l2g.push_back(2 * first + i);
  auto K = std::make_shared<const la::PetscOperator>(comm, s.elements(first, n_local), l2g, 2 * s.n_owned(), 2 * s.N, 1);
  const la::LinearSolverFactory dist = la::factor_factory(la::make_petsc_backend(comm, {}));
  const ContactConstraints split = constraints(s, false, block);
  check(comm.any(!split.remote.rows.empty()) && (far || comm.rank() > 0 || split.remote.rows.empty()),
        what0 + ": pieces held (near: none on rank 0)", comm);
  check(contact_needs(comm, split).spread_pairs && !contact_needs(comm, whole).spread_pairs,
        what0 + ": the needs say spread", comm);
  ContactSolverOptions two_solves;
  two_solves.max_cached_share = 0;
  const bool schur = R * block > 64;  // beyond one block of right-hand sides: MUMPS' Schur complement
  const std::pair<ContactSolverOptions, const char*> variants[] = {
      {{}, schur ? "two solves per step (S by MUMPS' Schur complement)" : "one solve per step (K⁻¹Nᵀ kept)"},
      {two_solves, schur ? "two solves per step (S by MUMPS' Schur complement)" : "two solves per step"}};
  const Vector F_own = F.segment(2 * first, 2 * s.n_owned()), u_own = u_s.segment(2 * first, 2 * s.n_owned());
  for (const auto& [opt, path] : variants) {
    auto solver = make_contact_solver("active-set", K, factored(dist, *K), split, dist, opt);
    const std::string what = fmt::format("{}, {}", what0, solver->describe());
    check(solver->describe().starts_with(path), what + ": the path taken", comm);
    Vector u = Vector::Zero(2 * s.n_owned()), lambda;
    const ContactReport r = solver->solve(F_own, u, lambda);
    check(r.converged && r.n_active == rs.n_active && r.n_stick == rs.n_stick && r.n_slip == rs.n_slip,
          fmt::format("{}: converged, {} active, {} stick, {} slip (one process: {}, {}, {})", what, r.n_active,
                      r.n_stick, r.n_slip, rs.n_active, rs.n_stick, rs.n_slip),
          comm);
    check(close(comm, lambda, l_s, 1e-12), what + ": lambda", comm);
    check(close(comm, u, u_own, 1e-12), what + ": u", comm);
    check(std::abs(r.total_force - rs.total_force) <= 1e-12 * std::abs(rs.total_force) &&
              std::abs(r.dissipation - rs.dissipation) <= 1e-12 * std::max(1.0, std::abs(rs.dissipation)),
          fmt::format("{}: force {} and dissipation {} (one process: {}, {})", what, r.total_force, r.dissipation,
                      rs.total_force, rs.dissipation),
          comm);
    // The residuals read whole rows: N u and T u summed over the pieces, the pieces' loads in Ku = F − Nᵀλ.
    const ContactResiduals x = contact_residuals(*K, solver->constraints(), F_own, u, lambda), y = rs.residuals;
    const double got[] = {x.equilibrium, x.penetration, x.negative_force, x.complementarity, x.friction_bound,
                          x.stick_slip, x.slip_direction};
    const double want[] = {y.equilibrium, y.penetration, y.negative_force, y.complementarity, y.friction_bound,
                           y.stick_slip, y.slip_direction};
    bool same = x.max() <= 1e-12 && std::abs(x.force_scale - y.force_scale) <= 1e-12 * y.force_scale;
    for (int i = 0; i < 7; ++i) same = same && std::abs(got[i] - want[i]) <= 1e-12;
    check(same && r.residuals.max() == x.max(),
          fmt::format("{}: residuals {:.2e} (one process: {:.2e})", what, x.max(), y.max()), comm);
    // Off the solution they see the pieces too: u_s with the master of a row apart from its slave moved.
    int moved = 0;
    while (moved + 1 < R && s.owner(s.row(moved).front().first) == s.owner(s.row(moved).back().first)) ++moved;
    Vector w = u_s;
    w[2 * s.row(moved).back().first + 1] -= 0.05;
    const Vector v = w.segment(2 * first, 2 * s.n_owned());
    const ContactResiduals xv = contact_residuals(*K, solver->constraints(), F_own, v, lambda);
    const ContactResiduals yv = contact_residuals(*K_serial, one->constraints(), F, w, l_s);
    check(std::abs(xv.penetration - yv.penetration) <= 1e-12 && std::abs(xv.complementarity - yv.complementarity) <= 1e-12 &&
              std::abs(xv.equilibrium - yv.equilibrium) <= 1e-12 && yv.max() > 1e-6,
          fmt::format("{}: residuals of a moved master {:.3e} {:.3e} (one process: {:.3e} {:.3e})", what,
                      xv.penetration, xv.complementarity, yv.penetration, yv.complementarity),
          comm);
  }
}

/// The primal and penalty–duality refuse spread rows, naming the dual; auto takes the dual.
void check_refusals(const la::Comm& comm) {
  const SplitChain s(comm, 20, true);
  const int first = s.begin(s.me), n_local = s.n_owned() + (s.me + 1 < s.p ? 1 : 0);
  std::vector<PetscInt> l2g;
  for (int i = 0; i < 2 * n_local; ++i) l2g.push_back(2 * first + i);
  auto K = std::make_shared<const la::PetscOperator>(comm, s.elements(first, n_local), l2g, 2 * s.n_owned(), 2 * s.N, 1);
  const la::LinearSolverFactory dist = la::factor_factory(la::make_petsc_backend(comm, {}));
  const ContactConstraints split = constraints(s, false, 1);
  for (const char* name : {"primal-active-set", "penalty-duality"}) {
    std::string message;
    try {
      make_contact_solver(name, K, factored(dist, *K), split, dist);
    } catch (const Error& e) {
      message = e.what();
    }
    check(message.find(fmt::format("contact solver '{}'", name)) != std::string::npos &&
              message.find("spread over the ranks") != std::string::npos &&
              message.find("--contact-solver active-set") != std::string::npos,
          fmt::format("{} refuses spread rows: '{}'", name, message), comm);
  }
  const ContactNeeds needs = contact_needs(comm, split);
  check(pick_contact_solver("auto", 100000, "cg-gamg", needs).name == "active-set" &&
            pick_contact_solver("auto", 100000, "cg-gamg", ContactNeeds{}).name == "primal-active-set",
        "auto takes the dual for spread rows", comm);
}

int run(int, char**) {
  const la::Comm comm = la::make_mpi_comm(PETSC_COMM_WORLD);
  for (const bool far : {true, false})
    for (const int R : {20, 90})
      for (const int block : {1, 2}) check_dual(comm, R, far, block);
  check_refusals(comm);
  if (comm.rank() == 0) fmt::print("{}\n", failures == 0 ? "spread contact rows: PASSED" : "FAILED");
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) { return vpc::test::petsc_main(argc, argv, "vpcontact_mpi_spread_rows", run); }
