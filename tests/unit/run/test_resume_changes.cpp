// --resume with a changed case (issue 48): a run continued with another E, μ or Tresca bound
// used to go on silently, steps 1–10 with one problem and 11–20 with another. Each kind of
// input that makes another problem is refused here, naming the key and its value in the
// checkpoint and now; each kind that may change (T and the steps after the checkpoint, the
// output and solver settings, the description) is accepted and recorded in summary.json.
#include "../../case_text.hpp"
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "run/run_case.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <unistd.h>

namespace vpc {
namespace {

namespace fs = std::filesystem;

// A small frictional block on a plane obstacle with a viscoplastic law, damage and loads: one
// key of each kind of input.
const std::string kCase = R"(
[case]
name = "rc"
description = "resume changes"
[mesh]
generator = "rectangle"
lower = [-1.0, 0.0]
upper = [1.0, 0.5]
cells = [4, 2]
[boundary]
clamped = ["top"]
contact = ["bottom"]
[elasticity]
kind = "plane-strain"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "perzyna"
E = 1000.0
lambda = 1000.0
sigma_y = 50.0
[damage]
kappa = 1.0
source = "strain"
c = 2.0
[loads]
f0 = ["0", "-t"]
[[obstacle]]
name = "plane"
shape = "plane"
point = ["0.02*t", "0.005*t"]
normal = [0.0, 1.0]
[contact]
friction = "coulomb"
mu = 0.3
[time]
T = 1.0
steps = 2
)";

fs::path resume_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("vpc_resume_changes_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

/// Runs `text` with `sets` into `dir`, resuming from it when `resume`.
RunResult run(const std::string& text, const std::vector<std::string>& sets, const fs::path& dir, bool resume) {
  RunOptions o;
  o.quiet = true;
  o.output_directory = dir;
  if (resume) o.resume = dir;
  return run_case(
      [&](const MeshRequest& mesh) {
        Case c = parse_case(text, "rc.toml", ".", {.sets = sets}, mesh);
        c.output.directory = dir;
        c.output.vtu = false;
        return c;
      },
      o);
}

/// The error of resuming the 2-step run of `text` with `sets`; "(resumed)" where it resumes.
std::string resume_error(const std::string& text, const std::vector<std::string>& sets, const std::string& name) {
  const fs::path dir = resume_dir(name);
  run(text, {}, dir, false);
  try {
    run(text, sets, dir, true);
  } catch (const Error& e) {
    fs::remove_all(dir);
    return e.what();
  }
  fs::remove_all(dir);
  return "(resumed)";
}

TEST(ResumeChanges, EachKindOfInputThatMakesAnotherProblemIsRefusedNamingTheKey) {
  const std::string tresca = test::replaced(kCase, "friction = \"coulomb\"\nmu = 0.3", "friction = \"tresca\"\nfriction_bound = 1.0");
  const struct {
    std::string text;
    std::vector<std::string> sets;
    std::string named;
  } changes[] = {
      {kCase, {"elasticity.E=2000"}, "elasticity.E: 1000 → 2000"},
      {kCase, {"viscoplasticity.lambda=500"}, "viscoplasticity.lambda: 1000 → 500"},
      {kCase, {"damage.c=3"}, "damage.c: 2 → 3"},
      {kCase, {"contact.law=normal-compliance", "contact.stiffness=1e4"}, "contact.law: (not given) → \"normal-compliance\""},
      {kCase, {"contact.mu=0.6"}, "contact.mu: 0.3 → 0.6"},
      {tresca, {"contact.friction_bound=5"}, "contact.friction_bound: 1 → 5"},
      {kCase, {"loads.f0=['0', '-2*t']"}, "loads.f0: [\"0\", \"-t\"] → [\"0\", \"-2*t\"]"},
      {kCase, {"obstacle[0].point=['0.03*t', '0.005*t']"}, "obstacle[0].point: [\"0.02*t\", \"0.005*t\"] → [\"0.03*t\", \"0.005*t\"]"},
      {kCase, {"mesh.cells=[6, 2]"}, "mesh.cells: [4, 2] → [6, 2]"},
      {kCase, {"boundary.clamped=['top', 'left']"}, "boundary.clamped: [\"top\"] → [\"top\", \"left\"]"},
  };
  int k = 0;
  for (const auto& c : changes) {
    const std::string what = resume_error(c.text, c.sets, fmt::format("refused{}", k++));
    EXPECT_NE(what.find("was written for another case: "), std::string::npos) << what;
    EXPECT_NE(what.find(c.named), std::string::npos) << c.named << " not in: " << what;
  }
}

TEST(ResumeChanges, TheKeysThatMayChangeAreAcceptedPrintedAndRecorded) {
  const fs::path dir = resume_dir("allowed");
  run(kCase, {}, dir, false);
  const std::vector<std::string> sets = {"time.T=2", "time.steps=4", "output.every=1", "solver.tolerance=1e-9",
                                         "case.description='continued'"};
  const RunResult r = run(kCase, sets, dir, true);
  EXPECT_EQ(r.steps, 4);
  std::ifstream in(dir / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  ASSERT_TRUE(summary.contains("changed_on_resume")) << summary.dump(1);
  std::map<std::string, std::pair<std::string, std::string>> changed;
  for (const auto& c : summary["changed_on_resume"]) {
    EXPECT_EQ(c["step"], 2);
    changed[c["key"]] = {c["checkpoint"], c["now"]};
  }
  using P = std::pair<std::string, std::string>;
  EXPECT_EQ(changed["time.T"], P("1", "2"));
  EXPECT_EQ(changed["time.steps"], P("2", "4"));
  EXPECT_EQ(changed["output.every"], P("", "1"));
  EXPECT_EQ(changed["solver.tolerance"], P("1e-08", "1e-09"));
  EXPECT_EQ(changed["case.description"], P("\"resume changes\"", "\"continued\""));
  EXPECT_EQ(changed.size(), 5u);
  // A second resume keeps the first one's changes and adds its own.
  run(kCase, {"time.T=3", "time.steps=6", "output.every=1", "solver.tolerance=1e-9", "case.description='continued'"},
      dir, true);
  std::ifstream again(dir / "summary.json");
  const auto second = nlohmann::json::parse(again)["changed_on_resume"];
  ASSERT_EQ(second.size(), 7u);
  EXPECT_EQ(second[5]["key"], "time.T");
  EXPECT_EQ(second[5]["step"], 4);
  EXPECT_EQ(second[5]["now"], "3");
  fs::remove_all(dir);
}

TEST(ResumeChanges, TheListOfWhatMayChange) {
  for (const char* key : {"time.T", "time.steps", "time.dt", "time.tolerance", "output.every", "output.times",
                          "output.fields", "output.vtu", "solver.contact", "solver.tolerance", "case.description"})
    EXPECT_TRUE(may_change_on_resume(key)) << key;
  for (const char* key : {"output.probes", "elasticity.E", "viscoplasticity.lambda", "damage.kappa", "contact.mu",
                          "contact.friction_bound", "loads.f0", "mesh.cells", "boundary.clamped", "case.name",
                          "obstacle[0].point", "case.units", "timer.x"})
    EXPECT_FALSE(may_change_on_resume(key)) << key;
  const auto changes = case_changes({{"a", "1"}, {"b", "2"}, {"c", "3"}}, {{"a", "1"}, {"b", "4"}, {"d", "5"}});
  ASSERT_EQ(changes.size(), 3u);
  EXPECT_EQ(describe_change(changes[0]), "b: 2 → 4");
  EXPECT_EQ(describe_change(changes[1]), "c: 3 → (not given)");
  EXPECT_EQ(describe_change(changes[2]), "d: (not given) → 5");
}

TEST(ResumeChanges, TheCaseKeysAreTheFileWithItsOverridesNumbersByValue) {
  const Case a = parse_case(kCase, "rc.toml", ".", {.sets = {"elasticity.E=1000"}, .steps = 3});
  const Case b = parse_case(kCase, "rc.toml", ".");
  auto value = [](const Case& c, const std::string& key) {
    for (const auto& [k, v] : c.keys)
      if (k == key) return v;
    return std::string("(none)");
  };
  EXPECT_EQ(value(a, "elasticity.E"), "1000");  // 1000 and 1000.0 alike
  EXPECT_EQ(value(b, "elasticity.E"), "1000");
  EXPECT_EQ(value(a, "time.steps"), "3");
  EXPECT_EQ(value(b, "obstacle[0].shape"), "\"plane\"");
  EXPECT_EQ(value(b, "loads.f0"), "[\"0\", \"-t\"]");
}

}  // namespace
}  // namespace vpc
