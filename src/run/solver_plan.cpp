#include "run/solver_plan.hpp"

#include "core/error.hpp"
#include "fem/cell_geometry.hpp"
#include "problem/contact_rows.hpp"
#include "scheme/discrete_system.hpp"
#include "solvers/contact_capabilities.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/solver_cost.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vpc {

namespace {

/// The node graph of the mesh (nodes joined by a cell), lower triangle with the diagonal:
/// the pattern of M, A and H, and K's with each entry a d × d block. Built from sorted
/// pairs, not triplets of values: 8 bytes a pair of a cell.
SparseMatrix node_graph(const Mesh& mesh) {
  const int per_cell = mesh.dim() + 1;
  std::vector<std::uint64_t> pairs;  // column (the smaller node) << 32 | row
  pairs.reserve(static_cast<std::size_t>(mesh.n_cells()) * per_cell * (per_cell - 1) / 2 + mesh.n_nodes());
  for (int i = 0; i < mesh.n_nodes(); ++i) pairs.push_back((std::uint64_t(i) << 32) | std::uint64_t(i));
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const int* v = mesh.cell(c);
    for (int a = 0; a < per_cell; ++a)
      for (int b = 0; b < per_cell; ++b)
        if (v[a] < v[b]) pairs.push_back((std::uint64_t(v[a]) << 32) | std::uint64_t(v[b]));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  SparseMatrix G(mesh.n_nodes(), mesh.n_nodes());
  G.reserve(static_cast<Eigen::Index>(pairs.size()));
  int column = -1;
  for (const std::uint64_t key : pairs) {  // in column order, rows increasing: appended as they come
    const int j = static_cast<int>(key >> 32), i = static_cast<int>(key & 0xffffffffu);
    while (column < j) G.startVec(++column);
    G.insertBackByOuterInner(j, i) = 1.0;
  }
  while (column < mesh.n_nodes() - 1) G.startVec(++column);
  G.finalize();
  return G;
}

/// K's factor from the node graph's: every entry a d × d block, so d² the entries and
/// (each column's count d times, d times the columns) d³ the flops.
FactorEstimate blocked(const FactorEstimate& node, int d, double unknowns) {
  FactorEstimate K = node;
  K.rows = unknowns;
  K.entries *= d * d;
  K.flops *= d * d * d;
  K.factor_bytes *= d * d;
  K.workspace_bytes *= d * d;
  return K;
}

double mesh_bytes(const ProblemSize& s, int d) { return mesh_and_state_bytes(s.nodes, (d + 1) * s.cells, s.cells); }

/// K, M, A and H (twice: H and its reduced copies) as Eigen or AIJ matrices, 12 bytes an entry.
double matrix_bytes(const ProblemSize& s) { return 12.0 * (s.K_nonzeros + 4.0 * s.node_nonzeros); }

/// MUMPS (the MUMPS users' guide, "memory"): its working area is the factors plus the stack
/// of contribution blocks, sized from the analysis and enlarged by ICNTL(14) percent (20 by
/// default; la/petsc.cpp retries a failed factorization with more). Conservatively: 1.5 ×
/// CHOLMOD's entries for MUMPS's own ordering (METIS on the distributed graph, or PORD) and
/// the non-distributed parts, 20 % relaxation, integers at 8 bytes for a fifth of the entries;
/// a stack of two largest contribution blocks on every rank, and 25 % imbalance on P > 1.
double mumps_factor_bytes(const FactorEstimate& f, int ranks, int ranks_on_machine) {
  const double factors = 1.5 * f.entries * (8.0 * 1.2 + 8.0 * 0.2);
  const double stack = 1.2 * 2.0 * f.workspace_bytes;
  const double per_rank = (ranks > 1 ? 1.25 : 1.0) * factors / ranks + stack;
  return per_rank * ranks_on_machine;
}

/// CG + GAMG beyond the mesh and the matrices, in bytes a nonzero of K (docs/parallel.md, "Where
/// the memory goes": foundation-3d n = 70 and 100 on 2 ranks, the ranks' peaks summed, 82 and 62 in
/// all, within 2 %): the copy of K with the active contact rows that the primal solver factors; the
/// hierarchy GAMG keeps (coarse operators, prolongators), its smoothers' and CG's vectors; and what
/// comes on top of those at the peak: the working data of GAMG's Galerkin products PᵀAP during a
/// set-up (la/petsc.cpp frees it after), PETSc's default algorithm holding A·P (0.98 GB a rank at
/// n = 70); or, with the products formed row by row (allatonce: none held, but a set-up takes
/// several times as long, so the plan only where the default does not fit), what a set-up still
/// holds and a checkpoint's one array at a time: 11, since checkpoints no longer copy the whole
/// state (d589959; n = 70 row by row, 3.80 GB summed against 4.33 before, 0.53 GB = 11 B a nonzero
/// less).
constexpr double kActiveRowsCopyBytesPerKNonzero = 12;
constexpr double kHierarchyBytesPerKNonzero = 28;
constexpr double kProductBytesPerKNonzero = 42;
constexpr double kRowByRowProductBytesPerKNonzero = 11;
/// CG + BoomerAMG (hypre) as a whole: 4.43 GB a rank at foundation-3d n = 70 (docs/parallel.md).
constexpr double kHypreBytesPerKNonzero = 150;

/// "memory about 12 MiB (CG + GAMG: about 5 MiB), limit 20 GiB".
std::string memory(const MemoryEstimate& e, const std::string& other, const MemoryEstimate& o, const MemoryLimit& limit) {
  return fmt::format("memory about {} ({}: about {}), limit {}", format_bytes(e.total()), other, format_bytes(o.total()),
                     format_bytes(limit.bytes));
}

/// Refuses the path of estimate `e` (check_memory's message); called only where it does not fit.
[[noreturn]] void refuse(const Problem& p, const MemoryEstimate& e, const MemoryLimit& limit, const std::string& path,
                         const std::string& instead) {
  check_memory(e, limit, p.name, path, instead);
  throw MemoryLimitError(fmt::format("{}: internal: {} refused within the memory limit", p.name, path));
}

/// Why the dual contact solver runs beyond auto's bound on its unknowns (kDualContactRows), and what
/// would avoid it (why empty where it does not): asked for, spread pair rows (the dual's alone) or a
/// law only the dual solves.
struct DualBeyondAuto {
  std::string why, instead;
};
DualBeyondAuto dual_beyond_auto(const Problem& p, const ProblemSize& s, const SolverChoice& solvers) {
  if (s.contact_unknowns <= kDualContactRows) return {};
  const bool spread = p.contact.spreads_pairs(solvers.spread_pairs);
  const std::string primal = s.dual_only ? ""
                             : spread    ? "without --spread-pairs auto takes the primal solver, which needs no S"
                                         : "--contact-solver auto takes the primal solver, which needs no S";
  if (solvers.contact == "active-set") return {"--contact-solver active-set", primal};
  if (solvers.contact != "auto") return {};
  if (spread) return {"--spread-pairs (the dual contact solver alone solves spread rows)", primal};
  if (s.dual_only) return {"the dual contact solver (the only one for this case's contact laws)", ""};
  return {};
}

}  // namespace

ProblemSize problem_size(const Problem& p, const ContactRows& built) {
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim();
  ProblemSize s;
  s.nodes = mesh.n_nodes();
  s.cells = mesh.n_cells();
  const DirichletDofs dirichlet = dirichlet_dofs(p);
  s.unknowns = static_cast<double>(std::ranges::count(dirichlet.condition, -1));
  const ContactRows shared = contact_rows_of(p, dirichlet.condition, built);
  const std::vector<ContactRow>& rows = *shared;
  s.contact_nodes = static_cast<double>(rows.size());
  s.contact_unknowns = s.contact_nodes * p.contact.block_size(d);
  // Frictionless adhesion: the dual's box QP has each bonded node's pull as an unknown besides its force
  // (BondDual, solvers/dual_active_set.cpp): up to 2m, the dense H four times S (pick_contact_solver alike).
  if (p.contact.adhesive() && p.contact.block_size(d) == 1) s.contact_unknowns *= 2;
  const auto laws = p.contact.laws();
  s.dual_only = std::ranges::any_of(rows, [&](const ContactRow& r) {
    return dual_only(*laws[static_cast<std::size_t>(r.law)]);
  });
  const SparseMatrix G = node_graph(mesh);
  s.node_nonzeros = 2.0 * static_cast<double>(G.nonZeros()) - s.nodes;
  const double free_share = s.nodes > 0 ? s.unknowns / (d * s.nodes) : 0;  // of a node's d × d block
  s.K_nonzeros = d * d * s.node_nonzeros * free_share;
  s.H = estimate_cholmod_factor(G, "the node graph of the mesh");
  s.K = blocked(s.H, d, s.unknowns);
  return s;
}

void scale_factors(ProblemSize& s, const Mesh& coarse, int d) {
  const FactorEstimate c = estimate_cholmod_factor(node_graph(coarse), "the node graph of a coarser mesh");
  const double n = coarse.n_nodes(), r = s.nodes / n;
  const double entries = d == 1 ? r : d == 2 ? r * std::log(s.nodes) / std::log(std::max(n, 2.0)) : std::pow(r, 4.0 / 3);
  const double flops = d == 1 ? r : d == 2 ? std::pow(r, 1.5) : r * r;
  s.H = c;
  s.H.rows = s.nodes;
  s.H.entries *= entries;
  s.H.factor_bytes *= entries;
  s.H.workspace_bytes *= entries;
  s.H.flops *= flops;
  s.K = blocked(s.H, d, s.unknowns);
}

MemoryEstimate cholmod_memory(const Problem& p, const ProblemSize& s, const SolverChoice& solvers) {
  const bool dual = solvers.contact == "active-set" ||
                    (solvers.contact == "auto" && (s.dual_only || s.contact_unknowns <= kDualContactRows));
  return estimate_run_memory(mesh_bytes(s, p.mesh.dim()), matrix_bytes(s), s.K, s.H, solvers.damage == "active-set",
                             dual ? s.contact_unknowns : 0);
}

MemoryEstimate mumps_memory(const Problem& p, const ProblemSize& s, int ranks, int ranks_on_machine) {
  MemoryEstimate e;
  e.add("mesh and state", mesh_bytes(s, p.mesh.dim()));
  e.add("matrices", matrix_bytes(s));
  e.add(fmt::format("MUMPS factors of K and H on {} rank{}", ranks_on_machine, ranks_on_machine > 1 ? "s" : ""),
        mumps_factor_bytes(s.K, ranks, ranks_on_machine) + mumps_factor_bytes(s.H, ranks, ranks_on_machine));
  // The dual contact solver's W = K⁻¹Bᵀ (dense, one column per contact unknown) where it takes the dual.
  if (s.contact_unknowns <= kDualContactRows) e.add("contact solver", 8.0 * s.unknowns * s.contact_unknowns);
  return e;
}

MemoryEstimate iterative_memory(const Problem& p, const ProblemSize& s, const std::string& linear_solver,
                                bool products_row_by_row) {
  MemoryEstimate e;
  e.add("mesh and state", mesh_bytes(s, p.mesh.dim()));
  e.add("matrices", matrix_bytes(s));
  if (linear_solver == "cg-hypre") {
    e.add("BoomerAMG and Krylov vectors", kHypreBytesPerKNonzero * s.K_nonzeros);
    return e;
  }
  e.add("K with its active contact rows", kActiveRowsCopyBytesPerKNonzero * s.K_nonzeros);
  e.add("multigrid hierarchy and Krylov vectors", kHierarchyBytesPerKNonzero * s.K_nonzeros);
  e.add(products_row_by_row ? "multigrid set-up (products row by row)" : "multigrid set-up",
        (products_row_by_row ? kRowByRowProductBytesPerKNonzero : kProductBytesPerKNonzero) * s.K_nonzeros);
  // With several bodies GAMG is set up on a copy of K without the couplings between them
  // (la/petsc_segregated.hpp), held through the set-up: foundation-pair-3d n = 70 peaked at
  // 4.75 GB on its larger rank against one body's 4.09 GB.
  if (!p.bodies.empty()) e.add("K without its couplings between bodies (multigrid set-up)", 12.0 * s.K_nonzeros);
  return e;
}

SolverPlan plan_solver(const Problem& p, const SolverChoice& solvers, const SolverRequest& request) {
  return plan_solver(p, problem_size(p), solvers, request, memory_limit(solvers.memory_limit));
}

SolverPlan plan_solver(const Problem& p, const ProblemSize& s, const SolverChoice& solvers,
                       const SolverRequest& r, const MemoryLimit& limit) {
  const MemoryEstimate iterative = iterative_memory(p, s, "cg-gamg", false),
                       row_by_row = iterative_memory(p, s, "cg-gamg", true);
  // `kind` where it fits: CG + GAMG with PETSc's default Galerkin products, else with them formed row
  // by row (saying so), else refused (as `label`) naming the smaller estimate.
  auto iterative_plan = [&](const std::string& kind, const std::string& why, const std::string& label) {
    const MemoryEstimate e = kind == "cg-gamg" ? iterative : iterative_memory(p, s, kind, false);
    if (e.total() <= limit.bytes)
      return SolverPlan{true, kind, fmt::format("{}; memory about {}, limit {}", why, format_bytes(e.total()),
                                                format_bytes(limit.bytes)),
                        e.total()};
    if (kind != "cg-gamg" || row_by_row.total() > limit.bytes) refuse(p, kind == "cg-gamg" ? row_by_row : e, limit, label, "");
    return SolverPlan{true, kind,
                      fmt::format("{}; the multigrid's Galerkin products formed row by row (less memory, slower "
                                  "set-ups): memory about {} against {} with PETSc's default, limit {}",
                                  why, format_bytes(row_by_row.total()), format_bytes(e.total()), format_bytes(limit.bytes)),
                      row_by_row.total(), true};
  };
  auto go_iterative = [&](const std::string& why) { return iterative_plan("cg-gamg", why, "CG + GAMG"); };
  const double cg_needs = iterative.total() <= limit.bytes ? iterative.total() : row_by_row.total();
  // One process's times (solvers/solver_cost.hpp), its direct path on the dual where auto takes it.
  const bool dual = s.dual_only || s.contact_unknowns <= kDualContactRows;
  const SolverCost cost = estimate_solver_cost(s.K, s.K_nonzeros, s.contact_unknowns, p.expected_steps(), dual);
  // The estimate's CG run is the primal solver's, which needs no S; a power law takes the dual,
  // whose S on CG is m solves of K (hertz-spheres-3d on the dual: 766 of them, minutes against
  // CHOLMOD's 20 s), so it moves only when CHOLMOD does not fit.
  // CHOLMOD fits here; CG + GAMG only with its default (faster) set-up.
  const bool cg_clearly_faster =
      solvers.contact == "auto" && !s.dual_only && iterative_is_faster(cost) && iterative.total() <= limit.bytes;
  const MemoryEstimate direct = cholmod_memory(p, s, solvers);
  if (r.engine == "petsc") {  // the PETSc engine: MUMPS (default or asked), or a Krylov solver as asked
    const std::string asked = r.linear_solver.empty() ? "mumps" : r.linear_solver;
    const std::string on = fmt::format("on {} MPI rank{}", r.ranks, r.ranks > 1 ? "s" : "");
    // The dual beyond auto's bound on its unknowns: asked for, forced by spread pair rows
    // (--spread-pairs: the dual's alone) or by a law only it solves. Its dense S, m x m on every rank
    // whatever the linear solver, is refused here where it cannot fit.
    if (const DualBeyondAuto forced = dual_beyond_auto(p, s, solvers); !forced.why.empty()) {
      MemoryEstimate S;
      S.add(fmt::format("the dual contact solver's S ({0:.0f} x {0:.0f}) on {1} rank{2}", s.contact_unknowns,
                        r.ranks_on_machine, r.ranks_on_machine > 1 ? "s" : ""),
            8.0 * s.contact_unknowns * s.contact_unknowns * r.ranks_on_machine);
      if (S.total() > limit.bytes)
        refuse(p, S, limit, forced.why, forced.instead);
    }
    if (asked != "mumps") return iterative_plan(asked, fmt::format("linear solver {} {} (as asked)", asked, on), asked);
    // --engine auto under mpirun: the route one process would take where several ranks cannot gain.
    if (r.auto_route && r.ranks > 1 && cost.direct < kDistributeAbove && direct.total() <= limit.bytes)
      return {false, "cholmod",
              fmt::format("auto under mpirun: rank 0 runs the case alone on CHOLMOD, the other {} rank{} waiting (one "
                          "process is estimated at {:.3g} s, less than the {} s below which {} ranks cannot gain on "
                          "their own costs; --engine petsc distributes it); linear solver CHOLMOD on one process; {}",
                          r.ranks - 1, r.ranks > 2 ? "s" : "", cost.direct, kDistributeAbove, r.ranks,
                          memory(direct, "CG + GAMG", iterative, limit)),
              direct.total()};
    if (r.auto_route && cg_clearly_faster)
      return go_iterative(fmt::format("linear solver CG + GAMG {}, estimated faster as on one process: {}; "
                                      "--linear-solver mumps keeps MUMPS",
                                      on, cost.detail));
    const MemoryEstimate mumps = mumps_memory(p, s, r.ranks, r.ranks_on_machine);
    if (mumps.total() <= limit.bytes)
      return {true, "mumps", fmt::format("linear solver MUMPS {}{}; {}", on,
                                         r.linear_solver.empty() ? " (the default)" : " (as asked)",
                                         memory(mumps, "CG + GAMG", iterative, limit)),
              mumps.total()};
    if (!r.linear_solver.empty()) refuse(p, mumps, limit, "MUMPS", "--linear-solver cg-gamg needs about " +
                                                                       format_bytes(cg_needs));
    return go_iterative(fmt::format("linear solver CG + GAMG {}: MUMPS's factors would need about {} ({}), more than "
                                    "the limit of {} set by {}",
                                    on, format_bytes(mumps.total()), mumps.describe(), format_bytes(limit.bytes),
                                    limit.source));
  }
  // One process: CHOLMOD, or (auto) CG + GAMG where CHOLMOD does not fit or is clearly slower.
  const bool can_switch = r.engine == "auto" && r.petsc_built;
  if (direct.total() > limit.bytes) {
    if (!can_switch) refuse(p, direct, limit, "the run", r.petsc_built ? "--engine auto would take CG + GAMG (about " +
                                                          format_bytes(cg_needs) + ")" : "");
    return go_iterative(fmt::format("CG + GAMG on one process (the PETSc engine): CHOLMOD's factors would need about "
                                    "{} ({}), more than the limit of {} set by {}; --engine serial refuses instead",
                                    format_bytes(direct.total()), direct.describe(), format_bytes(limit.bytes),
                                    limit.source));
  }
  if (can_switch && cg_clearly_faster)
    return go_iterative(fmt::format("CG + GAMG on one process (the PETSc engine), estimated faster: {}; --engine "
                                    "serial keeps CHOLMOD",
                                    cost.detail));
  return {false, "cholmod",
          fmt::format("linear solver CHOLMOD on one process{}; {}", can_switch ? fmt::format(" ({})", cost.detail) : "",
                      memory(direct, "CG + GAMG", iterative, limit)),
          direct.total()};
}

}  // namespace vpc
