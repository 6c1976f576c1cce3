// Issue 11 items 2 and 3: the memory estimate (CHOLMOD's symbolic analysis gives
// the factor's size before the numeric factorization), the limit, the refusal, and
// CHOLMOD failures as clean vpc::Errors.
#include "../error_of.hpp"
#include "../solve_with.hpp"
#include "la/memory_estimate.hpp"

#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "material/elasticity.hpp"
#include "mesh/generators.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

namespace vpc {
namespace {

TEST(MemoryEstimate, ParsesSizes) {
  EXPECT_EQ(parse_memory_size("512M", "x"), 512.0 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("1.5G", "x"), 1.5 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("8 GiB", "x"), 8.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("64kb", "x"), 64.0 * 1024);
  EXPECT_EQ(parse_memory_size("2000000000", "x"), 2e9);
  EXPECT_EQ(parse_memory_size("2000000000B", "x"), 2e9);
  EXPECT_TRUE(std::isinf(parse_memory_size("unlimited", "x")));
  for (const char* bad : {"", "3x", "-1G", "0", "G", "1e999"}) {
    const std::string msg = error_of([&] { parse_memory_size(bad, "--memory-limit"); });
    EXPECT_NE(msg.find("--memory-limit: expected a memory size > 0"), std::string::npos) << bad << ": " << msg;
  }
}

TEST(MemoryEstimate, LimitFromOptionThenEnvironmentThenMachine) {
  ::setenv(kMemoryLimitVariable, "3G", 1);
  EXPECT_EQ(memory_limit("1G").bytes, 1024.0 * 1024 * 1024);
  EXPECT_EQ(memory_limit("1G").source, "--memory-limit");
  EXPECT_EQ(memory_limit().bytes, 3.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(memory_limit().source, kMemoryLimitVariable);
  ::unsetenv(kMemoryLimitVariable);
  const MemoryLimit machine = memory_limit();
  EXPECT_GT(machine.bytes, 0);
  EXPECT_TRUE(std::isfinite(machine.bytes)) << "MemAvailable of /proc/meminfo not read";
  EXPECT_NE(machine.source.find("memory"), std::string::npos);
}

TEST(MemoryEstimate, RefusalNamesPartsAndLimit) {
  MemoryEstimate e;
  e.add("factor of K", 3.0 * 1024 * 1024 * 1024);
  e.add("matrices", 512.0 * 1024 * 1024);
  EXPECT_NO_THROW(check_memory(e, {4.0 * 1024 * 1024 * 1024, "test"}, "case"));
  const std::string msg = error_of([&] { check_memory(e, {1024.0 * 1024 * 1024, "--memory-limit"}, "case"); });
  EXPECT_NE(msg.find("case: the run would need about 3.5 GiB of memory (factor of K 3 GiB + matrices 512 MiB), "
                     "more than the limit of 1 GiB set by --memory-limit"),
            std::string::npos)
      << msg;
}

/// The stiffness of the unit cube of n³ cubes clamped at the bottom.
SparseMatrix clamped_cube_stiffness(int n) {
  const Mesh m = make_box({0, 0, 0}, {1, 1, 1}, n, n, n);
  const DofMap dofs(m.n_nodes(), 3, m.nodes_of_parts({"bottom"}));
  return assemble_stiffness(m, compute_geometry(m), Elasticity(Elasticity::Kind::Isotropic, 1.0, 0.3), dofs);
}

// The symbolic analysis predicts the factor's memory; factorize() then reuses it.
// Measured on a mid-size 3D case (n = 12: 6084 unknowns): the estimate is the
// factor's size exactly (same CHOLMOD structure), and the analysis costs a small
// part of the factorization.
TEST(MemoryEstimate, AnalysisPredictsFactorSize) {
  const SparseMatrix K = clamped_cube_stiffness(12);
  auto f = la::make_cholmod_factor();
  const FactorEstimate e = *f->analyze(la::SparseOperator(K), "K");
  EXPECT_GT(e.entries, static_cast<double>(K.nonZeros()) / 2);
  EXPECT_GT(e.workspace_bytes, 0);
  f->factorize(la::SparseOperator(K), "K");
  EXPECT_EQ(f->n_factorizations(), 1);
  EXPECT_NEAR(e.factor_bytes / f->factor_bytes(), 1.0, 1e-12);
  EXPECT_EQ(estimate_cholmod_factor(K, "K").factor_bytes, e.factor_bytes);
  // The factor solves (the reused analysis belongs to this matrix).
  const Vector b = Vector::LinSpaced(K.rows(), -1.0, 2.0);
  EXPECT_LT((K * solve_with(*f, b) - b).norm(), 1e-9 * b.norm());
}

// A new matrix after an analysis of another one: analysis redone, no stale structure.
TEST(MemoryEstimate, FactorizeOfAnotherMatrixReanalyzes) {
  const SparseMatrix small = clamped_cube_stiffness(2), large = clamped_cube_stiffness(3);
  auto f = la::make_cholmod_factor();
  f->analyze(la::SparseOperator(small), "K");
  f->factorize(la::SparseOperator(large), "K");
  const Vector b = Vector::Ones(large.rows());
  EXPECT_LT((large * solve_with(*f, b) - b).norm(), 1e-9 * b.norm());
}

TEST(CholmodErrors, SolveWithoutFactorIsAnError) {
  auto f = la::make_cholmod_factor();
  const SparseMatrix K = clamped_cube_stiffness(2);
  f->analyze(la::SparseOperator(K), "stiffness");
  EXPECT_NE(error_of([&] { solve_with(*f, Vector::Ones(K.rows())); }).find("stiffness: solve without a successful factorization"),
            std::string::npos);
}

// The not-positive-definite error names the matrix and its size.
TEST(CholmodErrors, NotPositiveDefiniteNamesMatrixAndSize) {
  SparseMatrix A = clamped_cube_stiffness(2);
  A.coeffRef(5, 5) = -1.0;
  auto f = la::make_cholmod_factor();
  const std::string msg = error_of([&] { f->factorize(la::SparseOperator(A), "elastic stiffness K"); });
  EXPECT_NE(msg.find(fmt::format("elastic stiffness K (n = {}, ", A.rows())), std::string::npos) << msg;
  EXPECT_NE(msg.find("nonzeros in the lower triangle): the matrix is not positive definite"), std::string::npos) << msg;
  EXPECT_EQ(f->n_factorizations(), 0);
}

// A run beyond the memory limit is refused before any factorization, at once,
// naming the estimate by part and the limit.
TEST(MemoryEstimate, TimeStepperRefusesRunBeyondLimit) {
  auto c = load_case("block-3d", {}, {.cells = 10});
  SolverChoice choice;
  choice.memory_limit = "1M";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = error_of([&] { TimeStepper s(c.problem, choice); });
  EXPECT_NE(msg.find("block-3d: the run would need about"), std::string::npos) << msg;
  for (const char* part : {"mesh and state", "matrices", "factor of K", "factor of H", "contact solver",
                           "more than the limit of 1 MiB set by --memory-limit"})
    EXPECT_NE(msg.find(part), std::string::npos) << part << ": " << msg;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  choice.memory_limit = "unlimited";
  EXPECT_NO_THROW(TimeStepper(c.problem, choice));
}

}  // namespace
}  // namespace vpc
