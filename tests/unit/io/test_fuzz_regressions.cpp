// Regressions from fuzzing (fuzz/, docs/reliability.md). Each input crashed the
// program, read undefined memory or exhausted it before its fix; it must now
// give a clear vpc::Error (or be read correctly).
#include "../../case_text.hpp"
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "mesh/gmsh_reader.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace vpc {
namespace {

namespace fs = std::filesystem;

const char* kCase = R"([mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [4, 2]

[boundary]
clamped = "top"
contact = "bottom"

[elasticity]
kind = "plane-stress"
E = 100.0
nu = 0.25

[contact]
gap = 0.0

[time]
steps = 2

[output]
probes = [[1.0, 0.5]]
)";

/// The case with the first occurrence of `from` replaced by `to`.
std::string variant(const std::string& from, const std::string& to) { return test::replaced(kCase, from, to); }

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  return test::case_error(text, "fuzz.toml", sets);
}

fs::path temp_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("vpc_fuzz_regressions_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / name, std::ios::binary) << text;
  return dir / name;
}

std::string read_error(const fs::path& file) {
  try {
    read_gmsh(file);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FuzzRegressions, TheCaseIsValid) { EXPECT_EQ(error_of(kCase), "(no error)"); }

// fuzz_case_file: `--set " =1"` left no key after trimming; the last part of
// the empty key was read from an empty vector.
TEST(FuzzRegressions, BlankOverrideKeyIsAnError) {
  for (const char* o : {" =1", "\t=x", " \t =[1]"})
    EXPECT_NE(error_of(kCase, {o}).find("expected key=value"), std::string::npos) << error_of(kCase, {o});
}

// fuzz_case_file: an integer that a double cannot hold exactly (> 2^53) was read
// through an empty std::optional (toml++'s value<double>() is empty for it).
TEST(FuzzRegressions, IntegersBeyondDoublePrecisionAreNumbers) {
  const Case c = parse_case(variant("E = 100.0", "E = 9007199254740993"), "fuzz.toml", ".");
  EXPECT_EQ(c.problem->elasticity.young(), 9007199254740992.0);
  EXPECT_EQ(error_of(variant("upper = [2.0, 1.0]", "upper = [9007199254740993, 9223372036854775807]")), "(no error)");
  EXPECT_EQ(error_of(variant("gap = 0.0", "gap = 9007199254740993")), "(no error)");
  // Read as the number it is; a probe outside the mesh is then refused (issue 26).
  EXPECT_NE(error_of(variant("probes = [[1.0, 0.5]]", "probes = [[9007199254740993, 0]]"))
                .find("output.probes[0]: probe point (9007199254740992, 0, 0) lies outside the mesh"),
            std::string::npos);
  // Issue 26 item 22: the message said "expected an integer of reasonable size, got an integer".
  const std::string big = error_of(variant("steps = 2", "steps = 9007199254740993"));
  EXPECT_NE(big.find("time.steps: expected an integer between -1073741824 and 1073741824, got 9007199254740993"),
            std::string::npos)
      << big;
}

// fuzz_case_file: nan and inf are TOML numbers; arrays, formulas given as
// numbers and probes took them (a mesh with infinite corners, a NaN gap).
TEST(FuzzRegressions, NonFiniteNumbersAreErrors) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"upper = [2.0, 1.0]", "upper = [inf, 1.0]"},
      {"lower = [0.0, 0.0]", "lower = [-inf, 0.0]"},
      {"upper = [2.0, 1.0]", "upper = [2.0, nan]"},
      {"gap = 0.0", "gap = nan"},
      {"gap = 0.0", "gap = 0.0\ndirection = [nan, -1]"},
      {"probes = [[1.0, 0.5]]", "probes = [[nan, 0.5]]"},
      {"probes = [[1.0, 0.5]]", "times = [inf]"},
      {"steps = 2", "steps = 2\n[loads]\nf0 = [0, -inf]"},
  };
  for (const auto& [from, to] : bad) {
    const std::string msg = error_of(variant(from, to));
    EXPECT_NE(msg.find("finite"), std::string::npos) << to << "\n" << msg;
  }
}

// fuzz_case_file: cells per direction were capped at 100000, but their product
// was not: [100000, 100000] asked for 2e10 triangles (int overflow, memory).
TEST(FuzzRegressions, HugeGeneratedMeshesAreRejectedAtOnce) {
  const auto start = std::chrono::steady_clock::now();
  std::string msg = error_of(variant("cells = [4, 2]", "cells = [100000, 100000]"));
  EXPECT_NE(msg.find("the mesh would have 20000000000 cells; at most 30000000 are allowed"), std::string::npos) << msg;
  msg = error_of(variant("cells = [4, 2]", "cells = 4000"));
  EXPECT_NE(msg.find("at most 30000000"), std::string::npos) << msg;
  msg = error_of(
      variant("generator = \"rectangle\"\nlower = [0.0, 0.0]\nupper = [2.0, 1.0]\ncells = [4, 2]",
              "generator = \"box\"\nlower = [0, 0, 0]\nupper = [1, 1, 1]\ncells = 1000"));
  EXPECT_NE(msg.find("the mesh would have 6000000000 cells"), std::string::npos) << msg;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

// A float cell count beyond int (1e300) was converted to int (undefined; on
// x86 the message said "got -2147483648").
TEST(FuzzRegressions, CellCountsOutOfRangeAreErrors) {
  const std::pair<const char*, const char*> cases[] = {
      {"cells = [1e300, 2]", "got 1e+300"}, {"cells = [-1e300, 2]", "got -1e+300"}, {"cells = [4.0, 1e10]", "got 10000000000"}};
  for (const auto& [cells, got] : cases) {
    const std::string msg = error_of(variant("cells = [4, 2]", cells));
    EXPECT_NE(msg.find(std::string("expected between 1 and 100000 cells per direction, ") + got), std::string::npos)
        << cells << "\n" << msg;
  }
}

// fuzz_gmsh_msh: Gmsh 4.8.4 crashes (SIGSEGV in GModel::setPhysicalName; the
// gmsh program too) on a physical name of dimension 4 (found by the fuzzer,
// then reduced); the program died with it. Gmsh now runs in a child process,
// and its crash is an error.
TEST(FuzzRegressions, GmshCrashOnMalformedMshIsAnError) {
  const fs::path file = temp_file("crash.msh", R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
4 3 "body")");
  const std::string msg = read_error(file);
  EXPECT_NE(msg.find("crash.msh: Gmsh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("the file is probably malformed"), std::string::npos) << msg;
  // The same through a case file, with the key that names the mesh.
  const std::string case_msg =
      error_of(variant("generator = \"rectangle\"\nlower = [0.0, 0.0]\nupper = [2.0, 1.0]\ncells = [4, 2]",
                       "file = \"" + file.string() + "\""));
  EXPECT_NE(case_msg.find("fuzz.toml:2:8: mesh.file: "), std::string::npos) << case_msg;
}

// fuzz_gmsh_msh: a 58-byte MSH 4.1 $Nodes header (9 blocks, 999994121 nodes,
// tags 1 to 0) makes Gmsh 4.8.4 take 15 GB and a minute before it gives up (the
// gmsh program too). Gmsh now reads a .msh file with a memory budget (4 GiB, or
// 100 times the file's size), and this is an error at once.
TEST(FuzzRegressions, GmshMemoryBlowUpIsBounded) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "no memory budget under AddressSanitizer (it reserves terabytes of address space)";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "no memory budget under AddressSanitizer (it reserves terabytes of address space)";
#endif
#endif
  const auto start = std::chrono::steady_clock::now();
  const fs::path file = temp_file("huge.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n9 999994121 1 0 ");
  const std::string msg = read_error(file);
  EXPECT_NE(msg.find("huge.msh: Gmsh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("the file is probably malformed"), std::string::npos) << msg;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
}

bool exit_is_a_failure = false;

// Gmsh ends the process for `Exit;` in a .geo script (found while reviewing the
// Gmsh reader for fuzzing; .geo files are not fuzzed, since they can run
// commands). It ended this test's process with status 0: a pass for CTest,
// unless the exit handler below turns it into a failure.
TEST(FuzzRegressions, GeoExitDoesNotEndTheProgram) {
  exit_is_a_failure = true;
  std::atexit([] {
    if (exit_is_a_failure) {
      std::fputs("FuzzRegressions.GeoExitDoesNotEndTheProgram: the process exited during the test\n", stderr);
      std::_Exit(1);
    }
  });
  const fs::path file = temp_file("exit.geo", "Point(1) = {0, 0, 0, 1};\nExit;\n");
  const std::string msg = read_error(file);
  exit_is_a_failure = false;
  EXPECT_NE(msg.find("exit.geo: Gmsh ended the program while reading the file (does the .geo file call Exit?)"),
            std::string::npos)
      << msg;
}

// fuzz_case_file (toml++ 3.3): "[" followed by a character that cannot start a
// key trips an assertion in toml++'s debug mode (marzer/tomlplusplus#301); the
// release mode used here reports it.
TEST(FuzzRegressions, TableHeaderWithoutKeyIsInvalidToml) {
  for (const char* text : {"[=]\n", "[[=]]\n", "[\x01]\n", "[[[a]]]\n"})
    EXPECT_NE(error_of(text).find("invalid TOML"), std::string::npos) << text;
}

std::string utf8(char32_t c) {
  std::string s;
  if (c < 0x80) {
    s += static_cast<char>(c);
  } else if (c < 0x800) {
    s += static_cast<char>(0xC0 | (c >> 6));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    s += static_cast<char>(0xE0 | (c >> 12));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  }
  return s;
}

// fuzz_case_file (toml++ 3.3, not fixable here): asked whether a non-ASCII
// character is whitespace, toml++ reaches __builtin_unreachable() for the code
// points of three ranges (marzer/tomlplusplus#190, #295). This checks every one
// of them where TOML allows only whitespace (the case file is invalid) and
// after a line-ending backslash in a multi-line string (valid): the build must
// report the character, or read the string, and never crash.
TEST(FuzzRegressions, NonAsciiWhereTomlExpectsWhitespace) {
  const std::pair<char32_t, char32_t> ranges[] = {{0xA0, 0x499}, {0x2C5E, 0x3057}, {0xFB26, 0xFEFF}};
  int checked = 0;
  for (const auto& [first, last] : ranges)
    for (char32_t c = first; c <= last; ++c) {
      const std::string ch = utf8(c);
      const std::string msg = error_of("a" + ch + " = 1\n");
      ASSERT_NE(msg.find("invalid TOML"), std::string::npos) << std::hex << static_cast<int>(c) << ": " << msg;
      const bool space = c == 0xA0 || c == 0x3000 || c == 0xFEFF;  // Unicode spaces toml++ skips here
      ASSERT_EQ(case_description("[case]\ndescription = \"\"\"\\\n" + ch + "x\"\"\"\n"), (space ? "" : ch) + "x")
          << std::hex << static_cast<int>(c);
      ++checked;
    }
  EXPECT_EQ(checked, 1018 + 1018 + 986);
}

}  // namespace
}  // namespace vpc
