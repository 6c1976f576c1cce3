#include "mesh/gmsh_script.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

namespace vpc {

namespace {

namespace fs = std::filesystem;

/// Includes nested deeper are refused (a script that includes itself would never end).
constexpr int kMaxIncludeDepth = 16;

/// Scripts larger are refused rather than read (no real geometry comes near).
constexpr std::uintmax_t kMaxScriptBytes = std::uintmax_t{256} << 20;

/// Why Gmsh's reading of `file` cannot be checked, or empty: Gmsh 4.8 uncompresses a .gz
/// file with a shell command built from its name ("gunzip -c NAME > ..."), then runs it;
/// a FIFO or device would block the scan (and Gmsh).
std::string unscannable(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".gz")
    return "reads a compressed file, which Gmsh uncompresses with a shell command (uncompress it first)";
  std::error_code ec;
  const auto status = fs::status(file, ec);
  if (ec || !fs::exists(status)) return {};  // Gmsh reports a missing file
  if (!fs::is_regular_file(status)) return "reads a file that is not a regular file";
  if (fs::file_size(file, ec) > kMaxScriptBytes) return "reads a script larger than 256 MiB, which vpcontact does not scan";
  return {};
}

struct Token {
  enum Kind { Name, String, Number, Punct } kind;
  std::string text;  // a string's contents without its quotes; a punctuation's one character
  int line, column;
};

bool is_alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

/// The tokens of `text` as Gmsh's lexer (Gmsh.l) sees them: comments dropped,
/// strings end at the next same quote (no escapes), names are [A-Za-z_][A-Za-z_0-9]*.
/// An unterminated comment or string ends the text (Gmsh reports it).
std::vector<Token> tokens(std::string_view text) {
  std::vector<Token> out;
  int line = 1;
  std::size_t line_start = 0;
  const std::size_t n = text.size();
  auto advance_lines = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to; ++k)
      if (text[k] == '\n') {
        ++line;
        line_start = k + 1;
      }
  };
  for (std::size_t i = 0; i < n;) {
    const char c = text[i];
    const int column = static_cast<int>(i - line_start) + 1;
    if (c == '/' && i + 1 < n && text[i + 1] == '/') {
      const std::size_t end = text.find('\n', i);
      i = end == std::string_view::npos ? n : end;
    } else if (c == '/' && i + 1 < n && text[i + 1] == '*') {
      const std::size_t end = text.find("*/", i + 2);
      const std::size_t stop = end == std::string_view::npos ? n : end + 2;
      advance_lines(i, stop);
      i = stop;
    } else if (c == '"' || c == '\'') {
      const std::size_t end = text.find(c, i + 1);
      const std::size_t stop = end == std::string_view::npos ? n : end;
      out.push_back({Token::String, std::string(text.substr(i + 1, stop - i - 1)), line, column});
      advance_lines(i, stop);
      i = stop == n ? n : stop + 1;
    } else if (is_alpha(c)) {
      std::size_t j = i + 1;
      while (j < n && (is_alpha(text[j]) || is_digit(text[j]))) ++j;
      out.push_back({Token::Name, std::string(text.substr(i, j - i)), line, column});
      i = j;
    } else if (is_digit(c) || (c == '.' && i + 1 < n && is_digit(text[i + 1]))) {
      std::size_t j = i;
      while (j < n && (is_digit(text[j]) || text[j] == '.')) ++j;
      if (j < n && (text[j] == 'e' || text[j] == 'E')) {  // an exponent only if digits follow
        std::size_t k = j + 1;
        if (k < n && (text[k] == '+' || text[k] == '-')) ++k;
        if (k < n && is_digit(text[k])) {
          j = k;
          while (j < n && is_digit(text[j])) ++j;
        }
      }
      out.push_back({Token::Number, std::string(text.substr(i, j - i)), line, column});
      i = j;
    } else {
      if (c == '\n') {
        ++line;
        line_start = i + 1;
      } else if (!std::isspace(static_cast<unsigned char>(c))) {
        out.push_back({Token::Punct, std::string(1, c), line, column});
      }
      ++i;
    }
  }
  return out;
}

/// Commands that reach outside the model whatever their arguments (Gmsh 4.8's
/// grammar, Gmsh.y, and later versions' DeleteFile and RenameFile).
const char* always_refused(const std::string& name) {
  static const std::array<std::pair<const char*, const char*>, 9> table = {{
      {"SystemCall", "runs a shell command"},
      {"System", "runs a shell command"},
      {"NonBlockingSystemCall", "runs a shell command"},
      {"OnelabRun", "runs a program (an ONELAB client)"},
      {"Save", "writes a file"},
      {"Print", "writes a file"},
      {"CreateDir", "creates a directory"},
      {"DeleteFile", "deletes a file"},
      {"RenameFile", "renames a file"},
  }};
  for (const auto& [command, what] : table)
    if (name == command) return what;
  return nullptr;
}

class Scanner {
 public:
  Scanner(std::string_view text, std::string name, fs::path dir, int depth)
      : t_(tokens(text)), name_(std::move(name)), dir_(std::move(dir)), depth_(depth) {}

  std::optional<GmshScriptCommand> run() {
    for (std::size_t i = 0; i < t_.size(); ++i) {
      if (t_[i].kind != Token::Name || punct(i - 1, '.') || punct(i + 1, '.')) continue;  // an option: Print.Width
      const std::string& name = t_[i].text;
      if (const char* what = always_refused(name)) return found(i, name, what);
      if (name == "Printf" && writes_to_file(i)) return found(i, "Printf ... >", "writes a file");
      if (name == "Plugin" && runs_plugin(i))
        return found(i, "Plugin(" + t_[i + 2].text + ")." + t_[i + 5].text,
                     "runs a Gmsh plugin (plugins act on files and views; HomologyComputation writes a file)");
      if (name == "Include" || name == "Merge" || name == "MergeWithBoundingBox")
        if (auto c = included(i)) return c;
    }
    return std::nullopt;
  }

 private:
  bool punct(std::size_t i, char c) const {
    return i < t_.size() && t_[i].kind == Token::Punct && t_[i].text[0] == c;  // i = -1 wraps: false
  }

  GmshScriptCommand found(std::size_t i, std::string command, std::string what) const {
    return {name_, t_[i].line, t_[i].column, std::move(command), std::move(what)};
  }

  /// Printf(...) > "file" or >> "file": a '>' after the closing parenthesis.
  bool writes_to_file(std::size_t i) const {
    if (!punct(i + 1, '(')) return false;
    int level = 0;
    for (std::size_t j = i + 1; j < t_.size(); ++j) {
      if (punct(j, '(')) ++level;
      if (punct(j, ')') && --level == 0) return punct(j + 1, '>');
      if (punct(j, ';')) return false;
    }
    return false;
  }

  /// Plugin(Name).Action; (an action, not an option `Plugin(Name).Option = value;`).
  bool runs_plugin(std::size_t i) const {
    return punct(i + 1, '(') && i + 5 < t_.size() && t_[i + 2].kind == Token::Name && punct(i + 3, ')') &&
           punct(i + 4, '.') && t_[i + 5].kind == Token::Name && !punct(i + 6, '=') && !punct(i + 6, '(');
  }

  /// Include "file"; or Merge "file";: the file is scanned if Gmsh reads it as a
  /// script; a name computed at run time (StrCat, a variable) cannot be.
  std::optional<GmshScriptCommand> included(std::size_t i) const {
    const std::string& name = t_[i].text;
    if (!(i + 2 < t_.size() && t_[i + 1].kind == Token::String && punct(i + 2, ';')))
      return found(i, name,
                   "reads a file named by an expression, which vpcontact cannot check for commands (name the "
                   "file by a literal string)");
    const fs::path file = fs::path(t_[i + 1].text).is_absolute() ? fs::path(t_[i + 1].text) : dir_ / t_[i + 1].text;
    if (const std::string why = unscannable(file); !why.empty()) return found(i, name, why);
    if (!is_gmsh_script(file)) return std::nullopt;  // a mesh or CAD file: data
    if (depth_ >= kMaxIncludeDepth)
      return found(i, name, fmt::format("nests scripts more than {} deep (does a file include itself?)", kMaxIncludeDepth));
    return find_unsafe_command(file, depth_ + 1);
  }

  std::vector<Token> t_;
  std::string name_;
  fs::path dir_;
  int depth_;
};

}  // namespace

bool is_gmsh_script(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const std::array<const char*, 24> data = {".msh",  ".msh2", ".msh4", ".step", ".stp", ".brep",
                                                   ".brp",  ".xao",  ".iges", ".igs",  ".stl", ".unv",
                                                   ".vtk",  ".mesh", ".bdf",  ".nas",  ".med", ".mail",
                                                   ".diff", ".p3d",  ".ply2", ".off",  ".cgns", ".inp"};
  return std::none_of(data.begin(), data.end(), [&](const char* e) { return ext == e; });
}

std::optional<GmshScriptCommand> find_unsafe_command(std::string_view text, const std::string& name,
                                                     const fs::path& dir, int depth) {
  return Scanner(text, name, dir, depth).run();
}

std::optional<GmshScriptCommand> find_unsafe_command(const fs::path& file, int depth) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  return find_unsafe_command(ss.str(), file.string(), file.parent_path(), depth);
}

void check_gmsh_script(const fs::path& file, const std::string& opt_in) {
  if (const std::string why = unscannable(file); !why.empty())
    fail("{}: Gmsh {}; vpcontact does not read such a file ({} allows it, for a file you trust)", file.string(), why,
         opt_in);
  if (!is_gmsh_script(file)) return;
  if (const auto c = find_unsafe_command(file))
    fail("{}:{}:{}: '{}' {}; vpcontact does not run a .geo script that runs programs or writes files ({} "
         "allows it, for a file you trust)",
         c->file, c->line, c->column, c->command, c->what, opt_in);
}

}  // namespace vpc
