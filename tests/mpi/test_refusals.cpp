// What the PETSc engine does not do yet is refused, never ignored (issue 12):
// DistributedTimeStepper's constructor throws vpc::Error naming the option and
// saying it is serial-only for now, on every rank alike. Run under mpirun -np 2.
// The command-line side (penalty–duality, --retry-halvings) is covered by the
// "expected refusal" entries of the equivalence matrix (CMakeLists.txt).
#include "cases/builtin_cases.hpp"
#include "parallel/distributed_time_stepper.hpp"
#include "la/petsc_util.hpp"

#include <gtest/gtest.h>

#include <string>

namespace vpc {
namespace {

/// The message the constructor throws with `choice` ("" if none); collective.
std::string refusal(const SolverChoice& choice) {
  const Case c = load_case("paper-1d", {.steps = 2}, {.cells = 12});
  try {
    DistributedTimeStepper stepper(c.problem, distribute_mesh(PETSC_COMM_WORLD, *c.problem), choice);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

void expect_refused(const SolverChoice& choice, const std::string& option) {
  const std::string what = refusal(choice);
  EXPECT_NE(what.find(option), std::string::npos) << what;
  EXPECT_NE(what.find("serial-only for now"), std::string::npos) << what;
  EXPECT_NE(what.find("--engine serial"), std::string::npos) << what;
  // Every rank refuses alike (no rank left waiting in a collective call).
  EXPECT_TRUE(allreduce_and(PETSC_COMM_WORLD, !what.empty()));
}

TEST(PetscEngineRefuses, TheDefaultsAreAccepted) { EXPECT_EQ(refusal({}), ""); }

TEST(PetscEngineRefuses, PenaltyDualityContact) {
  SolverChoice s;
  s.contact = "penalty-duality";
  expect_refused(s, "--contact-solver (solver.contact) penalty-duality");
}

TEST(PetscEngineRefuses, PenaltyDualityDamage) {
  SolverChoice s;
  s.damage = "penalty-duality";
  expect_refused(s, "--damage-solver (solver.damage) penalty-duality");
}

TEST(PetscEngineRefuses, StepHalving) {
  SolverChoice s;
  s.max_halvings = 3;
  expect_refused(s, "--retry-halvings 3");
}

TEST(PetscEngineRefuses, ContactSolverOptions) {
  for (int which = 0; which < 4; ++which) {
    SolverChoice s;
    if (which == 0) s.contact_options.tolerance = 1e-10;
    if (which == 1) s.contact_options.max_iterations = 10;
    if (which == 2) s.contact_options.omega = 2;
    if (which == 3) s.contact_options.max_cached_share = 0;
    expect_refused(s, "SolverChoice::contact_options");
  }
}

TEST(PetscEngineRefuses, DamageReducedSolve) {
  for (ReducedSolve r : {ReducedSolve::capacitance, ReducedSolve::reduced_factor}) {
    SolverChoice s;
    s.damage_reduced = r;
    expect_refused(s, "SolverChoice::damage_reduced");
  }
}

}  // namespace
}  // namespace vpc

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (PetscInitializeNoArguments() != 0) return 2;
  const int rc = RUN_ALL_TESTS();
  PetscFinalize();
  return rc;
}
