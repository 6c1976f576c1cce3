// The run loop (run/run_case.hpp): on a scripted engine (what it calls, and when:
// checkpoints at step 0, on schedule, at the end and when interrupted; the
// failed-step error) and on the serial engine (a run, and its resume).
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "run/run_case.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <unistd.h>

namespace vpc {
namespace {

namespace fs = std::filesystem;

/// An engine whose steps are scripted: it logs what the loop asks of it.
class ScriptedRun final : public Run {
 public:
  int n = 0, total = 5, fail_at = -1, signal_after = -1;
  std::string log;
  fs::path dir = fs::temp_directory_path();

  bool done() const override { return n >= total; }
  StepReport step() override {
    StepReport r;
    r.n = ++n;
    r.t = 0.1 * n;
    r.ok = n != fail_at;
    log += fmt::format("s{} ", n);
    return r;
  }
  int n_steps() const override { return total; }
  double final_time() const override { return total; }
  double tolerance() const override { return 1e-8; }
  void open_output() override { log += "open "; }
  const fs::path& directory() const override { return dir; }
  void start() override { log += "start "; }
  void record(const StepReport& r) override { log += fmt::format("r{} ", r.n); }
  void finish(double) override { log += "finish"; }
  void checkpoint() override { log += fmt::format("c{} ", n); }
  std::optional<ResumedAt> resume(const fs::path&, std::vector<std::string>& skipped) override {
    skipped.push_back("checkpoint_00009.bin: bad checksum");
    return std::nullopt;
  }
  int interrupt_anywhere() const override { return n == signal_after ? SIGTERM : 0; }
};

RunOptions quiet(int checkpoint_every = 0) {
  RunOptions o;
  o.quiet = true;
  o.checkpoint_every = checkpoint_every;
  return o;
}

TEST(RunLoop, CheckpointsAtTheStartOnScheduleAndAtTheEnd) {
  ScriptedRun e;
  const RunResult r = run_engine(e, quiet(2));
  EXPECT_EQ(e.log, "open start c0 s1 r1 s2 r2 c2 s3 r3 s4 r4 c4 s5 r5 c5 finish");
  EXPECT_EQ(r.steps, 5);
  EXPECT_EQ(r.signal, 0);
}

TEST(RunLoop, ASignalStopsAfterTheStepWithACheckpoint) {
  ScriptedRun e;
  e.signal_after = 2;
  const RunResult r = run_engine(e, quiet());
  EXPECT_EQ(e.log, "open start c0 s1 r1 s2 r2 c2 finish");
  EXPECT_EQ(r.steps, 2);
  EXPECT_EQ(r.signal, SIGTERM);
}

TEST(RunLoop, AFailedStepIsOneErrorForEveryProcess) {
  ScriptedRun e;
  e.fail_at = 3;
  try {
    run_engine(e, quiet());
    FAIL() << "no error";
  } catch (const CollectiveError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("step 3 (t = 0.3) failed: the contact solver stopped at its iteration limit"), std::string::npos) << what;
    EXPECT_NE(what.find("continues from step 0 (--retry-halvings N retries"), std::string::npos) << what;
  }
  EXPECT_EQ(e.log, "open start c0 s1 r1 s2 r2 s3 finish");  // step 3 is not recorded
}

TEST(RunLoop, ResumeWithoutAGoodCheckpointSaysWhy) {
  ScriptedRun e;
  RunOptions o = quiet();
  o.resume = "somewhere";
  try {
    run_engine(e, o);
    FAIL() << "no error";
  } catch (const CollectiveError& err) {
    EXPECT_STREQ(err.what(),
                 "--resume: no good checkpoint for this case in 'somewhere': checkpoint_00009.bin: bad checksum");
  }
}

// RunLoop one step at a time (the Python module's Simulation): the same calls as run_engine,
// a checkpoint when asked, finish once; without files it only steps.
TEST(RunLoop, StepByStepAndWithoutFiles) {
  ScriptedRun e;
  RunLoop loop(e, quiet(0));
  loop.step();
  loop.step();
  loop.checkpoint();
  EXPECT_EQ(loop.last_checkpoint(), 2);
  loop.finish();
  loop.finish();
  EXPECT_TRUE(loop.finished());
  EXPECT_EQ(e.log, "open start c0 s1 r1 s2 r2 c2 finish");

  ScriptedRun bare;
  RunOptions o = quiet(0);
  o.files = false;
  RunLoop only_steps(bare, o);
  while (!only_steps.done()) only_steps.step();
  only_steps.checkpoint();
  only_steps.finish();
  EXPECT_EQ(bare.log, "s1 s2 s3 s4 s5 ");
  EXPECT_EQ(only_steps.result().steps, 5);
  bare.n = 0;
  bare.fail_at = 2;
  RunLoop failing(bare, o);
  failing.step();
  try {
    failing.step();
    FAIL() << "no error";
  } catch (const CollectiveError& err) {
    EXPECT_NE(std::string(err.what()).find("failed: the contact solver stopped at its iteration limit"), std::string::npos);
    EXPECT_NE(std::string(err.what()).find("No output directory"), std::string::npos) << err.what();
  }
  EXPECT_TRUE(failing.finished());
}

fs::path run_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("vpc_run_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

TEST(RunCase, SerialRunThenResumeFromItsLastCheckpoint) {
  RunOptions o = quiet();
  o.output_directory = run_dir("serial");
  const CaseLoader load = [&](const MeshRequest&) {
    Case c = load_case("paper-1d", {.steps = 6});
    c.output.directory = o.output_directory;
    return c;
  };
  const RunResult r = run_case(load, o);
  EXPECT_EQ(r.steps, 6);
  EXPECT_EQ(r.signal, 0);
  for (const char* f : {"history.csv", "probes.csv", "summary.json", "checkpoint_00006.bin"})
    EXPECT_TRUE(fs::exists(o.output_directory / f)) << f;
  o.resume = o.output_directory;  // nothing left to do: the summary is written again
  EXPECT_EQ(run_case(load, o).steps, 6);
  fs::remove_all(o.output_directory);
}

}  // namespace
}  // namespace vpc
