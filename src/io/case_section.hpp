#pragma once
// The case file's reading machinery, shared by every section's reader (io/case_readers.hpp):
// a Section is one table of the file with typed accessors whose errors name the file, line,
// column and key path (or the command-line option that set the key), and "did you mean" for
// unknown keys and values. Internal to io/: the rest of the program sees io/case_file.hpp.
#include "core/expression.hpp"

#include <toml++/toml.h>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace vpc::case_file {

/// "; did you mean 'x'?" for the nearest of `known` (by edit distance), or "".
std::string did_you_mean(const std::string& key, const std::set<std::string>& known);

/// "a table", "a string", "an integer", ...: what a node is, for messages.
const char* type_name(const toml::node& n);

/// Location of a node: "file:line:column".
std::string location(const toml::node& n, const std::string& file);

/// The value of a number node (integer or float). toml++'s value<double>() is
/// empty for an integer that a double cannot hold exactly (beyond 2^53).
double number_value(const toml::node& n);

/// Where a case's values come from: its file, and the command-line option behind
/// each key that an override set (such a value has no line in the file).
struct Origins {
  std::string file;
  std::map<std::string, std::string> of_key;  // key path -> "--kappa -1", "--set damage.kappa=-1"
  toml::table replaced_grid;  // the file's [time] steps or dt that a tolerance override replaced (read_output)
  /// The formulas whose values reach the state (Problem::formulas), as they are read.
  std::shared_ptr<std::vector<std::shared_ptr<const Expression>>> formulas =
      std::make_shared<std::vector<std::shared_ptr<const Expression>>>();

  std::string of(const std::string& key_path) const {
    const auto it = of_key.find(key_path);
    return it == of_key.end() ? "--set " + key_path : it->second;
  }
};

/// One table of the case file. Every key asked for (present or not) is known;
/// finish() rejects keys nobody asked for.
class Section {
 public:
  Section(const toml::table* t, std::string path, const Origins& origins)
      : t_(t), path_(std::move(path)), origins_(origins), file_(origins.file) {}

  bool exists() const { return t_ != nullptr; }
  const std::string& path() const { return path_; }
  const Origins& origins() const { return origins_; }
  std::string key_path(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }

  const toml::node* get(const std::string& k) {
    known_.insert(k);
    return t_ ? t_->get(k) : nullptr;
  }
  bool has(const std::string& k) { return get(k) != nullptr; }

  /// "file:line:col: key" for a present key, "file: [section] key" otherwise.
  std::string where(const std::string& k);
  std::string where_section() const;

  [[noreturn]] void expected(const std::string& k, const std::string& what);

  double number(const std::string& k);
  double number(const std::string& k, double fallback) { return has(k) ? number(k) : fallback; }
  double positive(const std::string& k, double fallback);
  int integer(const std::string& k);
  int integer(const std::string& k, int fallback) { return has(k) ? integer(k) : fallback; }
  std::string string(const std::string& k);
  std::string string(const std::string& k, const std::string& fallback) { return has(k) ? string(k) : fallback; }
  std::string choice(const std::string& k, const std::vector<std::string>& options, const std::string& fallback = "");
  bool boolean(const std::string& k, bool fallback);
  const toml::array& array(const std::string& k, const std::string& what);
  std::vector<std::string> strings(const std::string& k);
  std::vector<double> numbers(const std::string& k, size_t size);
  /// A formula: a string, or a plain number.
  std::shared_ptr<const Expression> expression(const std::string& k, Expression::Kind kind);
  /// A formula whose values reach the state: checked at every step (check_formulas).
  std::shared_ptr<const Expression> state_expression(const std::string& k, Expression::Kind kind);
  std::vector<std::shared_ptr<const Expression>> state_expressions(const std::string& k, int d, Expression::Kind kind);
  /// An array of d formulas (strings or numbers).
  std::vector<std::shared_ptr<const Expression>> expressions(const std::string& k, int d, Expression::Kind kind);

  Section table(const std::string& k);

  /// Keys present but never asked for are errors.
  void finish() const;
  /// The keys present that were not asked for (law parameters).
  std::vector<std::string> remaining() const;
  const std::set<std::string>& known() const { return known_; }

 private:
  const toml::table* t_;
  std::string path_;
  const Origins& origins_;
  const std::string& file_;
  std::set<std::string> known_;
};

}  // namespace vpc::case_file
