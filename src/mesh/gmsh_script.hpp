#pragma once
// What a Gmsh script (.geo) may do before vpcontact runs it (issue 26 item 14).
// Gmsh's language can run shell commands (SystemCall), start programs
// (OnelabRun) and write, create or delete files (Save, Print, Printf > file,
// CreateDir, DeleteFile, RenameFile, plugins); a case and geometry received from
// someone else must not. The scanner reads the script as Gmsh's lexer does
// (// and /* */ comments, "..." and '...' strings without escapes, case-sensitive
// keywords) and follows Include and Merge of scripts named by a literal string.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace vpc {

/// A command of a script that reaches outside the model.
struct GmshScriptCommand {
  std::string file;     // the script that holds it (an included one, perhaps)
  int line = 0, column = 0;
  std::string command;  // "SystemCall", "Printf ... >", "Include"
  std::string what;     // "runs a shell command"
};

/// Whether Gmsh reads `file` as a script: its extension is none of the mesh and
/// CAD formats that Gmsh reads as data (.msh, .step, .brep, .stl, ...).
bool is_gmsh_script(const std::filesystem::path& file);

/// The first command of the script `text` (named `name` in the result; its
/// Includes are resolved against `dir`) that runs a program or writes, creates or
/// deletes a file, or includes a file by a name computed at run time (which
/// cannot be scanned); nothing if there is none. `depth`: of nested includes.
std::optional<GmshScriptCommand> find_unsafe_command(std::string_view text, const std::string& name,
                                                     const std::filesystem::path& dir, int depth = 0);

/// The same for the script in `file` (nothing if it cannot be read: Gmsh reports that).
std::optional<GmshScriptCommand> find_unsafe_command(const std::filesystem::path& file, int depth = 0);

/// Throws vpc::Error "FILE:LINE:COLUMN: COMMAND WHAT; ..." for such a command in the
/// script `file` (see find_unsafe_command); `opt_in` names how a case allows it.
void check_gmsh_script(const std::filesystem::path& file, const std::string& opt_in);

}  // namespace vpc
