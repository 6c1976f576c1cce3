// Issue 49: a contact law's per-node state (contact/surface_state.hpp) reaches the step's rollback,
// the checkpoints, the VTU files, history.csv and the [output] fields with no code outside the law.
// The test-only "worn-coulomb" law (tests/support/test_laws.hpp) is Coulomb friction that keeps
// Archard's worn depth and its slip path without acting on the step: its runs are Coulomb's, and
// its state is checked against what the test recomputes from each step's λ and slip.
#include "friction_runs.hpp"
#include "io/checkpoint.hpp"
#include "run/run_case.hpp"
#include "test_laws.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace vpc {
namespace {

namespace fs = std::filesystem;
using namespace friction_test;

constexpr double kWearRate = 2e-3;

Case worn_shear(const std::string& solver = "active-set", double gap_share = 0) {
  test::register_test_laws();
  Case c = case_of("shear-2d", replaced(shipped_text("shear-2d"), test::kShippedCoulomb,
                                        fmt::format("friction = \"worn-coulomb\"\nmu = 0.3\nwear_factor = {}\ngap_share = {}",
                                                    kWearRate, gap_share)));
  c.solvers.contact = solver;
  return c;
}

const SurfaceField& field(const State& s, const std::string& name) {
  const SurfaceField* f = s.surface_field(name);
  if (!f) throw std::runtime_error("no surface field " + name);
  return *f;
}

TEST(SurfaceState, TheLawsStateIsUpdatedEveryStepFromTheStepsForcesAndSlip) {
  Case coulomb = case_of("shear-2d", shipped_text("shear-2d"));
  coulomb.solvers.contact = "active-set";
  std::vector<Vector> plain;
  run_to_end(coulomb, [&](const TimeStepper& s, const StepReport&) { plain.push_back(s.state().u); });
  EXPECT_TRUE(TimeStepper(coulomb.problem, coulomb.solvers).state().surface.empty());

  const Case c = worn_shear();
  TimeStepper first(c.problem, c.solvers);
  ASSERT_EQ(first.state().surface.size(), 2u);  // at t_0: the declared initial values
  EXPECT_EQ(first.state().surface[0].name, "worn");
  EXPECT_EQ(first.state().surface[1].width, 2);
  EXPECT_EQ(first.state().surface[0].values.size(), first.part().n_contact);
  EXPECT_EQ(first.state().surface[0].values.cwiseAbs().maxCoeff(), 0.0);

  Vector worn = Vector::Zero(first.part().n_contact);  // recomputed here, step by step
  double off_plain = 0, off_worn = 0, off_path = 0, off_volume = 0;
  std::size_t n = 0;
  int steps_off = 0;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    const State& st = s.state();
    off_plain = std::max(off_plain, relative_difference(st.u, plain[n++]));
    double volume = 0;
    for (const PartContactNode& node : s.contact().nodes) {
      const double slip = st.slip_step.segment(node.row, 1).norm();
      worn[node.row] += kWearRate * std::max(st.lambda[node.row * 2], 0.0) / node.measure * slip;
      volume += worn[node.row] * node.measure;
    }
    const SurfaceField &w = field(st, "worn"), &path = field(st, "slip_path");
    off_worn = std::max(off_worn, (w.values - worn).cwiseAbs().maxCoeff() / std::max(worn.maxCoeff(), 1e-300));
    for (Eigen::Index i = 0; i < st.slip.size(); ++i) {
      off_path = std::max(off_path, std::abs(path.values[2 * i] - st.slip[i]) / std::max(st.slip.maxCoeff(), 1e-300));
      steps_off += path.values[2 * i + 1] != r.n;  // one update per accepted step
    }
    ASSERT_EQ(r.surface_integral.size(), 1u);
    off_volume = std::max(off_volume, std::abs(r.surface_integral[0] - volume) / std::max(volume, 1e-300));
  });
  std::printf("  worn-coulomb on shear-2d: u against coulomb %.3g; worn %.3g (max %.4g), slip path against "
              "State::slip %.3g, worn_volume %.3g\n",
              off_plain, off_worn, worn.maxCoeff(), off_path, off_volume);
  EXPECT_EQ(off_plain, 0.0);  // the state does not act on the step: the runs are Coulomb's
  EXPECT_GT(worn.maxCoeff(), 0.0);
  EXPECT_LE(off_worn, 1e-14);
  EXPECT_LE(off_path, 1e-14);
  EXPECT_LE(off_volume, 1e-14);
  EXPECT_EQ(steps_off, 0);
}

// shear-2d's plane rises to y = 0.005 min(t, 1) under the face y = 0 (ν = −e_y): a node in contact has
// u_y = p(t_n) − ω_{n−1} once the worn depth of the step before opens its gap, on both solvers.
TEST(SurfaceState, StateThatMovesTheGapActsOnTheNextStep) {
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    const Case c = worn_shear(solver, 1.0);
    Vector before;
    double off = 0, worn_max = 0, against_plain = 0;
    int in_contact = 0;
    Case coulomb = case_of("shear-2d", shipped_text("shear-2d"));
    TimeStepper plain(coulomb.problem, coulomb.solvers);
    run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
      const State& st = s.state();
      plain.step();
      against_plain = std::max(against_plain, relative_difference(st.u, plain.state().u));
      const Vector& worn = field(st, "worn").values;
      if (before.size() == 0) before = Vector::Zero(worn.size());
      const double p = 0.005 * std::min(r.t, 1.0);
      for (const PartContactNode& node : s.contact().nodes) {
        if (!(st.lambda[node.row * 2] > 0)) continue;
        ++in_contact;
        off = std::max(off, std::abs(st.u[node.local_node * 2 + 1] - (p - before[node.row])) / 0.005);
      }
      worn_max = std::max(worn_max, worn.maxCoeff());
      before = worn;
    });
    std::printf("  %s: worn depth up to %.3g opens the gap: |u_y - (p - w_(n-1))| / 0.005 <= %.3g over %d node-steps "
                "in contact; u against Coulomb's run %.3g\n",
                solver.c_str(), worn_max, off, in_contact, against_plain);
    EXPECT_GT(in_contact, 100);
    // The dual meets an active row's gap to round-off; the primal's frictional iteration stops at its
    // slip-force tolerance (a tenth of the step's residual tolerance), which leaves 1.5e-11 here.
    EXPECT_LE(off, solver == "active-set" ? 1e-12 : 1e-10);
    EXPECT_GT(against_plain, 1e-3);  // the worn face carries the plane's push differently
  }
}

TEST(SurfaceState, ARejectedStepRollsTheStateBack) {
  const Case c = worn_shear();
  TimeStepper s(c.problem, c.solvers);
  for (int i = 0; i < 14; ++i) s.step();  // sliding
  const Snapshot before = s.snapshot();
  s.step();
  ASSERT_NE(s.state().surface[0].values, before.state.surface[0].values);
  const double* storage = s.state().surface[0].values.data();
  s.restore(before);
  EXPECT_EQ(s.state().surface[0].values, before.state.surface[0].values);
  EXPECT_EQ(s.state().surface[1].values, before.state.surface[1].values);
  EXPECT_EQ(s.state().surface[0].values.data(), storage);  // in place: Python's views stay valid
}

TEST(SurfaceState, ACheckpointCarriesTheStateByNameAndAnotherLawsRunIsRefused) {
  const Case c = worn_shear();
  TimeStepper a(c.problem, c.solvers), b(c.problem, c.solvers);
  for (int i = 0; i < 12; ++i) a.step();
  const fs::path dir = fs::temp_directory_path() / "vpc_surface_state_ckpt";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_checkpoint(a, dir, "shear-2d", {}, RunTotals{});
  ASSERT_TRUE(resume_from_checkpoint(b, dir).has_value());
  ASSERT_EQ(b.state().surface.size(), 2u);
  EXPECT_EQ(b.state().surface[0].values, a.state().surface[0].values);
  EXPECT_EQ(b.state().surface[1].values, a.state().surface[1].values);
  while (!a.done()) {  // and it continues as the run that was not interrupted
    a.step();
    b.step();
  }
  EXPECT_EQ(b.state().surface[0].values, a.state().surface[0].values);
  EXPECT_EQ(b.state().u, a.state().u);
  // The whole-state reader has it too.
  const Checkpoint whole = read_checkpoint(dir / "checkpoint_00012.bin");
  ASSERT_EQ(whole.snapshot.state.surface.size(), 2u);
  EXPECT_EQ(whole.snapshot.state.surface[1].name, "slip_path");
  // Coulomb keeps no state: its run cannot continue this checkpoint (nor the other way round).
  Case coulomb = case_of("shear-2d", shipped_text("shear-2d"));
  coulomb.solvers.contact = "active-set";
  TimeStepper other(coulomb.problem, coulomb.solvers);
  std::vector<std::string> skipped;
  EXPECT_FALSE(resume_from_checkpoint(other, dir, &skipped).has_value());
  ASSERT_EQ(skipped.size(), 1u);
  std::printf("  a Coulomb run passes the checkpoint over: %s\n", skipped[0].c_str());
  EXPECT_NE(skipped[0].find("per-node state worn, slip_path, this problem's keep (none)"), std::string::npos);
  fs::remove_all(dir);
}

std::string file_text(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SurfaceState, TheRunsFilesHaveTheStateAndOutputFieldsMayNameIt) {
  RunOptions o;
  o.quiet = true;
  o.checkpoint_every = 0;
  o.output_directory = fs::temp_directory_path() / "vpc_surface_state_run";
  fs::remove_all(o.output_directory);
  const CaseLoader load = [&](const MeshRequest&) {
    Case c = worn_shear();
    c.output.directory = o.output_directory;
    c.output.encoding.compression = VtuCompression::none;
    return c;
  };
  EXPECT_EQ(run_case(load, o).steps, 20);
  const std::string history = file_text(o.output_directory / "history.csv");
  EXPECT_NE(history.substr(0, history.find('\n')).find(",worn_volume"), std::string::npos);
  fs::path last;
  for (const auto& e : fs::directory_iterator(o.output_directory))
    if (e.path().extension() == ".vtu" && e.path() > last) last = e.path();
  const std::string vtu = file_text(last);
  EXPECT_NE(vtu.find("Name=\"worn\""), std::string::npos);
  EXPECT_NE(vtu.find("Name=\"slip_path\" NumberOfComponents=\"2\""), std::string::npos);
  fs::remove_all(o.output_directory);

  // [output] fields names it like any field; an unknown name lists it among those expected.
  test::register_test_laws();
  const std::string text = replaced(shipped_text("shear-2d"), test::kShippedCoulomb, "friction = \"worn-coulomb\"\nmu = 0.3");
  const Case only = case_of("shear-2d", replaced(text, "every = 5", "every = 5\nfields = [\"worn\", \"slip\"]"));
  EXPECT_EQ(only.output.fields, (std::vector<std::string>{"worn", "slip"}));
  try {
    (void)case_of("shear-2d", replaced(text, "every = 5", "every = 5\nfields = [\"wron\"]"));
    ADD_FAILURE() << "an unknown field was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("slip_path"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vpc
