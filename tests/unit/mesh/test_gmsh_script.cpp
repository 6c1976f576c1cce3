// The .geo scanner (issue 26 item 14): commands that run programs or write files
// are found where Gmsh's lexer would see them, and nowhere else.
#include "mesh/gmsh_script.hpp"

#include "core/error.hpp"
#include "mesh/gmsh_reader.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace vpc {
namespace {

namespace fs = std::filesystem;

std::optional<GmshScriptCommand> scan(const std::string& text, const fs::path& dir = ".") {
  return find_unsafe_command(text, "t.geo", dir);
}

/// "LINE:COLUMN COMMAND" of the first unsafe command, or "none".
std::string first(const std::string& text, const fs::path& dir = ".") {
  const auto c = scan(text, dir);
  return c ? std::to_string(c->line) + ":" + std::to_string(c->column) + " " + c->command : "none";
}

fs::path temp_dir() {
  const fs::path dir = fs::temp_directory_path() / ("vpc_gmsh_script_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

const char* kSquare = R"(Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5};
Point(3) = {1, 1, 0, 0.5}; Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve("contact") = {1};
Physical Surface("body") = {1};
)";

TEST(GmshScript, CommandsThatReachOutsideAreFound) {
  EXPECT_EQ(first("SystemCall \"touch x\";"), "1:1 SystemCall");
  EXPECT_EQ(first("SystemCall\"touch x\";"), "1:1 SystemCall");  // no space
  EXPECT_EQ(first("Point(1) = {0,0,0};\n  NonBlockingSystemCall 'x';"), "2:3 NonBlockingSystemCall");
  EXPECT_EQ(first("System \"x\";"), "1:1 System");
  EXPECT_EQ(first("OnelabRun(\"a\", \"b\");"), "1:1 OnelabRun");
  EXPECT_EQ(first("Save \"out.msh\";"), "1:1 Save");
  EXPECT_EQ(first("Save View[0] \"v.pos\";"), "1:1 Save");
  EXPECT_EQ(first("Print \"a.png\";"), "1:1 Print");
  EXPECT_EQ(first("CreateDir \"d\";"), "1:1 CreateDir");
  EXPECT_EQ(first("DeleteFile \"d\";"), "1:1 DeleteFile");
  EXPECT_EQ(first("RenameFile \"a\", \"b\";"), "1:1 RenameFile");
  EXPECT_EQ(first("Printf(\"%g\", 1) > \"f.txt\";"), "1:1 Printf ... >");
  EXPECT_EQ(first("Printf(\"%g\", (1+2)) >> \"f.txt\";"), "1:1 Printf ... >");
  EXPECT_EQ(first("Plugin(HomologyComputation).Run;"), "1:1 Plugin(HomologyComputation).Run");
  EXPECT_EQ(first("If (1)\nSystemCall \"x\";\nEndIf"), "2:1 SystemCall");
  EXPECT_EQ(first("Macro m\nSystemCall \"x\";\nReturn"), "2:1 SystemCall");
  EXPECT_EQ(first("x = 2;SystemCall \"x\";"), "1:7 SystemCall");
  EXPECT_EQ(first("/* c */ 2SystemCall \"x\";"), "1:10 SystemCall");  // Gmsh's lexer: 2, then the name
  EXPECT_EQ(first("// line\n/* a\n b */ SystemCall \"x\";"), "3:7 SystemCall");
  EXPECT_EQ(first("s = \"a\"; SystemCall s;"), "1:10 SystemCall");
  EXPECT_EQ(first("Include StrCat(CurrentDir, \"a.geo\");"), "1:1 Include");
  EXPECT_EQ(first("Merge s;"), "1:1 Merge");
}

TEST(GmshScript, CommentsStringsOptionsAndOtherNamesAreFine) {
  EXPECT_EQ(first(kSquare), "none");
  EXPECT_EQ(first("// SystemCall \"x\";\nPoint(1) = {0,0,0};"), "none");
  EXPECT_EQ(first("/* SystemCall \"x\";\n Save \"y\"; */"), "none");
  EXPECT_EQ(first("Physical Curve(\"SystemCall x; Save\") = {1};"), "none");
  EXPECT_EQ(first("Physical Curve('Print') = {1};"), "none");
  EXPECT_EQ(first("systemcall \"x\";"), "none");  // Gmsh's keywords are case sensitive: an unknown command
  EXPECT_EQ(first("SystemCalls = 2; MySave = 1; Saved = 3;"), "none");
  EXPECT_EQ(first("Print.Width = 100; General.Save = 0; Mesh.SaveAll = 1;"), "none");
  EXPECT_EQ(first("Printf(\"n = %g\", 3);"), "none");                  // to the terminal
  EXPECT_EQ(first("Printf(\"a > b\");"), "none");                      // '>' in the string
  EXPECT_EQ(first("Printf(\"%g\", 2 > 1);"), "none");                  // inside the parentheses
  EXPECT_EQ(first("Plugin(Crack).Dimension = 1;"), "none");            // an option, not an action
  EXPECT_EQ(first("Merge \"body.step\"; ShapeFromFile(\"b.brep\");"), "none");  // CAD data
  EXPECT_EQ(first("s = \"unterminated"), "none");
  EXPECT_EQ(first("/* unterminated SystemCall"), "none");
}

TEST(GmshScript, IncludedScriptsAreScanned) {
  const fs::path dir = temp_dir();
  std::ofstream(dir / "safe.geo") << kSquare;
  std::ofstream(dir / "bad.geo") << "// a comment\n\nSave \"x.msh\";\n";
  std::ofstream(dir / "self.geo") << "Include \"self.geo\";\n";
  EXPECT_EQ(first("Include \"safe.geo\";", dir), "none");
  const auto c = scan("Include \"bad.geo\";", dir);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->file, (dir / "bad.geo").string());
  EXPECT_EQ(c->line, 3);
  EXPECT_EQ(c->command, "Save");
  EXPECT_EQ(first("Merge \"bad.geo\";", dir), "3:1 Save");  // Merge of a script runs it
  EXPECT_EQ(first("Include \"self.geo\";", dir), "1:1 Include");
  // Gmsh 4.8 uncompresses a .gz with a shell command made from its name; a FIFO would block.
  std::ofstream(dir / "a.geo.gz") << "x";
  EXPECT_EQ(first("Merge \"a.geo.gz\";", dir), "1:1 Merge");
  fs::remove(dir / "fifo.geo");
  ASSERT_EQ(::mkfifo((dir / "fifo.geo").c_str(), 0600), 0);
  EXPECT_EQ(first("Include \"fifo.geo\";", dir), "1:1 Include");
  EXPECT_EQ(first("Include \"missing.geo\";", dir), "none");  // Gmsh reports it
  EXPECT_TRUE(is_gmsh_script("a.geo"));
  EXPECT_TRUE(is_gmsh_script("a.pos"));
  EXPECT_FALSE(is_gmsh_script("a.MSH"));
  EXPECT_FALSE(is_gmsh_script("a.step"));
}

/// The reporter's case: the script's command does not run, and the message names
/// the file, line and command; the case's opt-in runs it.
TEST(GmshScript, ReaderRefusesUntrustedScripts) {
  const fs::path dir = temp_dir() / "reader";
  fs::create_directories(dir);
  const fs::path marker = dir / "INJECTED_BY_GEO";
  fs::remove(marker);
  const fs::path file = dir / "syscall.geo";
  std::ofstream(file) << "SystemCall \"touch " << marker.string() << "\";\n" << kSquare;
  std::string what;
  try {
    read_gmsh(file);
  } catch (const Error& e) {
    what = e.what();
  }
  EXPECT_NE(what.find(file.string() + ":1:1: 'SystemCall' runs a shell command; vpcontact does not run a .geo"),
            std::string::npos)
      << what;
  EXPECT_FALSE(fs::exists(marker));
  std::ofstream(dir / "body.msh.gz") << "x";  // gunzip -c NAME: a shell command
  try {
    read_gmsh(dir / "body.msh.gz");
    ADD_FAILURE() << "a .gz was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("body.msh.gz: Gmsh reads a compressed file, which Gmsh uncompresses with a "
                                         "shell command"),
              std::string::npos)
        << e.what();
  }
  GmshOptions trusted;
  trusted.trust_script = true;
  EXPECT_EQ(read_gmsh(file, trusted).n_cells() > 0, true);
  EXPECT_TRUE(fs::exists(marker));
}

}  // namespace
}  // namespace vpc
