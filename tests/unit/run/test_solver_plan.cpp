// Issue 27: the engine and linear solver chosen before set-up (run/solver_plan.hpp): the
// estimates from the node graph, MUMPS's memory, the refusals and the moves to CG + GAMG.
#include "../error_of.hpp"
#include "run/solver_plan.hpp"

#include "cases/builtin_cases.hpp"
#include "fem/assembly.hpp"
#include "part/mesh_part.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <tuple>

namespace vpc {
namespace {


// K's factor scaled from the node graph's analysis is close to CHOLMOD's analysis of K itself.
TEST(SolverPlan, NodeGraphEstimateMatchesTheAnalysisOfK) {
  auto c = load_case("block-3d", {}, {.cells = 10});
  const ProblemSize s = problem_size(*c.problem);
  const MeshPart part = whole_mesh_part(c.problem);
  const Mesh& mesh = c.problem->mesh;
  const auto geo = compute_geometry(mesh);
  const SparseMatrix K = assemble_stiffness(mesh, geo, c.problem->elasticity, part.dofs);
  const FactorEstimate exact = estimate_cholmod_factor(K, "K");
  EXPECT_EQ(s.unknowns, static_cast<double>(K.rows()));
  EXPECT_NEAR(s.K_nonzeros / static_cast<double>(K.nonZeros()), 1.0, 0.15);
  EXPECT_GT(s.K.entries, 0.8 * exact.entries);
  EXPECT_LT(s.K.entries, 2.0 * exact.entries);
  EXPECT_GT(s.K.flops, 0.8 * exact.flops);
  EXPECT_LT(s.K.flops, 3.0 * exact.flops);
  EXPECT_EQ(s.contact_nodes, static_cast<double>(part.n_contact));
}

// A generated mesh built by blocks (issue 30): its factors scaled from a coarser grid's analysis
// (scale_factors) against the analysis of the whole mesh's node graph, in 2D and 3D.
TEST(SolverPlan, FactorsScaledFromACoarserGridMatchTheWholeMeshsAnalysis) {
  for (const auto& [name, fine, coarse] : {std::tuple{"foundation-3d", 24, 12}, std::tuple{"foundation-3d", 30, 10},
                                           std::tuple{"paper-2d", 160, 40}}) {
    auto f = load_case(name, {}, {.cells = fine});
    auto c = load_case(name, {}, {.cells = coarse});
    const ProblemSize whole = problem_size(*f.problem);
    ProblemSize scaled = whole;
    scale_factors(scaled, c.problem->mesh, f.problem->mesh.dim());
    SCOPED_TRACE(::testing::Message() << name << " n = " << fine << " from n = " << coarse);
    std::printf("%s n = %d from n = %d: factor entries %.3f, flops %.3f of the whole mesh's analysis\n", name, fine,
                coarse, scaled.H.entries / whole.H.entries, scaled.H.flops / whole.H.flops);
    EXPECT_EQ(scaled.H.rows, whole.H.rows);
    EXPECT_NEAR(scaled.H.entries / whole.H.entries, 1.0, 0.35);
    EXPECT_NEAR(scaled.H.factor_bytes / whole.H.factor_bytes, 1.0, 0.35);
    EXPECT_GT(scaled.H.flops / whole.H.flops, 0.5);
    EXPECT_LT(scaled.H.flops / whole.H.flops, 2.0);
    EXPECT_NEAR(scaled.K.entries / whole.K.entries, scaled.H.entries / whole.H.entries, 1e-12);
  }
}

// The same for a Gmsh mesh refined on every rank (block_problem_size): the factors scaled from the
// file's mesh refined fewer times. The dome (Gmsh, 6,010 tetrahedra) refined twice, from once.
TEST(SolverPlan, FactorsScaledFromAFewerTimesRefinedMeshMatchTheWholeMeshsAnalysis) {
  for (const auto& [name, fine, coarse] : {std::tuple{"dome-3d", 2, 1}, std::tuple{"dome-3d", 2, 0}}) {
    CaseOverrides refine_fine, refine_coarse;
    refine_fine.sets = {fmt::format("mesh.refine={}", fine)};
    refine_coarse.sets = {fmt::format("mesh.refine={}", coarse)};
    auto f = load_case(name, refine_fine);
    auto c = load_case(name, refine_coarse);
    const ProblemSize whole = problem_size(*f.problem);
    ProblemSize scaled = whole;
    scale_factors(scaled, c.problem->mesh, f.problem->mesh.dim());
    SCOPED_TRACE(::testing::Message() << name << " refined " << fine << " times, from " << coarse);
    std::printf("%s refined %d times from %d: factor entries %.3f, flops %.3f of the whole mesh's analysis\n", name,
                fine, coarse, scaled.H.entries / whole.H.entries, scaled.H.flops / whole.H.flops);
    EXPECT_NEAR(scaled.H.entries / whole.H.entries, 1.0, 0.35);
    EXPECT_GT(scaled.H.flops / whole.H.flops, 0.5);
    EXPECT_LT(scaled.H.flops / whole.H.flops, 2.0);
  }
}

// MUMPS's estimate holds at least CHOLMOD's factors, and every estimate grows with the mesh.
TEST(SolverPlan, MumpsEstimateCoversTheFactorAndGrowsWithTheMesh) {
  double last_mumps = 0, last_cg = 0, last_cholmod = 0;
  for (int n : {4, 6, 8, 10}) {
    auto c = load_case("foundation-3d", {}, {.cells = n});
    const ProblemSize s = problem_size(*c.problem);
    for (int ranks : {1, 2, 4}) {
      const double mumps = mumps_memory(*c.problem, s, ranks, ranks).total();
      EXPECT_GE(mumps, s.K.factor_bytes + s.H.factor_bytes) << n << " " << ranks;
    }
    const double mumps = mumps_memory(*c.problem, s, 2, 2).total();
    const double cg = iterative_memory(*c.problem, s).total();
    const double cholmod = cholmod_memory(*c.problem, s, {}).total();
    EXPECT_GT(mumps, last_mumps) << n;
    EXPECT_GT(cg, last_cg) << n;
    EXPECT_GT(cholmod, last_cholmod) << n;
    last_mumps = mumps, last_cg = cg, last_cholmod = cholmod;
  }
}

// An explicit solver that does not fit is refused, naming the estimate, the limit and the
// option to use; the default moves to CG + GAMG and says why.
TEST(SolverPlan, RefusesOrMovesToCgBeforeSetUp) {
  auto c = load_case("foundation-3d", {}, {.cells = 8});
  const Problem& p = *c.problem;
  const ProblemSize s = problem_size(p);
  const double mumps = mumps_memory(p, s, 2, 2).total(), cg = iterative_memory(p, s).total();
  ASSERT_GT(mumps, cg);
  const MemoryLimit between{0.5 * (mumps + cg), "--memory-limit"};
  const SolverChoice choice;

  const SolverPlan moved = plan_solver(p, s, choice, {.engine = "petsc", .ranks = 2, .ranks_on_machine = 2}, between);
  EXPECT_EQ(moved.linear_solver, "cg-gamg");
  EXPECT_NE(moved.why.find("MUMPS's factors would need about"), std::string::npos) << moved.why;
  const std::string refused = error_of([&] {
    plan_solver(p, s, choice, {.engine = "petsc", .linear_solver = "mumps", .ranks = 2, .ranks_on_machine = 2},
                between);
  });
  for (const char* part : {"foundation-3d: MUMPS would need about", "more than the limit of",
                           "set by --memory-limit", "--linear-solver cg-gamg needs about"})
    EXPECT_NE(refused.find(part), std::string::npos) << part << ": " << refused;
  const std::string nothing_fits = error_of([&] {
    plan_solver(p, s, choice, {.engine = "petsc", .ranks = 2, .ranks_on_machine = 2}, {1024.0 * 1024, "test"});
  });
  EXPECT_NE(nothing_fits.find("CG + GAMG would need about"), std::string::npos) << nothing_fits;

  const SolverPlan fits = plan_solver(p, s, choice, {.engine = "petsc", .ranks = 2}, {1e15, "test"});
  EXPECT_EQ(fits.linear_solver, "mumps");
  EXPECT_TRUE(fits.petsc);
}

// Where CG + GAMG with PETSc's default Galerkin products does not fit, the plan forms them row by
// row (less memory, slower set-ups) and says so; below that it refuses, naming the smaller estimate.
// MUMPS refused points at what CG + GAMG needs; hypre keeps its own estimate.
TEST(SolverPlan, CgGamgFormsItsProductsRowByRowWhereTheDefaultDoesNotFit) {
  auto c = load_case("foundation-3d", {}, {.cells = 8});
  const Problem& p = *c.problem;
  const ProblemSize s = problem_size(p);
  const MemoryEstimate by_default = iterative_memory(p, s), row_by_row = iterative_memory(p, s, "cg-gamg", true);
  ASSERT_LT(row_by_row.total(), by_default.total());
  EXPECT_NE(row_by_row.describe().find("multigrid set-up (products row by row)"), std::string::npos);
  EXPECT_GT(iterative_memory(p, s, "cg-hypre").total(), by_default.total());
  const MemoryLimit between{0.5 * (row_by_row.total() + by_default.total()), "--memory-limit"};
  const SolverChoice choice;
  for (const SolverRequest& r : {SolverRequest{.engine = "petsc", .linear_solver = "cg-gamg", .ranks = 2},
                                 SolverRequest{.engine = "petsc", .ranks = 2}}) {
    const SolverPlan low = plan_solver(p, s, choice, r, between);
    EXPECT_EQ(low.linear_solver, "cg-gamg");
    EXPECT_TRUE(low.products_row_by_row);
    EXPECT_DOUBLE_EQ(low.memory, row_by_row.total());
    EXPECT_NE(low.why.find("Galerkin products formed row by row"), std::string::npos) << low.why;
    const SolverPlan ample = plan_solver(p, s, choice, r, {1e15, "test"});
    EXPECT_FALSE(ample.products_row_by_row);
  }
  const std::string mumps = error_of([&] {
    plan_solver(p, s, choice, {.engine = "petsc", .linear_solver = "mumps", .ranks = 2}, between);
  });
  EXPECT_NE(mumps.find("--linear-solver cg-gamg needs about " + format_bytes(row_by_row.total())), std::string::npos)
      << mumps;
  const std::string refused = error_of([&] {
    plan_solver(p, s, choice, {.engine = "petsc", .linear_solver = "cg-gamg", .ranks = 2},
                {0.99 * row_by_row.total(), "--memory-limit"});
  });
  EXPECT_NE(refused.find("cg-gamg would need about " + format_bytes(row_by_row.total())), std::string::npos) << refused;
  EXPECT_NE(refused.find("(products row by row)"), std::string::npos) << refused;
  const SolverPlan hypre =
      plan_solver(p, s, choice, {.engine = "petsc", .linear_solver = "cg-hypre", .ranks = 2}, {1e15, "test"});
  EXPECT_FALSE(hypre.products_row_by_row);
  EXPECT_DOUBLE_EQ(hypre.memory, iterative_memory(p, s, "cg-hypre").total());
  // One process: auto keeps CHOLMOD where it fits rather than take CG + GAMG's slower set-ups.
  const SolverPlan one = plan_solver(p, s, choice, {.engine = "auto", .petsc_built = true}, between);
  if (cholmod_memory(p, s, choice).total() <= between.bytes)
    EXPECT_EQ(one.linear_solver, "cholmod") << one.why;
  else
    EXPECT_TRUE(one.products_row_by_row) << one.why;
}

// One process: --engine serial refuses a run whose CHOLMOD factors would not fit, at once,
// naming the estimate by part (issue 11); auto takes CG + GAMG instead where the build has it.
TEST(SolverPlan, OneProcessRefusesOrMoves) {
  auto c = load_case("block-3d", {}, {.cells = 10});
  const Problem& p = *c.problem;
  SolverChoice choice;
  choice.memory_limit = "1M";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = error_of([&] { plan_solver(p, choice, {.engine = "serial"}); });
  EXPECT_NE(msg.find("block-3d: the run would need about"), std::string::npos) << msg;
  for (const char* part : {"mesh and state", "matrices", "factor of K", "factor of H",
                           "more than the limit of 1 MiB set by --memory-limit"})
    EXPECT_NE(msg.find(part), std::string::npos) << part << ": " << msg;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);

  auto f = load_case("foundation-3d", {}, {.cells = 12});
  const ProblemSize s = problem_size(*f.problem);
  const double direct = cholmod_memory(*f.problem, s, choice).total(), cg = iterative_memory(*f.problem, s).total();
  ASSERT_GT(direct, cg);
  const MemoryLimit between{0.5 * (direct + cg), "test"};
  const SolverPlan moved = plan_solver(*f.problem, s, choice, {.engine = "auto", .petsc_built = true}, between);
  EXPECT_TRUE(moved.petsc);
  EXPECT_EQ(moved.linear_solver, "cg-gamg");
  EXPECT_NE(moved.why.find("CHOLMOD's factors would need about"), std::string::npos) << moved.why;
  const SolverPlan direct_plan = plan_solver(*f.problem, s, choice, {.engine = "serial"}, {1e15, "test"});
  EXPECT_FALSE(direct_plan.petsc);
  EXPECT_EQ(direct_plan.linear_solver, "cholmod");
}

// Contact pairs (issue 29) are planned as one body is: the primal solver takes them as it takes
// rigid contact (its basis writes a slave node in its masters' dofs), so no engine's estimate adds
// the dual's dense S for a large pair (20,000 slave nodes would be 6.4 GB there), and where CHOLMOD
// does not fit, auto takes CG + GAMG on the PETSc engine, where it fits it keeps it.
TEST(SolverPlan, ContactPairsArePlannedAsOneBodyIs) {
  auto f = load_case("foundation-3d", {}, {.cells = 12});
  Problem& p = *f.problem;
  ProblemSize s = problem_size(p);
  SolverChoice choice;
  const double direct = cholmod_memory(p, s, choice).total(), cg = iterative_memory(p, s).total();
  const MemoryLimit between{0.5 * (direct + cg), "test"}, ample{1e15, "test"};
  const SolverPlan moved_one = plan_solver(p, s, choice, {.engine = "auto", .petsc_built = true}, between);
  const SolverPlan kept_one = plan_solver(p, s, choice, {.engine = "auto", .petsc_built = true}, ample);
  ProblemSize large = s;
  large.contact_unknowns = 20000;
  const double one_body[3] = {cholmod_memory(p, large, choice).total(), iterative_memory(p, large).total(),
                              mumps_memory(p, large, 2, 2).total()};
  ContactPair pair;  // the plan reads only that there are pairs
  pair.slave = "top";
  pair.master = "bottom";
  p.contact.pairs.push_back(pair);
  EXPECT_DOUBLE_EQ(cholmod_memory(p, large, choice).total(), one_body[0]);
  EXPECT_DOUBLE_EQ(iterative_memory(p, large).total(), one_body[1]);
  EXPECT_DOUBLE_EQ(mumps_memory(p, large, 2, 2).total(), one_body[2]);
  const SolverPlan moved = plan_solver(p, s, choice, {.engine = "auto", .petsc_built = true}, between);
  EXPECT_TRUE(moved.petsc);
  EXPECT_EQ(moved.linear_solver, "cg-gamg");
  EXPECT_EQ(moved.why, moved_one.why);
  const std::string msg = error_of([&] { plan_solver(p, s, choice, {.engine = "serial", .petsc_built = true}, between); });
  EXPECT_NE(msg.find("--engine auto would take"), std::string::npos) << msg;
  const SolverPlan kept = plan_solver(p, s, choice, {.engine = "auto", .petsc_built = true}, ample);
  EXPECT_FALSE(kept.petsc);
  EXPECT_EQ(kept.linear_solver, "cholmod");
  EXPECT_EQ(kept.why, kept_one.why);
  // Several bodies: CG + GAMG also holds K without the couplings between them through its set-up.
  p.bodies.push_back({});
  EXPECT_DOUBLE_EQ(iterative_memory(p, large).total(), one_body[1] + 12.0 * large.K_nonzeros);
  EXPECT_DOUBLE_EQ(cholmod_memory(p, large, choice).total(), one_body[0]);
  p.bodies.clear();
  // The dual asked for counts its S = N K⁻¹Nᵀ on pairs as on one body.
  choice.contact = "active-set";
  EXPECT_GE(cholmod_memory(p, large, choice).total() - one_body[0], 8.0 * 20000 * 20000);
  // --spread-pairs on the PETSc engine forces the dual beyond auto's bound: its S (20000² doubles
  // on each of the machine's 2 ranks, 6.4 GB) is refused before set-up where it cannot fit; the
  // same plan without the flag fits (auto takes the primal, which needs no S).
  choice.contact = "auto";
  choice.spread_pairs = true;
  const MemoryLimit four_gb{4e9, "test"};
  const SolverRequest petsc{.engine = "petsc", .ranks = 2, .ranks_on_machine = 2};
  const std::string spread = error_of([&] { plan_solver(p, large, choice, petsc, four_gb); });
  EXPECT_NE(spread.find("--spread-pairs (the dual contact solver alone solves spread rows)"), std::string::npos) << spread;
  EXPECT_NE(spread.find("the dual contact solver's S (20000 x 20000) on 2 ranks"), std::string::npos) << spread;
  choice.spread_pairs = false;
  EXPECT_NO_THROW(plan_solver(p, large, choice, petsc, {1e15, "test"}));
  choice.spread_pairs = true;
  EXPECT_NO_THROW(plan_solver(p, large, choice, petsc, {1e15, "test"}));
  // The dual asked for on the PETSc engine, or taken for a law only it solves, counts its S the same way.
  choice.spread_pairs = false;
  choice.contact = "active-set";
  const std::string asked = error_of([&] { plan_solver(p, large, choice, petsc, four_gb); });
  EXPECT_NE(asked.find("--contact-solver active-set"), std::string::npos) << asked;
  EXPECT_NE(asked.find("the dual contact solver's S (20000 x 20000) on 2 ranks"), std::string::npos) << asked;
  EXPECT_NE(asked.find("--contact-solver auto takes the primal solver"), std::string::npos) << asked;
  choice.contact = "auto";
  ProblemSize power_law = large;
  power_law.dual_only = true;
  const std::string only = error_of([&] { plan_solver(p, power_law, choice, petsc, four_gb); });
  EXPECT_NE(only.find("the only one for this case's contact laws"), std::string::npos) << only;
  EXPECT_EQ(only.find("takes the primal solver"), std::string::npos) << only;
  const std::string primal = error_of([&] { plan_solver(p, large, choice, petsc, four_gb); });  // auto: the primal
  EXPECT_EQ(primal.find("contact solver's S"), std::string::npos) << primal;
}

}  // namespace
}  // namespace vpc
