// A set-up builds each contact datum once (issue 49): the whole mesh's contact rows (contact_rows),
// each pair's mortar coupling and the part's contact matrix (contact_matrix), counted from the case
// file to the stepper ready (set_up_serial: the case read and checked, the solver plan, the
// stepper's assembly and the contact solver's set-up). A large-sliding pair builds its rows again
// at every step (scheme/pair_slider.hpp), its set-up once.
#include "cases/builtin_cases.hpp"
#include "mortar/mortar_coupling.hpp"
#include "part/contact_matrix.hpp"
#include "problem/contact_rows.hpp"
#include "run/run_case.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace vpc {
namespace {

struct Builds {
  long long rows = 0, mortar = 0, matrix = 0;
};

Builds builds_so_far() { return {contact_rows_builds(), mortar::mortar_coupling_builds(), contact_matrix_builds()}; }

/// What one serial set-up of case `name` builds.
Builds set_up_builds(const std::string& name, const CaseOverrides& overrides = {}) {
  const Builds before = builds_so_far();
  RunOptions options;
  options.quiet = true;
  const std::unique_ptr<Run> run =
      set_up_serial([&](const MeshRequest& m) { return load_case(name, overrides, m); }, options);
  const Builds after = builds_so_far();
  return {after.rows - before.rows, after.mortar - before.mortar, after.matrix - before.matrix};
}

void expect_once(const std::string& name, const Builds& b, long long pairs) {
  EXPECT_EQ(b.rows, 1) << name << ": contact rows";
  EXPECT_EQ(b.mortar, pairs) << name << ": mortar couplings (one per pair)";
  EXPECT_EQ(b.matrix, 1) << name << ": contact matrices";
}

TEST(SetUpBuilds, APairCaseBuildsItsRowsMortarCouplingAndContactMatrixOnce) {
  expect_once("contact-patch-2d", set_up_builds("contact-patch-2d"), 1);
  expect_once("contact-patch-3d", set_up_builds("contact-patch-3d"), 1);
}

TEST(SetUpBuilds, AFrictionalCaseBuildsItsContactDataOnce) {
  expect_once("shear-3d", set_up_builds("shear-3d"), 0);
  // Friction on a pair: the friction frame and the masters' mean come from the same matrix.
  expect_once("cattaneo-mindlin-pair-2d",
              set_up_builds("cattaneo-mindlin-pair-2d", {.sets = {"mesh.size_factor=5", "body[0].mesh.size_factor=5"}}),
              1);
}

TEST(SetUpBuilds, ThePrimalSolverTakesItsReflectionsFromTheSameMatrix) {
  // The primal's K_rot needs N over the part's local columns: the matrix the system keeps.
  expect_once("shear-3d primal", set_up_builds("shear-3d", {.sets = {"solver.contact=\"primal-active-set\""}}), 0);
  expect_once("contact-patch-2d primal",
              set_up_builds("contact-patch-2d", {.sets = {"solver.contact=\"primal-active-set\""}}), 1);
}

// The library's stepper of a problem (Python, `converge`'s levels): its validation's rows cut its part.
TEST(SetUpBuilds, AStepperOfAProblemBuildsItsContactDataOnce) {
  const Case c = load_case("contact-patch-2d");
  const Builds before = builds_so_far();
  const TimeStepper stepper(c.problem);
  const Builds after = builds_so_far();
  expect_once("TimeStepper(contact-patch-2d)",
              {after.rows - before.rows, after.mortar - before.mortar, after.matrix - before.matrix}, 1);
}

TEST(SetUpBuilds, ALargeSlidingPairBuildsItsRowsOnceAtSetUp) {
  const CaseOverrides coarse{.sets = {"mesh.cells=[12, 6, 3]", "body[0].mesh.cells=[3, 3, 2]"}};
  expect_once("punch-3d", set_up_builds("punch-3d", coarse), 1);
}

}  // namespace
}  // namespace vpc
