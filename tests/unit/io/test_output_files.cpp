// The output directory: checked before set-up with the OS's reason, and a fresh
// run's clean-up of an earlier run's outputs (and of nothing else).
#include "core/error.hpp"
#include "io/output_files.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <unistd.h>

namespace vpc {
namespace {

namespace fs = std::filesystem;

fs::path output_files_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("vpc_output_files_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void touch(const fs::path& p) { std::ofstream(p) << "x"; }

TEST(OutputFiles, PrepareGivesTheReason) {
  try {
    prepare_output_directory("/proc/vpc_no_such/out");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create the output directory '/proc/vpc_no_such/out': "),
              std::string::npos)
        << e.what();
  }
  const fs::path d = output_files_dir("file");
  touch(d / "plain");
  EXPECT_THROW(prepare_output_directory(d / "plain"), Error);
  EXPECT_NO_THROW(prepare_output_directory(d / "new" / "sub"));
  EXPECT_TRUE(fs::is_directory(d / "new" / "sub"));
  EXPECT_TRUE(fs::is_empty(d / "new" / "sub"));  // the write test leaves nothing
}

TEST(OutputFiles, RemovesAnEarlierRunsOutputsOnly) {
  const fs::path d = output_files_dir("earlier");
  const std::vector<std::string> outputs = {"solution.pvd", "solution_00001.vtu", "solution_00002.pvtu",
                                            "solution_00002_p0001.vtu", "history.csv", "probes.csv",
                                            "summary.json", "checkpoint_00010.bin", "history.csv.tmp.1234"};
  const std::vector<std::string> others = {"notes.txt", "mesh.vtu", "history.csv.bak", "solution.pvd.orig",
                                           "checkpoint_1.bin.old", "x.tmp.abc"};
  for (const auto& f : outputs) touch(d / f);
  for (const auto& f : others) touch(d / f);
  fs::create_directories(d / "figures");
  touch(d / "figures" / "fig_4_6_x.png");
  touch(d / "figures" / "y.svg");
  const auto removed = remove_run_outputs(d);
  EXPECT_EQ(removed.size(), outputs.size() + 2);
  for (const auto& f : outputs) EXPECT_FALSE(fs::exists(d / f)) << f;
  for (const auto& f : others) EXPECT_TRUE(fs::exists(d / f)) << f;
  EXPECT_FALSE(fs::exists(d / "figures"));  // empty once the figures are gone
  // A figures folder with the user's own files in it stays, with them.
  fs::create_directories(d / "figures");
  touch(d / "figures" / "a.png");
  touch(d / "figures" / "keep.txt");
  remove_run_outputs(d);
  EXPECT_FALSE(fs::exists(d / "figures" / "a.png"));
  EXPECT_TRUE(fs::exists(d / "figures" / "keep.txt"));
}

TEST(OutputFiles, RemovesTemporaryFiles) {
  const fs::path d = output_files_dir("tmp");
  touch(d / "checkpoint_00001.bin.tmp.42");
  touch(d / "summary.json.tmp.7");
  touch(d / "summary.json");
  EXPECT_EQ(remove_temporary_files(d), 2);
  EXPECT_TRUE(fs::exists(d / "summary.json"));
  EXPECT_EQ(remove_temporary_files(d / "no_such_dir"), 0);
}

}  // namespace
}  // namespace vpc
