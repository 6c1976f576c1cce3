// Issue 15: non-uniform and error-controlled time steps (problem/time_grid.hpp), the
// damage matrix per step size, exact rollback of a rejected step, and continuing a run
// from a checkpoint with other steps or a later T.
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "problem/time_grid.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "../error_of.hpp"
#include "bar_case.hpp"

namespace vpc {
namespace {

namespace fs = std::filesystem;

std::shared_ptr<Problem> rod(const std::vector<std::string>& sets = {}) {
  return load_case("paper-1d", {.sets = sets}).problem;
}

/// paper-1d with error-controlled steps of this tolerance (no landings but T; the step
/// limits given, not T's defaults).
std::shared_ptr<Problem> adaptive_rod(double tolerance, double T = 1) {
  auto p = rod({fmt::format("time.T={}", T), fmt::format("time.tolerance={}", tolerance), "time.dt_initial=0.01",
                "time.dt_max=0.1", "time.dt_min=1e-6"});
  p->step_control->landings.clear();  // the case file's output times
  return p;
}

fs::path steps_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("vpc_steps_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void expect_same_state(const TimeStepper& a, const TimeStepper& b) {
  const State &x = a.state(), &y = b.state();
  EXPECT_EQ(x.n, y.n);
  EXPECT_EQ(x.t, y.t);
  EXPECT_EQ(x.u, y.u);
  EXPECT_EQ(x.beta, y.beta);
  EXPECT_EQ(x.lambda, y.lambda);
  ASSERT_EQ(x.z.size(), y.z.size());
  for (std::size_t c = 0; c < x.z.size(); ++c) {
    EXPECT_EQ(x.z[c].c, y.z[c].c);
    EXPECT_EQ(x.sigma[c].c, y.sigma[c].c);
  }
  EXPECT_EQ(a.times(), b.times());
}

void run_to_end(TimeStepper& s) {
  while (!s.done()) ASSERT_TRUE(s.step().ok) << "t = " << s.state().t;
}

// ------------------------------------------------------------------ the grids

TEST(TimeGrid, ListsIntervalsAndFormulasEndExactlyAtT) {
  const std::vector<double> steps = {0.25, 0.25, 0.5};
  EXPECT_EQ(fixed_grid_of_steps(1.0, steps).times, (std::vector<double>{0.25, 0.5, 1.0}));
  const std::vector<double> b = {0.4}, k = {0.2, 0.3};
  const FixedGrid intervals = fixed_grid_of_intervals(1.0, b, k);
  EXPECT_EQ(intervals.times, (std::vector<double>{0.2, 0.4, 0.7, 1.0}));
  // The sizes as given, not t_n - t_{n-1} (0.7 - 0.4 is not 0.3 in floating point).
  EXPECT_EQ(intervals.sizes, (std::vector<double>{0.2, 0.2, 0.3, 0.3}));
  // k(t) = 0.3: 0.3, 0.6, 0.9 and a last step of 0.1 to T.
  const FixedGrid f = fixed_grid_of_formula(1.0, [](double) { return 0.3; });
  ASSERT_EQ(f.times.size(), 4u);
  EXPECT_DOUBLE_EQ(f.times[2], 0.9);
  EXPECT_EQ(f.times.back(), 1.0);
  EXPECT_EQ(f.sizes[0], 0.3);
  EXPECT_NEAR(f.sizes[3], 0.1, 1e-15);
}

TEST(TimeGrid, ErrorControlledSizesComeFromALadder) {
  EXPECT_EQ(step_on_ladder(0.5, 1e-6, 0.1), 0.1);
  EXPECT_EQ(step_on_ladder(0.05, 1e-6, 0.1), 0.05);              // dt_max 2^-1, exactly
  EXPECT_EQ(step_on_ladder(0.06, 1e-6, 0.1), 0.1 * std::exp2(-0.75));  // the next size down
  EXPECT_DOUBLE_EQ(step_on_ladder(0.09, 1e-6, 0.1), 0.1 * std::exp2(-0.25));
  EXPECT_EQ(step_on_ladder(1e-9, 1e-6, 0.1), 1e-6);              // not below dt_min
}

TEST(TimeGrid, BadGridsSayWhatIsWrong) {
  const std::vector<double> short_list = {0.25, 0.25};
  EXPECT_NE(error_of([&] { fixed_grid_of_steps(1.0, short_list); }).find("the step sizes add up to 0.5, not to T = 1"),
            std::string::npos);
  const std::vector<double> b = {0.4}, k = {0.3, 0.3};
  EXPECT_NE(error_of([&] { fixed_grid_of_intervals(1.0, b, k); }).find("does not divide [0, 0.4] into whole steps"),
            std::string::npos);
  EXPECT_NE(error_of([&] { fixed_grid_of_formula(1.0, [](double t) { return 0.5 - t; }); }).find("must be > 0"),
            std::string::npos);
  StepControl c;
  c.dt_min = 0.5;
  c.dt_initial = 0.1;
  EXPECT_NE(error_of([&] { (void)c.completed(1.0); }).find("dt_min <= dt_initial <= dt_max"), std::string::npos);
}

TEST(TimeGrid, AStepEndsOnTheNextLandingWithoutASliver) {
  const std::vector<double> landings = {0.5};
  EXPECT_EQ(step_end(0.0, 0.1, 1.0, landings), 0.1);
  EXPECT_EQ(step_end(0.45, 0.1, 1.0, landings), 0.5);     // shortened to land
  EXPECT_EQ(step_end(0.35, 0.1, 1.0, landings), 0.425);   // 0.15 left: two equal steps, not 0.1 + 0.05
  EXPECT_EQ(step_end(0.5, 0.1, 1.0, landings), 0.6);      // a landing reached is passed
  EXPECT_EQ(step_end(0.95, 0.1, 1.0, landings), 1.0);     // T is a landing
}

// ------------------------------------------------------------------ the case file

TEST(TimeSteps, TheCaseFileGivesListsBreakpointsFormulasAndTolerance) {
  const auto list = rod({"time.dt=[0.5, 0.25, 0.25]"});
  EXPECT_EQ(list->n_steps, 3);
  EXPECT_EQ(list->time_at(2), 0.75);
  const auto intervals = rod({"time.breakpoints=[0.5]", "time.dt=[0.1, 0.05]"});
  EXPECT_EQ(intervals->n_steps, 15);
  EXPECT_EQ(intervals->time_at(5), 0.5);
  EXPECT_NEAR(intervals->step_at(6), 0.05, 1e-15);
  const auto formula = rod({"time.dt=\"0.01 + 0.1*t\""});
  EXPECT_DOUBLE_EQ(formula->step_at(1), 0.01);
  EXPECT_EQ(formula->time_at(formula->n_steps), 1.0);
  const auto controlled = rod({"time.tolerance=1e-3", "time.dt_max=0.05"});
  ASSERT_TRUE(controlled->step_control.has_value());
  EXPECT_EQ(controlled->n_steps, 0);
  EXPECT_EQ(controlled->step_control->dt_max, 0.05);
  // The output times (every tenth of T by default) are landings.
  EXPECT_EQ(controlled->step_control->landings.size(), 10u);
  // --steps on a case with error control: a uniform grid again.
  std::string text = test::bar_text("");
  text.replace(text.find("steps = 10"), 10, "tolerance = 1e-3\ndt_max = 0.05");
  EXPECT_TRUE(parse_case(text, "bar.toml", ".", {}).problem->step_control.has_value());
  const auto back = parse_case(text, "bar.toml", ".", {.steps = 20}).problem;
  EXPECT_FALSE(back->step_control.has_value());
  EXPECT_EQ(back->n_steps, 20);
}

TEST(TimeSteps, BadTimeSectionsAreLocated) {
  auto message = [](const std::vector<std::string>& sets) {
    return error_of([&] { load_case("paper-1d", {.sets = sets}); });
  };
  EXPECT_NE(message({"time.dt=[0.5, 0.25]"}).find("--set time.dt=[0.5, 0.25]: the step sizes add up to 0.75, not to T = 1"),
            std::string::npos)
      << message({"time.dt=[0.5, 0.25]"});
  EXPECT_NE(message({"time.dt_min=0.001"}).find("--set time.dt_min=0.001: applies to error-controlled steps only"),
            std::string::npos);
  EXPECT_NE(message({"time.tolerance=-1"}).find("the tolerance must be a number > 0"), std::string::npos);
  EXPECT_NE(message({"time.dt=\"0.1*x\""}).find("a formula in t only"), std::string::npos);
  EXPECT_NE(message({"time.breakpoints=[0.5]"}).find("breakpoints need dt"), std::string::npos);
}

// ------------------------------------------------------------------ the scheme

TEST(TimeSteps, TwoStepSizesFactorTheDamageMatrixTwice) {
  TimeStepper uniform(rod({"time.dt=0.05"})), two(rod({"time.breakpoints=[0.5]", "time.dt=[0.1, 0.05]"}));
  run_to_end(uniform);
  run_to_end(two);
  EXPECT_EQ(uniform.n_damage_matrices(), 1);
  EXPECT_EQ(two.n_damage_matrices(), 2);
  EXPECT_EQ(two.state().t, 1.0);
  EXPECT_EQ(two.state().n, 15);
}

TEST(TimeSteps, TheErrorEstimateIsFirstOrder) {
  // Summed over the run, the local estimates are the global error's estimate: O(k).
  auto summed = [](int n) {
    TimeStepper s(load_case("paper-1d", {.steps = n}).problem);
    double sum = 0;
    while (!s.done()) sum += s.step().error_estimate;
    return sum;
  };
  const double coarse = summed(50), fine = summed(100);
  EXPECT_GT(fine, 0);
  EXPECT_NEAR(coarse / fine, 2.0, 0.2);
}

TEST(TimeSteps, ErrorControlledStepsLandAndMeetTheTolerance) {
  auto p = rod({"time.tolerance=2e-3"});
  const StepControl c = p->step_control->completed(p->final_time);
  TimeStepper s(p);
  int rejected = 0;
  std::vector<double> landed;
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok);
    rejected += r.rejected;
    EXPECT_LE(r.error_estimate, c.tolerance * r.k * (1 + 1e-12)) << "t = " << r.t;
    EXPECT_GE(r.k, c.dt_min);
    EXPECT_LE(r.k, c.dt_max * (1 + 1e-12));
    for (double t : c.landings)
      if (t == r.t) landed.push_back(t);
  }
  EXPECT_EQ(landed, c.landings);  // every output time is a step's end, exactly
  EXPECT_EQ(s.state().t, 1.0);
  EXPECT_GT(rejected, 0);          // contact onset at t = 0.5 is an event
  EXPECT_EQ(s.step_control_state().rejected, rejected);
}

/// Issue 26 (item 5): the reporter's block pressed onto a rigid cylinder, Perzyna with E/(2λ) = 50,
/// on a 20 × 10 mesh.
std::shared_ptr<Problem> block_on_cylinder(const std::string& time) {
  const std::string text = R"([case]
name = "block-cyl"
[mesh]
generator = "rectangle"
lower = [-1.0, 0.0]
upper = [1.0, 1.0]
cells = [20, 10]
diagonal = "crossed"
[boundary]
contact = ["bottom"]
[[boundary.displacement]]
parts = ["top"]
ux = 0
uy = "-0.02*t"
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "perzyna"
lambda = 10.0
sigma_y = 5.0
[damage]
kappa = 1.0
source = "von-mises"
c = 0.01
[[obstacle]]
name = "cylinder"
shape = "cylinder"
center = [0.0, -1.0]
radius = 1.0
[time]
T = 1.0
)" + time;
  return parse_case(text, "block_cyl.toml", ".", {}).problem;
}

TEST(TimeSteps, ErrorControlledStepsOfADampingLawMeetTheirToleranceWithoutOverRefining) {
  // Perzyna damps an error of z at the rate E/(2λ) = 50: a step's local error has faded
  // long before T = 1, so it must not be counted as if it lasted to T. Counted so, the
  // tolerance 1e-2 took 2,547 steps for a σ error of 5e-4 at T (20 times below tolerance · T),
  // where 50 fixed steps give 2e-3.
  TimeStepper fine(block_on_cylinder("steps = 1600")), controlled(block_on_cylinder("tolerance = 1e-2"));
  run_to_end(fine);
  int steps = 0;
  while (!controlled.done()) {
    ASSERT_TRUE(controlled.step().ok);
    ++steps;
  }
  double diff = 0, norm = 0;
  for (std::size_t c = 0; c < fine.state().sigma.size(); ++c) {
    const SymTensor d = controlled.state().sigma[c] - fine.state().sigma[c];
    diff += d.dot(d);
    norm += fine.state().sigma[c].dot(fine.state().sigma[c]);
  }
  const double error = std::sqrt(diff / norm);  // the cells have equal areas
  EXPECT_LT(steps, 200);             // measured 81 (+19 rejected)
  EXPECT_LT(error, 1e-2);            // tolerance · T; measured 2.3e-3
  EXPECT_GT(error, 1e-2 / 20);       // not over-refined either
}

TEST(TimeSteps, ARejectedStepLeavesNoTrace) {
  // The error-controlled run rejects steps; the same steps given as a fixed grid, taken
  // directly, give the same bits.
  TimeStepper adaptive(adaptive_rod(1e-3));
  int rejected = 0;
  FixedGrid taken;
  while (!adaptive.done()) {
    const StepReport r = adaptive.step();
    ASSERT_TRUE(r.ok);
    rejected += r.rejected;
    taken.times.push_back(r.t);
    taken.sizes.push_back(r.k);
  }
  ASSERT_GT(rejected, 0);
  auto fixed = rod();
  fixed->set_fixed_grid(taken);
  TimeStepper direct(fixed);
  run_to_end(direct);
  expect_same_state(adaptive, direct);
}

TEST(TimeSteps, ARejectedStepOfThePenaltySolversLeavesNoTraceEither) {
  // The penalty–duality solvers carry multipliers from step to step: rolled back too.
  SolverChoice pd;
  pd.contact = pd.damage = "penalty-duality";
  TimeStepper adaptive(adaptive_rod(1e-3), pd);
  FixedGrid taken;
  while (!adaptive.done()) {
    const StepReport r = adaptive.step();
    ASSERT_TRUE(r.ok);
    taken.times.push_back(r.t);
    taken.sizes.push_back(r.k);
  }
  ASSERT_GT(adaptive.step_control_state().rejected, 0);
  auto fixed = rod();
  fixed->set_fixed_grid(taken);
  TimeStepper direct(fixed, pd);
  run_to_end(direct);
  expect_same_state(adaptive, direct);
}

// ------------------------------------------------------------------ resume and extend

/// Writes a's checkpoint and resumes b from it; returns what was skipped.
std::vector<std::string> checkpoint_into(const TimeStepper& a, TimeStepper& b, const std::string& name,
                                         bool expect_found = true) {
  const fs::path dir = steps_dir(name);
  write_checkpoint(a, dir, "paper-1d", {}, {});
  std::vector<std::string> skipped;
  EXPECT_EQ(resume_from_checkpoint(b, dir, &skipped).has_value(), expect_found);
  return skipped;
}

TEST(TimeSteps, AResumeInTheMiddleOfAnErrorControlledRunIsBitIdentical) {
  TimeStepper a(adaptive_rod(1e-3)), b(adaptive_rod(1e-3));
  while (a.state().t < 0.55) a.step();  // past the contact onset's rejections
  checkpoint_into(a, b, "adaptive_resume");
  EXPECT_EQ(b.step_control_state().k_next, a.step_control_state().k_next);
  run_to_end(a);
  run_to_end(b);
  expect_same_state(a, b);
}

TEST(TimeSteps, ExtendingTIsTheLongerRun) {
  // A finished run to T = 1 continued to T = 2 (the same k): the run to T = 2 from the start.
  TimeStepper to1(rod({"time.dt=0.05"})), to2(rod({"time.T=2", "time.dt=0.05"})), longer(rod({"time.T=2", "time.dt=0.05"}));
  run_to_end(to1);
  checkpoint_into(to1, to2, "extend");
  EXPECT_EQ(to2.state().n, 20);
  run_to_end(to2);
  run_to_end(longer);
  expect_same_state(to2, longer);
}

TEST(TimeSteps, ExtendingAnErrorControlledRunGoesOnWithItsSteps) {
  // Continued to T = 2, an error-controlled run to T = 1 is the run to T = 2 that lands on t = 1.
  TimeStepper to1(adaptive_rod(1e-3, 1)), to2(adaptive_rod(1e-3, 2));
  auto p = adaptive_rod(1e-3, 2);
  p->step_control->landings = {1.0};
  TimeStepper longer(p);
  run_to_end(to1);
  checkpoint_into(to1, to2, "extend_adaptive");
  run_to_end(to2);
  run_to_end(longer);
  expect_same_state(to2, longer);
}

TEST(TimeSteps, AnErrorControlledRunContinuedWithTheDefaultsGoesOnFromItsProposal) {
  // Issue 26 (item 7), what docs/cases.md claims with the default limits (T/100, T/10) and output
  // times (T/10, …): continued to T = 2, the run to T = 1 takes as its next step the proposal
  // its controller made at T = 1, on the new ladder (dt_max = 0.2), ending at the new output
  // times (0.2, 0.4, …).
  TimeStepper to1(rod({"time.tolerance=2e-3"})), to2(rod({"time.T=2", "time.tolerance=2e-3"}));
  run_to_end(to1);
  const double proposal = to1.step_control_state().k_next;
  checkpoint_into(to1, to2, "extend_defaults");
  EXPECT_EQ(to2.step_control_state().k_next, proposal);
  const StepReport first = to2.step();
  ASSERT_TRUE(first.ok);
  ASSERT_EQ(first.rejected, 0);
  const StepControl c = to2.problem().step_control->completed(2.0);
  EXPECT_EQ(first.t, step_end(1.0, step_on_ladder(proposal, c.dt_min, c.dt_max), 2.0, c.landings));
  // The run to T = 2 from the start takes other steps before t = 1 (dt_initial 0.02, output
  // times 0.2, 0.4, …): the continued run is not it, as docs/cases.md says.
  TimeStepper longer(rod({"time.T=2", "time.tolerance=2e-3"}));
  while (longer.state().t < 1.0) longer.step();
  EXPECT_NE(std::vector<double>(longer.times().begin(), longer.times().begin() + 3),
            std::vector<double>(to1.times().begin(), to1.times().begin() + 3));
}

TEST(TimeSteps, AResumeRefusesOtherStepsBeforeTheCheckpointAndSaysWhere) {
  TimeStepper a(rod({"time.dt=0.1"}));
  for (int i = 0; i < 5; ++i) a.step();
  // Other steps before the checkpoint: refused, naming the first step that differs.
  TimeStepper finer(rod({"time.dt=0.05"}));
  const auto skipped = checkpoint_into(a, finer, "refuse", false);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find("the steps differ from step 1 on: t = 0.10000000000000001 in the checkpoint, "
                            "0.050000000000000003 in this case"),
            std::string::npos)
      << skipped[0];
  // The same steps up to the checkpoint and others after it: continued.
  TimeStepper after(rod({"time.breakpoints=[0.5]", "time.dt=[0.1, 0.05]"}));
  checkpoint_into(a, after, "other_steps_after");
  EXPECT_EQ(after.state().n, 5);
  run_to_end(after);
  EXPECT_EQ(after.state().n, 15);
  // A case whose T ends before the checkpoint.
  TimeStepper shorter(rod({"time.T=0.3", "time.dt=0.1"}));
  const auto too_short = checkpoint_into(a, shorter, "shorter", false);
  ASSERT_EQ(too_short.size(), 1u);
  EXPECT_NE(too_short[0].find("after this case's T = 0.3"), std::string::npos) << too_short[0];
}

}  // namespace
}  // namespace vpc
