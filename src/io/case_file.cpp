#include "io/case_file.hpp"
#include "io/state_fields.hpp"

#include "contact/registry.hpp"
#include "core/error.hpp"
#include "core/expression.hpp"
#include "core/quote.hpp"
#include "la/memory_estimate.hpp"
#include "material/sources/expression_source.hpp"
#include "mesh/generators.hpp"
#include "mesh/mesh_block.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_extent.hpp"
#include "mesh/refine.hpp"

#include <fmt/ranges.h>
#include <toml++/toml.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

namespace vpc {

namespace {

namespace fs = std::filesystem;

/// Edit distance, for "did you mean".
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t prev = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cur = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, prev + (a[i - 1] == b[j - 1] ? 0 : 1)});
      prev = cur;
    }
  }
  return row[b.size()];
}

std::string did_you_mean(const std::string& key, const std::set<std::string>& known) {
  std::string best;
  size_t best_d = std::max<size_t>(2, key.size() / 3) + 1;
  for (const auto& k : known) {
    const size_t d = edit_distance(key, k);
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  return best.empty() ? "" : fmt::format("; did you mean '{}'?", best);
}

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    default: return "a date/time";
  }
}

/// Location of a node: "file:line:column".
std::string location(const toml::node& n, const std::string& file) {
  const auto& src = n.source();
  if (src.begin.line == 0) return "command line (--set)";  // a value given by --set
  const std::string path = src.path ? *src.path : file;
  return fmt::format("{}:{}:{}", path, src.begin.line, src.begin.column);
}

/// The value of a number node (integer or float). toml++'s value<double>() is
/// empty for an integer that a double cannot hold exactly (beyond 2^53).
double number_value(const toml::node& n) {
  if (n.is_integer()) return static_cast<double>(*n.value_exact<int64_t>());
  return *n.value_exact<double>();
}

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
  std::string where(const std::string& k) {
    const toml::node* n = get(k);
    if (n && n->source().begin.line == 0) return origins_.of(key_path(k));
    if (n) return fmt::format("{}: {}", location(*n, file_), printable(key_path(k)));
    return where_section() + ": " + printable(key_path(k));
  }
  std::string where_section() const {
    if (t_ && t_->source().begin.line > 0) return location(*t_, file_);
    return file_;
  }

  [[noreturn]] void expected(const std::string& k, const std::string& what) {
    const toml::node* n = get(k);
    if (!n) fail("{}: missing key '{}': expected {}", where_section(), key_path(k), what);
    fail("{}: expected {}, got {}", where(k), what, type_name(*n));
  }

  double number(const std::string& k) {
    const toml::node* n = get(k);
    if (!n || !n->is_number()) expected(k, "a number");
    const double v = number_value(*n);
    if (!std::isfinite(v)) fail("{}: expected a finite number, got {}", where(k), v);
    return v;
  }
  double number(const std::string& k, double fallback) { return has(k) ? number(k) : fallback; }
  double positive(const std::string& k, double fallback) {
    const double v = number(k, fallback);
    if (!(v > 0)) fail("{}: expected a number > 0, got {}", where(k), v);
    return v;
  }
  int integer(const std::string& k) {
    const toml::node* n = get(k);
    if (!n || !n->is_integer()) expected(k, "an integer");
    const int64_t v = *n->value<int64_t>();
    if (v < -(1 << 30) || v > (1 << 30))
      fail("{}: expected an integer between -{} and {}, got {}", where(k), 1 << 30, 1 << 30, v);
    return static_cast<int>(v);
  }
  int integer(const std::string& k, int fallback) { return has(k) ? integer(k) : fallback; }
  std::string string(const std::string& k) {
    const toml::node* n = get(k);
    if (!n || !n->is_string()) expected(k, "a string");
    return *n->value<std::string>();
  }
  std::string string(const std::string& k, const std::string& fallback) { return has(k) ? string(k) : fallback; }
  std::string choice(const std::string& k, const std::vector<std::string>& options, const std::string& fallback = "") {
    if (!has(k) && !fallback.empty()) return fallback;
    const std::string v = string(k);
    if (std::find(options.begin(), options.end(), v) == options.end()) {
      const std::set<std::string> known(options.begin(), options.end());
      fail("{}: unknown value {}; expected one of: {}{}", where(k), quote(v), fmt::join(options, ", "), did_you_mean(v, known));
    }
    return v;
  }
  bool boolean(const std::string& k, bool fallback) {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (!n->is_boolean()) expected(k, "true or false");
    return *n->value<bool>();
  }
  const toml::array& array(const std::string& k, const std::string& what) {
    const toml::node* n = get(k);
    if (!n || !n->is_array()) expected(k, what);
    return *n->as_array();
  }
  std::vector<std::string> strings(const std::string& k) {
    const toml::node* n = get(k);
    if (n && n->is_string()) return {*n->value<std::string>()};
    std::vector<std::string> out;
    for (const auto& e : array(k, "a string or an array of strings")) {
      if (!e.is_string()) fail("{}: expected an array of strings, got an element that is {}", where(k), type_name(e));
      out.push_back(*e.value<std::string>());
    }
    return out;
  }
  std::vector<double> numbers(const std::string& k, size_t size) {
    const toml::node* n = get(k);
    if (n && n->is_number() && size == 1) return {number(k)};
    std::vector<double> out;
    const auto& a = array(k, fmt::format("an array of {} numbers", size));
    for (const auto& e : a) {
      if (!e.is_number()) fail("{}: expected an array of numbers, got an element that is {}", where(k), type_name(e));
      out.push_back(number_value(e));
      if (!std::isfinite(out.back())) fail("{}: expected an array of finite numbers, got {}", where(k), out.back());
    }
    if (size > 0 && out.size() != size)
      fail("{}: expected an array of {} numbers (one per space dimension), got {}", where(k), size, out.size());
    return out;
  }
  /// A formula: a string, or a plain number.
  std::shared_ptr<const Expression> expression(const std::string& k, Expression::Kind kind) {
    const toml::node* n = get(k);
    if (n && n->is_number()) return std::make_shared<Expression>(fmt::format("{:.17g}", number(k)), kind, where(k));
    if (!n || !n->is_string()) expected(k, "a formula (a string such as \"-10*t\") or a number");
    return std::make_shared<Expression>(*n->value<std::string>(), kind, where(k));
  }
  /// A formula whose values reach the state: checked at every step (check_formulas).
  std::shared_ptr<const Expression> state_expression(const std::string& k, Expression::Kind kind) {
    auto e = expression(k, kind);
    origins_.formulas->push_back(e);
    return e;
  }
  std::vector<std::shared_ptr<const Expression>> state_expressions(const std::string& k, int d, Expression::Kind kind) {
    auto e = expressions(k, d, kind);
    origins_.formulas->insert(origins_.formulas->end(), e.begin(), e.end());
    return e;
  }
  /// An array of d formulas (strings or numbers).
  std::vector<std::shared_ptr<const Expression>> expressions(const std::string& k, int d, Expression::Kind kind) {
    const auto& a = array(k, fmt::format("an array of {} formulas (one per component)", d));
    if (static_cast<int>(a.size()) != d)
      fail("{}: expected an array of {} formulas (one per component), got {}", where(k), d, a.size());
    std::vector<std::shared_ptr<const Expression>> out;
    for (size_t i = 0; i < a.size(); ++i) {
      const toml::node& e = a[i];
      const std::string w = fmt::format("{}: {}[{}]", location(e, file_), key_path(k), i);
      if (e.is_number()) {
        const double v = number_value(e);
        if (!std::isfinite(v)) fail("{}: expected a finite number, got {}", w, v);
        out.push_back(std::make_shared<Expression>(fmt::format("{:.17g}", v), kind, w));
      } else if (e.is_string()) {
        out.push_back(std::make_shared<Expression>(*e.value<std::string>(), kind, w));
      } else {
        fail("{}: expected a formula or a number, got {}", w, type_name(e));
      }
    }
    return out;
  }

  Section table(const std::string& k) {
    const toml::node* n = get(k);
    if (n && !n->is_table()) expected(k, "a table");
    return Section(n ? n->as_table() : nullptr, key_path(k), origins_);
  }

  /// Keys present but never asked for are errors.
  void finish() const {
    if (!t_) return;
    for (const auto& [key, node] : *t_) {
      const std::string k(key.str());
      if (known_.count(k)) continue;
      const std::string where = key.source().begin.line > 0
                                    ? fmt::format("{}:{}:{}", key.source().path ? *key.source().path : file_,
                                                  key.source().begin.line, key.source().begin.column)
                                    : origins_.of(key_path(k));  // set by --set
      fail("{}: unknown key {}{}{}", where, quote(k), path_.empty() ? " (a section)" : fmt::format(" in [{}]", path_),
           did_you_mean(k, known_));
    }
  }
  /// The keys present that were not asked for (law parameters).
  std::vector<std::string> remaining() const {
    std::vector<std::string> out;
    if (!t_) return out;
    for (const auto& [key, node] : *t_)
      if (!known_.count(std::string(key.str()))) out.emplace_back(key.str());
    return out;
  }
  const std::set<std::string>& known() const { return known_; }

 private:
  const toml::table* t_;
  std::string path_;
  const Origins& origins_;
  const std::string& file_;
  std::set<std::string> known_;
};


VectorField vector_field(std::vector<std::shared_ptr<const Expression>> e) {
  return [e = std::move(e)](const Point& x, double t) {
    Point v{0, 0, 0};
    for (size_t i = 0; i < e.size(); ++i) v[i] = (*e[i])(x, t);
    return v;
  };
}

// ---------------------------------------------------------------- overrides

/// The keys of [time] that only error-controlled steps (`tolerance`) take.
const std::vector<std::string>& step_control_keys() {
  static const std::vector<std::string> keys = {"dt_initial", "dt_min", "dt_max", "growth", "cut",
                                                "safety", "event_dt", "events", "max_rejections"};
  return keys;
}

/// Keys of one section that exclude each other: an override of a key on one side
/// replaces the keys of the other side that the file gives (the file's `dt` gives
/// way to `--set time.steps=200`).
struct ExclusiveKeys {
  std::string_view section;
  std::vector<std::string_view> a, b;
};

const std::vector<ExclusiveKeys>& exclusive_keys() {
  static const std::vector<ExclusiveKeys> pairs = {
      {"time", {"steps"}, {"dt"}},
      {"time", {"tolerance"}, {"steps", "dt"}},
      {"output", {"every"}, {"times"}},
      {"damage", {"phi"}, {"source"}},
      // A mesh file or a generated mesh; lower, upper and cells alone refine a generated mesh.
      {"mesh", {"file"}, {"generator"}},
  };
  return pairs;
}

/// The keys of `section` that an override of `key` replaces (see exclusive_keys).
std::vector<std::string> replaced_keys(const std::string& section, const std::string& key, const toml::table& t) {
  std::vector<std::string> out;
  for (const auto& e : exclusive_keys()) {
    if (e.section != section) continue;
    const bool in_a = std::find(e.a.begin(), e.a.end(), key) != e.a.end();
    const bool in_b = std::find(e.b.begin(), e.b.end(), key) != e.b.end();
    if (!in_a && !in_b) continue;
    for (auto k : in_a ? e.b : e.a) out.emplace_back(k);
    if (section == "damage" && key == "phi") {  // a formula for phi replaces the source and its parameters
      if (auto src = t["source"].value<std::string>())
        for (const auto& param : damage_source_parameters(*src)) out.push_back(param);
    }
    if (section == "mesh" && key == "file")
      for (auto k : {"lower", "upper", "cells", "diagonal"}) out.emplace_back(k);
    if (section == "mesh" && key == "generator")
      for (auto k : {"size_factor", "trust_geo", "time_limit", "memory_limit"}) out.emplace_back(k);
    if (section == "time" && key != "tolerance")  // a fixed grid replaces the step control's keys
      for (const auto& k : step_control_keys()) out.emplace_back(k);
    if (section == "time" && key == "steps") out.emplace_back("breakpoints");
  }
  return out;
}

/// The parameters that a change of law, damage source or friction law drops: those of the old
/// one that the new one does not take (`--set viscoplasticity.law=elastic` on a
/// Perzyna case drops lambda and sigma_y; `--set contact.friction=tresca` drops mu); also in
/// [[material]] and [[contact.part]] sections.
std::vector<std::string> replaced_parameters(const std::string& section, const std::string& key, const toml::table& t,
                                             const toml::node& value) {
  const std::string last = section.substr(section.rfind('.') + 1);  // "material[0].viscoplasticity": viscoplasticity
  std::vector<std::string> (*parameters)(const std::string&) = nullptr;
  std::string old_name;
  if (last == "viscoplasticity" && key == "law") {
    parameters = viscoplastic_law_parameters;
    old_name = t["law"].value_or(std::string("elastic"));
  } else if (last == "damage" && key == "source") {
    parameters = damage_source_parameters;
    old_name = t["source"].value_or(std::string("zero"));
  } else if ((last == "contact" || last.starts_with("part[") || last.starts_with("pair[")) && key == "friction") {
    // [contact], [[contact.part]], [[contact.pair]]
    parameters = friction_law_keys;
    old_name = t["friction"].value_or(std::string("none"));
  }
  const auto new_name = value.value<std::string>();
  if (!parameters || !new_name || *new_name == old_name) return {};
  const auto kept = parameters(*new_name);
  std::vector<std::string> out;
  for (const auto& p : parameters(old_name))
    if (std::find(kept.begin(), kept.end(), p) == kept.end() && t.contains(p)) out.push_back(p);
  return out;
}

/// One key set from the command line.
struct KeyOverride {
  std::vector<std::string> key;  // its path, e.g. {"time", "steps"}
  std::string value;             // TOML; a bare word is taken as a string
  std::string origin;            // for messages: "--set time.steps=50", "--steps 50"
  bool generated_mesh_only = false;  // --n: refused for a mesh file
  std::string key_path() const { return fmt::format("{}", fmt::join(key, ".")); }
};

/// `--set key.path=value`.
KeyOverride parse_set(const std::string& o) {
  KeyOverride ov{{}, {}, "--set " + printable(o, 200)};
  const auto eq = o.find('=');
  require(eq != std::string::npos && eq > 0, "{}: expected key=value (e.g. damage.kappa=0.1)", ov.origin);
  std::string key = o.substr(0, eq);
  ov.value = o.substr(eq + 1);
  // TOML would take a second line as more keys, which one value cannot hold.
  require(ov.value.find_first_of("\n\r") == std::string::npos,
          "{}: the value holds a line break; give one value, on one line", ov.origin);
  key.erase(key.find_last_not_of(" \t") + 1);
  std::stringstream ss(key);
  for (std::string p; std::getline(ss, p, '.');) {
    require(!p.empty(), "{}: empty part in the key {}", ov.origin, quote(key));
    const auto open = p.find('[');  // obstacle[0]: a table of an array of tables
    require(open == std::string::npos ||
                (open > 0 && p.back() == ']' && p.size() > open + 2 &&
                 p.find_first_not_of("0123456789", open + 1) == p.size() - 1),
            "{}: expected a key part such as obstacle or obstacle[0], got {}", ov.origin, quote(p));
    ov.key.push_back(p);
  }
  require(!ov.key.empty(), "{}: expected key=value (e.g. damage.kappa=0.1)", ov.origin);
  require(ov.key.back().back() != ']', "{}: give a key of the indexed table, e.g. {}.radius", ov.origin,
          printable(ov.key_path()));
  return ov;
}

/// The overrides in the order they apply: --set, then --n, --kappa, --steps, --dt.
std::vector<KeyOverride> key_overrides(const CaseOverrides& o, std::optional<int> cells) {
  std::vector<KeyOverride> out;
  for (const auto& s : o.sets) out.push_back(parse_set(s));
  if (cells) out.push_back({{"mesh", "cells"}, fmt::format("{}", *cells), fmt::format("--n {}", *cells), true});
  // 17 digits: the value that TOML reads back is the option's double.
  if (o.kappa) out.push_back({{"damage", "kappa"}, fmt::format("{:.17g}", *o.kappa), fmt::format("--kappa {}", *o.kappa)});
  if (o.steps) out.push_back({{"time", "steps"}, fmt::format("{}", *o.steps), fmt::format("--steps {}", *o.steps)});
  if (o.time_step)
    out.push_back({{"time", "dt"}, fmt::format("{:.17g}", *o.time_step), fmt::format("--dt {}", *o.time_step)});
  if (o.every) out.push_back({{"output", "every"}, fmt::format("{}", *o.every), fmt::format("--every {}", *o.every)});
  return out;
}

/// The value of an override as a TOML node (in a one-key table).
toml::table override_value(const KeyOverride& ov) {
  try {
    return toml::parse(std::string_view("v = " + ov.value), std::string_view(ov.origin));
  } catch (const toml::parse_error&) {
    toml::table bare;
    bare.insert_or_assign("v", ov.value);  // a bare word: a string
    return bare;
  }
}

/// The table that holds `key` (all its parts but the last), created where
/// missing; `name[i]` is the i-th table of the array of tables [[name]].
toml::table& table_of(toml::table& root, const std::vector<std::string>& key, const std::string& origin) {
  toml::table* t = &root;
  std::string header;  // the array's [[header]]
  for (size_t i = 0; i + 1 < key.size(); ++i) {
    const std::string& part = key[i];
    const auto open = part.find('[');
    const std::string name = part.substr(0, open);
    header += (header.empty() ? "" : ".") + name;
    toml::node* n = t->get(name);
    if (open != std::string::npos) {
      const auto index = std::stoull(part.substr(open + 1, part.size() - open - 2));
      const std::size_t size = n && n->is_array_of_tables() ? n->as_array()->size() : 0;
      require(n == nullptr || n->is_array_of_tables(), "{}: {} is not an array of tables ([[{}]]) in the case file",
              origin, quote(name), printable(header));
      require(index < size, "{}: the case has {} [[{}]] table{}{}", origin, size, printable(header),
              size == 1 ? "" : "s", size == 0   ? ""
              : size == 1 ? fmt::format(" ({}[0])", name)
                          : fmt::format(" ({}[0] to {}[{}])", name, name, size - 1));
      t = (*n->as_array())[index].as_table();
      continue;
    }
    if (!n) {
      t->insert_or_assign(name, toml::table{});
      n = t->get(name);
    }
    require(n->is_table(), "{}: {} is not a table in the case file", origin, quote(name));
    t = n->as_table();
  }
  return *t;
}

/// `--n N` sets the cells per edge of a generated mesh only (a mesh file has no cells to set).
void check_generated_cells(const toml::table& root, const KeyOverride& ov, const std::string& file) {
  const auto mesh_file = root["mesh"]["file"].value<std::string>();
  if (ov.generated_mesh_only && mesh_file)
    fail("{}: --n sets the cells per edge of a generated mesh only; {} reads its mesh from {} (refine that mesh "
         "with --set mesh.refine=k, each level cutting every cell into 2^d, or a .geo's with --set mesh.size_factor=...)", ov.origin, file, quote(*mesh_file));
}

/// Applies the overrides to the parsed table and records their origins. A key that
/// excludes one of the file's (exclusive_keys) replaces it; two overrides that
/// exclude each other are an error.
/// Sets `key` to `value` for the override `ov`. An inline table sets its keys
/// one by one (`--set 'damage={kappa=0.5}'` is `--set damage.kappa=0.5`: the
/// table's other keys stay).
void apply_value(toml::table& root, const KeyOverride& ov, const std::vector<std::string>& key,
                 const toml::node& value, Origins& origins) {
  if (value.is_table()) {
    std::vector<std::string> sub = key;
    sub.emplace_back();
    (void)table_of(root, sub, ov.origin);  // the table exists, even for {}
    for (const auto& [k, v] : *value.as_table()) {
      sub.back() = std::string(k.str());
      apply_value(root, ov, sub, v, origins);
    }
    return;
  }
  toml::table& t = table_of(root, key, ov.origin);
  const std::string section = fmt::format("{}", fmt::join(key.begin(), key.end() - 1, "."));
  const std::string path = fmt::format("{}", fmt::join(key, "."));
  auto replaced = replaced_keys(section, key.back(), t);
  for (const auto& p : replaced_parameters(section, key.back(), t, value)) replaced.push_back(p);
  for (const auto& other : replaced) {
    const std::string full = section + "." + other;
    if (auto it = origins.of_key.find(full); it != origins.of_key.end())
      fail("{}: conflicts with {} (give only one of {} and {})", ov.origin, it->second, printable(path), full);
    if (path == "time.tolerance")  // the fixed grid it replaces: output.every counts its steps (read_output)
      t[other].visit([&](auto&& node) { origins.replaced_grid.insert_or_assign(other, node); });
    t.erase(other);
  }
  origins.of_key[path] = ov.origin;
  value.visit([&](auto&& node) { t.insert_or_assign(key.back(), node); });
}

void apply_overrides(toml::table& root, const std::vector<KeyOverride>& overrides, Origins& origins) {
  for (const auto& ov : overrides) {
    check_generated_cells(root, ov, origins.file);
    const toml::table value = override_value(ov);
    apply_value(root, ov, ov.key, *value.get("v"), origins);
  }
}

// ---------------------------------------------------------------- [mesh]

/// `memory_limit`: --memory-limit, the default limit of meshing a script.
/// [mesh] file's path and Gmsh's options, every key of them read.
std::pair<fs::path, GmshOptions> mesh_file_options(Section& m, const fs::path& base_dir,
                                                   const std::string& memory_limit_option) {
  const fs::path path = base_dir / m.string("file");
  GmshOptions g;
  g.size_factor = m.positive("size_factor", 1.0);
  g.trust_script = m.boolean("trust_geo", false);
  g.trust_how = "[mesh] trust_geo = true";
  // Meshing a script is bounded in time and memory (a loop without end, a tiny size factor).
  g.time_limit = m.number("time_limit", 600.0);
  if (!(g.time_limit >= 0))
    fail("{}: expected a number of seconds >= 0 (0: no limit), got {}", m.where("time_limit"), g.time_limit);
  g.time_limit_how = "[mesh] time_limit";
  const MemoryLimit limit = m.has("memory_limit")
                                ? MemoryLimit{parse_memory_size(m.string("memory_limit"), m.where("memory_limit")),
                                              "[mesh] memory_limit"}
                                : memory_limit(memory_limit_option);
  // At least 1 GiB: the limit is on address space, of which Gmsh's libraries alone map hundreds of MiB.
  g.memory_limit =
      std::isfinite(limit.bytes) ? static_cast<std::size_t>(std::max(limit.bytes, 1024.0 * 1024 * 1024)) : 0;
  g.memory_limit_how =
      m.has("memory_limit") ? limit.source : limit.source + "; [mesh] memory_limit sets it for meshing";
  return {path, g};
}

Mesh read_mesh_file(Section& m, const fs::path& base_dir, const std::string& memory_limit_option) {
  const auto [path, options] = mesh_file_options(m, base_dir, memory_limit_option);
  return located(m.where("file"), [&] { return read_gmsh(path, options); });
}

/// The cells per direction of a generated mesh: one number for all, or one each;
/// `cells_multiple_of` (with `cells_reason`) states what the case's geometry needs.
std::vector<int> read_cells(Section& m, int d) {
  std::vector<int> n;
  const toml::node* c = m.get("cells");
  if (c && c->is_integer()) {
    n.assign(d, m.integer("cells"));
  } else {
    for (double v : m.numbers("cells", d)) {
      if (v != std::floor(v)) fail("{}: expected whole numbers of cells", m.where("cells"));
      if (v < 1 || v > 100000) fail("{}: expected between 1 and 100000 cells per direction, got {}", m.where("cells"), v);
      n.push_back(static_cast<int>(v));
    }
  }
  const int multiple = m.integer("cells_multiple_of", 1);
  if (multiple < 1) fail("{}: expected an integer >= 1", m.where("cells_multiple_of"));
  const std::string reason = m.string("cells_reason", "");
  for (int a = 0; a < d; ++a) {
    if (n[a] < 1 || n[a] > 100000)
      fail("{}: expected between 1 and 100000 cells per direction, got {}", m.where("cells"), n[a]);
    if (n[a] % multiple != 0)
      fail("{}: the number of cells per edge n must be a multiple of {}{}; got {}", m.where("cells"), multiple,
           reason.empty() ? "" : " (" + reason + ")", n[a]);
  }
  return n;
}

/// The rank's block of the grid (split_grid) and a layer of cells around it (MeshBlock).
std::pair<GridBlock, std::vector<GridBlock>> block_with_layer(const std::array<int, 3>& n, int d,
                                                              const MeshRequest::Block& request) {
  std::vector<GridBlock> parts = split_grid(whole_grid(n, d), d, request.ranks);
  GridBlock b = parts[static_cast<std::size_t>(request.rank)];
  for (int a = 0; a < d; ++a) {
    b.lo[a] = std::max(b.lo[a] - 1, 0);
    b.hi[a] = std::min(b.hi[a] + 1, n[a]);
  }
  return {b, std::move(parts)};
}

/// Each cell's rank: the part of the grid (`parts`) holding its segment, square or cube.
std::vector<int> cell_ranks(const BlockMesh& bm, const std::array<int, 3>& n, int d, const GridBlock& block,
                            const std::vector<GridBlock>& parts) {
  std::vector<int> near;  // the parts that the block meets
  for (std::size_t r = 0; r < parts.size(); ++r) {
    bool meets = true;
    for (int a = 0; a < d; ++a) meets = meets && parts[r].lo[a] < block.hi[a] && block.lo[a] < parts[r].hi[a];
    if (meets) near.push_back(static_cast<int>(r));
  }
  long long boxes = 1;
  for (int a = 0; a < d; ++a) boxes *= n[a];
  const long long per_box = bm.whole_cells / boxes;
  std::vector<int> rank(bm.cell_id.size(), -1);
  for (std::size_t c = 0; c < rank.size(); ++c) {
    long long box = bm.cell_id[c] / per_box;
    int at[3] = {0, 0, 0};
    for (int a = 0; a < d; ++a) {
      at[a] = static_cast<int>(box % n[a]);
      box /= n[a];
    }
    for (const int r : near) {
      bool in = true;
      for (int a = 0; a < d; ++a) in = in && parts[static_cast<std::size_t>(r)].lo[a] <= at[a] && at[a] < parts[static_cast<std::size_t>(r)].hi[a];
      if (in) {
        rank[c] = r;
        break;
      }
    }
    require(rank[c] >= 0, "internal: cell {} of the generated mesh is in no rank's part of the grid", bm.cell_id[c]);
  }
  return rank;
}

/// [mesh] with a generator: the whole mesh, or with `block` a rank's block (MeshBlock) into `*out`.
Mesh generate_mesh(Section& m, const std::optional<MeshRequest::Block>& block = std::nullopt,
                   std::shared_ptr<MeshBlock>* out = nullptr) {
  const std::string gen = m.choice("generator", {"interval", "rectangle", "box"});
  if (m.has("refine"))
    fail("{}: refine applies to a mesh read from a file; a generated mesh is refined by its cells per edge (cells)",
         m.where("refine"));
  const int d = gen == "interval" ? 1 : (gen == "rectangle" ? 2 : 3);
  const auto lo = m.numbers("lower", d), hi = m.numbers("upper", d);
  const std::vector<int> n = read_cells(m, d);
  for (int a = 0; a < d; ++a)
    if (!(hi[a] > lo[a])) fail("{}: expected upper > lower in every direction", m.where("upper"));
  // How squares and cubes are cut (generators.hpp); an interval has nothing to cut.
  if (d == 1 && m.has("diagonal"))
    fail("{}: diagonal applies to the rectangle and box generators only", m.where("diagonal"));
  const Diagonal diagonal = d == 1 ? Diagonal::right : diagonal_from_name(m.choice("diagonal", diagonal_names(), "right"));
  // The generators check the mesh size (check_mesh_size) before allocating; the
  // other checks above make the size the only thing they can refuse.
  const std::array<int, 3> n3{n[0], d > 1 ? n[1] : 0, d > 2 ? n[2] : 0};
  const Point box_lo{lo[0], d > 1 ? lo[1] : 0, d > 2 ? lo[2] : 0}, box_hi{hi[0], d > 1 ? hi[1] : 0, d > 2 ? hi[2] : 0};
  if (!block) return located(m.where("cells"), [&] { return generate(d, box_lo, box_hi, n3, diagonal); });
  return located(m.where("cells"), [&] {
    const auto [b, parts] = block_with_layer(n3, d, *block);
    BlockMesh bm = generate_block(d, box_lo, box_hi, n3, diagonal, b);
    auto info = std::make_shared<MeshBlock>();
    info->rank = block->rank;
    info->ranks = block->ranks;
    info->cell_rank = cell_ranks(bm, n3, d, b, parts);
    info->node_id = std::move(bm.node_id);
    info->cell_id = std::move(bm.cell_id);
    info->whole_nodes = bm.whole_nodes;
    info->whole_cells = bm.whole_cells;
    info->lo = box_lo;
    info->hi = box_hi;
    info->cells = n3;
    info->diagonal = diagonal;
    *out = std::move(info);
    return std::move(bm.mesh);
  });
}

/// [mesh] file with `refine` uniform refinements (mesh/refine.hpp): the whole refined mesh, or with
/// a block request the rank's block into `*out`: the children of its coarse cells (split_cells) and
/// a layer of fine cells around them, which every rank refines from the file's mesh (rank 0's,
/// MeshRequest::coarse, where given; else read here).
Mesh read_refined_mesh(Section& m, const fs::path& base_dir, const std::string& memory_limit_option,
                       const MeshRequest& request, std::shared_ptr<MeshBlock>* out) {
  const std::optional<MeshRequest::Block>& block = request.block;
  const int levels = m.integer("refine", 0);
  if (levels < 0 || levels > 10)
    fail("{}: expected a number of uniform refinements from 0 to 10 (each cuts every cell into 2^d), got {}",
         m.where("refine"), levels);
  std::shared_ptr<const Mesh> coarse = request.coarse;
  if (coarse && block)
    (void)mesh_file_options(m, base_dir, memory_limit_option);  // its keys read and checked, as by rank 0
  else
    coarse = std::make_shared<const Mesh>(read_mesh_file(m, base_dir, memory_limit_option));
  if (levels == 0) return *coarse;
  return located(m.where("refine"), [&] {
    const MeshRefinement refinement(*coarse, levels);
    if (!block) return refinement.refine_all().mesh;
    const std::vector<int> coarse_rank = split_cells(*coarse, block->ranks);
    std::vector<int> own;
    for (int c = 0; c < coarse->n_cells(); ++c)
      if (coarse_rank[static_cast<std::size_t>(c)] == block->rank) own.push_back(c);
    BlockMesh bm = refinement.refine(own, layer_cells(*coarse, coarse_rank, block->rank));
    auto info = std::make_shared<MeshBlock>();
    info->rank = block->rank;
    info->ranks = block->ranks;
    const int shift = coarse->dim() * levels;  // 2^(d·levels) children a coarse cell
    for (const int id : bm.cell_id) info->cell_rank.push_back(coarse_rank[static_cast<std::size_t>(id >> shift)]);
    info->node_id = std::move(bm.node_id);
    info->cell_id = std::move(bm.cell_id);
    info->whole_nodes = bm.whole_nodes;
    info->whole_cells = bm.whole_cells;
    std::tie(info->lo, info->hi) = coarse->bounding_box();  // the refined mesh's: its corners are coarse nodes
    info->coarse = coarse;
    info->levels = levels;
    *out = std::move(info);
    return std::move(bm.mesh);
  });
}

/// [[mesh.part]]: re-tag the boundary facets whose centroid satisfies a predicate.
/// `check`: whether a part must have facets here (not in a block, whose MeshBlock::checks keeps
/// the check for all ranks together).
void read_mesh_parts(Section& m, Mesh& mesh, const Origins& origins, bool check, MeshBlock* block) {
  if (!m.has("part")) return;
  const toml::node* parts = m.get("part");
  if (!parts->is_array_of_tables()) m.expected("part", "an array of tables [[mesh.part]] with name and where");
  int i = 0;
  for (const auto& node : *parts->as_array()) {
    Section p(node.as_table(), fmt::format("mesh.part[{}]", i++), origins);
    const std::string name = p.string("name");
    const auto where = p.expression("where", Expression::Kind::Space);
    p.finish();
    mesh.tag_facets(name, [&](const Point& x) { return (*where)(x) != 0.0; });
    const std::string none = fmt::format("{}: the predicate {} selects no boundary facet", p.where("where"),
                                         quote_formula(where->text()));
    if (check && mesh.part_size(name) == 0) fail("{}", none);
    if (block) block->checks.push_back({MeshBlock::Check::Of::part, name, none});
  }
}

/// [mesh], built, or an empty mesh of the requested dimension (a rank that does not build it),
/// or with a block request (only for a generator: parse_case) the rank's block into `*block`.
Mesh read_mesh(Section m, const fs::path& base_dir, const Origins& origins, const MeshRequest& request,
               const std::string& memory_limit_option, std::shared_ptr<MeshBlock>* block = nullptr) {
  if (!m.exists()) fail("{}: missing section [mesh]", origins.file);
  if (!request.build && !request.block) {
    require(request.dim >= 1 && request.dim <= 3, "{}: the mesh dimension must be 1, 2 or 3", origins.file);
    return Mesh(request.dim);  // [mesh] is read by the rank that builds the mesh
  }
  Mesh mesh = m.has("file") ? read_refined_mesh(m, base_dir, memory_limit_option, request, block)
                             : generate_mesh(m, request.block, block);
  // Coordinates such as 1e120 overflow the method's products (issue 26): refused here, at check.
  located(m.has("file") ? fmt::format("{}: {}", m.where("file"), quote(m.string("file"))) : m.where("upper"),
          [&] { check_mesh_extent(mesh); });
  read_mesh_parts(m, mesh, origins, !request.block, block ? block->get() : nullptr);
  m.finish();
  return mesh;
}

// ---------------------------------------------------------------- [[body]]

/// [[body]] (SPEC §8): each further body's name and [body.mesh] (as [mesh]), appended to
/// p.mesh: its parts become "<name>.<part>" and its regions "<name>.<region>" for the rest
/// of the case. Returns the bodies' sections, whose other tables read_body_data reads once
/// the case's own material is known.
std::vector<Section> read_body_meshes(Section& top, Problem& p, const fs::path& base_dir, const Origins& origins,
                                      const MeshRequest& request, const std::string& memory_limit_option) {
  std::vector<Section> bodies;
  if (!top.has("body")) return bodies;
  const toml::node* list = top.get("body");
  if (!list->is_array_of_tables()) top.expected("body", "an array of tables [[body]] with name and [body.mesh]");
  std::set<std::string> names{"body"};
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("body[{}]", bodies.size()), origins);
    const std::string name = s.string("name");
    const bool plain = !name.empty() && name.size() <= 100 && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
    });
    if (!plain || names.count(name))
      fail("{}: expected a new body name of letters, digits, '-' and '_' (at most 100; \"body\" is the case's own "
           "[mesh]){}; its parts are then named \"<name>.<part>\"",
           s.where("name"), names.count(name) ? fmt::format("; {} is taken", quote(name)) : "");
    names.insert(name);
    if (request.build) {
      const std::string prefix = name + ".";
      for (const auto& list_of : {p.mesh.part_names(), p.mesh.region_names()})
        for (const auto& taken : list_of)
          if (taken.starts_with(prefix))
            fail("{}: the mesh already has a part or region {}, which the body's own parts would be confused with; "
                 "name the body otherwise",
                 s.where("name"), quote(taken));
    }
    Section m = s.table("mesh");
    if (!m.exists()) fail("{}: missing section [body.mesh] of body {} (a generator or a file, as [mesh])", s.where_section(), quote(name));
    const Mesh mesh = read_mesh(m, base_dir, origins, {request.build, request.dim, std::nullopt, std::nullopt, nullptr}, memory_limit_option);
    if (request.build) p.mesh.append(mesh, name);
    bodies.push_back(std::move(s));
  }
  return bodies;
}

// ---------------------------------------------------------------- [boundary], [elasticity], laws

/// `check`: whether the parts must exist in the problem's mesh (not on a rank that did not build
/// it; on a block, MeshBlock::required_parts keeps the check for all ranks together).
std::vector<std::string> read_parts(Section& b, const std::string& key, Problem& problem, bool required, bool check) {
  if (!required && !b.has(key)) return {};
  const auto parts = b.strings(key);
  if (parts.empty()) fail("{}: expected at least one boundary part name", b.where(key));
  for (const auto& p : parts) {
    const std::string missing =
        fmt::format("{}: boundary part {} does not exist in the mesh (or has no facets); the mesh has: ", b.where(key), quote(p));
    if (check && problem.mesh.part_size(p) == 0) fail("{}{}", missing, describe_parts(problem.mesh));
    if (problem.block) problem.block->checks.push_back({MeshBlock::Check::Of::part, p, missing, true});
  }
  return parts;
}

/// [[boundary.displacement]]: prescribed components ux, uy, uz (formulas in x, y, z, t) on named parts.
void read_displacements(Section& b, Problem& p, const Origins& origins, bool check) {
  if (!b.has("displacement")) return;
  const toml::node* list = b.get("displacement");
  if (!list->is_array_of_tables())
    b.expected("displacement", "an array of tables [[boundary.displacement]] with parts and ux, uy or uz");
  const int d = p.mesh.dim();
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("boundary.displacement[{}]", k++), origins);
    PrescribedDisplacement bc;
    bc.parts = read_parts(s, "parts", p, true, check);
    for (int c = 0; c < 3; ++c) {
      const std::string key = std::string("u") + "xyz"[c];
      if (!s.has(key)) continue;
      if (c >= d) fail("{}: the mesh has d = {}: its components are {}", s.where(key), d, d == 1 ? "ux" : "ux, uy");
      const auto e = s.state_expression(key, Expression::Kind::SpaceTime);
      bc.value[c] = [e](const Point& x, double t) { return (*e)(x, t); };
    }
    if (std::none_of(bc.value.begin(), bc.value.end(), [](const ScalarField& f) { return static_cast<bool>(f); }))
      fail("{}: expected at least one of {} (a formula in x, y, z, t)", s.where_section(),
           d == 1 ? "ux" : d == 2 ? "ux, uy" : "ux, uy, uz");
    s.finish();
    p.displacement.push_back(std::move(bc));
  }
}

/// `pairs`: the case has [[contact.pair]]s, and Γ3 (`contact`) may then be left out.
void read_boundary(Section b, Problem& p, const Origins& origins, bool check, bool pairs) {
  if (!b.exists()) fail("{}: missing section [boundary] (clamped and contact parts)", origins.file);
  read_displacements(b, p, origins, check);
  p.symmetry = read_parts(b, "symmetry", p, false, check);
  if (check)
    for (const auto& part : p.symmetry) located(b.where("symmetry"), [&] { symmetry_axis(p.mesh, part); });
  // Γ1 may be left out when prescribed displacements or symmetry planes hold the body.
  p.clamped = read_parts(b, "clamped", p, p.displacement.empty() && p.symmetry.empty(), check);
  p.contact.parts = read_parts(b, "contact", p, !pairs, check);
  p.traction = read_parts(b, "traction", p, false, check);
  b.finish();
}

Elasticity read_elasticity(Section e, int d, const std::string& file) {
  if (!e.exists()) fail("{}: missing section [elasticity] (kind, E, nu)", file);
  const std::string default_kind = d == 1 ? "1d" : (d == 3 ? "isotropic" : "");
  const std::string kind = e.choice("kind", {"1d", "plane-stress", "plane-strain", "isotropic"}, default_kind);
  const double young = e.number("E");
  const double nu = d == 1 ? e.number("nu", 0.0) : e.number("nu");
  const Elasticity elasticity = located(e.where_section(), [&] { return Elasticity::from_name(kind, young, nu); });
  if (elasticity.dim() != d)
    fail("{}: elasticity '{}' is for d = {} but the mesh has d = {}", e.where("kind"), kind, elasticity.dim(), d);
  e.finish();
  return elasticity;
}

/// [material.elasticity]: E and nu of another material; the kind is the body's, and
/// a key left out keeps the body's value.
Elasticity read_material_elasticity(Section e, const Elasticity& body) {
  if (e.has("kind") && e.string("kind") != body.name())
    fail("{}: every material of a body has the body's kind '{}' (the stresses have the same components); "
         "leave kind out", e.where("kind"), body.name());
  const double young = e.number("E", body.young()), nu = e.number("nu", body.poisson());
  const Elasticity elasticity = located(e.where_section(), [&] { return Elasticity(body.kind(), young, nu); });
  e.finish();
  return elasticity;
}

Parameters law_parameters(Section& s) {
  Parameters p;
  for (const auto& k : s.remaining()) p.set(k, s.number(k));
  return p;
}

/// If a law rejected a parameter it does not know, say where it is and what the
/// law's parameters are.
void unknown_parameter(Section& s, const Parameters& params, const std::string& law,
                       const std::vector<std::string>& names) {
  const auto unused = params.unused();
  if (unused.empty()) return;
  std::set<std::string> candidates(names.begin(), names.end());
  candidates.insert(s.known().begin(), s.known().end());  // a misspelt key of the section itself
  for (const auto& u : unused) candidates.erase(u);
  fail("{}: unknown key or parameter of the {}{}; its parameters are: {}", s.where(unused.front()), law,
       did_you_mean(unused.front(), candidates), names.empty() ? "(none)" : fmt::format("{}", fmt::join(names, ", ")));
}

/// [viscoplasticity]: G, named, with its parameters (Perzyna's E defaults to ℰ's).
std::shared_ptr<const ViscoplasticLaw> read_viscoplasticity(Section v, double young) {
  const std::string law = v.choice("law", viscoplastic_law_names(), "elastic");
  Parameters params = law_parameters(v);
  if (law.rfind("perzyna", 0) == 0 && !params.has("E")) params.set("E", young);
  try {
    return make_viscoplastic_law(law, params);
  } catch (const Error& err) {
    unknown_parameter(v, params, "viscoplastic law '" + law + "'", viscoplastic_law_parameters(law));
    fail("{}: [viscoplasticity]: {}", v.where_section(), err.what());
  }
}

// ---------------------------------------------------------------- [damage]

/// φ: a formula (`phi`), or a named source with its parameters.
std::shared_ptr<const DamageSource> read_damage_source(Section& dm) {
  if (dm.has("phi")) {
    if (dm.has("source") && dm.string("source") != "expression")
      fail("{}: give either source = \"<name>\" or phi = \"<formula>\", not both", dm.where("phi"));
    return std::make_shared<ExpressionSource>(dm.state_expression("phi", Expression::Kind::PointState));
  }
  const std::string src = dm.choice("source", damage_source_names(), "zero");
  Parameters params = law_parameters(dm);
  try {
    return make_damage_source(src, params);
  } catch (const Error& err) {
    unknown_parameter(dm, params, "damage source '" + src + "'", damage_source_parameters(src));
    fail("{}: [damage]: {}", dm.where_section(), err.what());
  }
}

void read_damage(Section dm, Problem& p) {
  p.kappa = dm.number("kappa", 1.0);
  located(dm.where("kappa"), [&] { check_kappa(p.kappa); });
  const auto b0 = dm.has("beta0") ? dm.expression("beta0", Expression::Kind::Space) : nullptr;
  if (b0) {
    p.beta0 = [b0](const Point& x, double) { return (*b0)(x); };
    located(dm.where("beta0"), [&] { check_beta0(p.mesh, p.beta0, p.mesh.n_bodies() > 1 ? 0 : -1, p.block.get()); });
  } else {
    p.beta0 = [](const Point&, double) { return 1.0; };
  }
  p.source = read_damage_source(dm);
  dm.finish();
}

/// [[material]]: further materials, each on Gmsh regions (`regions`: physical groups of
/// the mesh's dimension) or on the cells whose centroid satisfies `where`; a later one
/// takes the cells it selects from an earlier one. [material.elasticity],
/// [material.viscoplasticity] and [material.damage] left out are the body's.
/// `build`: this process has the mesh (the regions can be checked and tagged).
void read_materials(Section& top, Problem& p, const Origins& origins, bool build) {
  if (!top.has("material")) return;
  const toml::node* list = top.get("material");
  if (!list->is_array_of_tables())
    top.expected("material", "an array of tables [[material]] with name and regions or where");
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("material[{}]", k++), origins);
    Material m;
    m.name = s.string("name");
    const bool taken = m.name == "body" || std::any_of(p.materials.begin(), p.materials.end(),
                                                       [&](const Material& o) { return o.name == m.name; });
    if (m.name.empty() || taken)
      fail("{}: expected a new material name (\"body\" is the body's material{})", s.where("name"),
           m.name.empty() ? "" : fmt::format("; {} is taken", quote(m.name)));
    if (s.has("regions") == s.has("where"))
      fail("{}: expected either regions (Gmsh physical groups of dimension {}) or where (a predicate on the cell "
           "centroid), not {}", s.where_section(), p.mesh.dim(), s.has("where") ? "both" : "neither");
    if (s.has("regions")) {
      m.regions = s.strings("regions");
      if (m.regions.empty()) fail("{}: expected at least one region name", s.where("regions"));
      for (const auto& r : m.regions) {
        const std::string none = fmt::format(
            "{}: the mesh has no cell in region {}; its regions: {}", s.where("regions"), quote(r),
            p.mesh.region_names().empty() ? "(none: give the cells Gmsh physical groups of dimension d)"
                                           : printable(fmt::format("{}", fmt::join(p.mesh.region_names(), ", ")), 300));
        if (build && p.mesh.region_size(r) == 0) fail("{}", none);
        if (p.block) p.block->checks.push_back({MeshBlock::Check::Of::region, r, none});
      }
    } else {
      const auto where = s.expression("where", Expression::Kind::Space);
      if (build && p.mesh.find_region(m.name) >= 0)
        fail("{}: the mesh has a region named {} already; name the material otherwise, or give regions = [{}]",
             s.where("name"), quote(m.name), quote_formula(m.name));
      p.mesh.tag_cells(m.name, [&](const Point& x) { return (*where)(x) != 0.0; });
      const std::string none = fmt::format("{}: the predicate {} selects no cell (it is evaluated at cell centroids)",
                                           s.where("where"), quote_formula(where->text()));
      if (build && p.mesh.region_size(m.name) == 0) fail("{}", none);
      if (p.block) p.block->checks.push_back({MeshBlock::Check::Of::region, m.name, none});
      m.regions = {m.name};
    }
    Section e = s.table("elasticity");
    m.elasticity = e.exists() ? read_material_elasticity(e, p.elasticity) : p.elasticity;
    Section v = s.table("viscoplasticity");
    m.law = v.exists() ? read_viscoplasticity(v, m.elasticity.young()) : p.law;
    Section dm = s.table("damage");
    m.source = p.source;
    if (dm.exists()) {
      for (const char* global : {"kappa", "beta0"})
        if (dm.has(global))
          fail("{}: {} belongs to [damage]: the damage equation is one field over the whole body", dm.where(global),
               global);
      m.source = read_damage_source(dm);
      dm.finish();
    }
    s.finish();
    p.materials.push_back(std::move(m));
  }
}

/// The [[body]] tables' [body.elasticity] (E, nu; the case's kind), [body.viscoplasticity]
/// and [body.damage] (kappa, beta0, the source): each left out, or each key of
/// [body.elasticity] and [body.damage] left out, is the case's.
void read_body_data(std::vector<Section>& sections, Problem& p) {
  for (Section& s : sections) {
    Body b;
    b.name = s.string("name");
    Section e = s.table("elasticity");
    b.material.name = b.name;
    b.material.elasticity = e.exists() ? read_material_elasticity(e, p.elasticity) : p.elasticity;
    Section v = s.table("viscoplasticity");
    b.material.law = v.exists() ? read_viscoplasticity(v, b.material.elasticity.young()) : p.law;
    Section dm = s.table("damage");
    b.kappa = dm.number("kappa", p.kappa);
    located(dm.where("kappa"), [&] { check_kappa(b.kappa); });
    if (dm.has("beta0")) {
      const auto b0 = dm.expression("beta0", Expression::Kind::Space);
      b.beta0 = [b0](const Point& x, double) { return (*b0)(x); };
      const int index = static_cast<int>(p.bodies.size()) + 1;
      located(dm.where("beta0"), [&] { check_beta0(p.mesh, b.beta0, index); });
    } else {
      b.beta0 = p.beta0;
    }
    b.material.source = dm.has("source") || dm.has("phi") ? read_damage_source(dm) : p.source;
    dm.finish();
    s.finish();
    p.bodies.push_back(std::move(b));
  }
}

// ---------------------------------------------------------------- [loads], [contact], [time]

/// [[loads.pressure]]: a normal pressure p(x, t) on named parts.
void read_pressure(Section& l, Problem& p, const Origins& origins, bool check) {
  if (!l.has("pressure")) return;
  const toml::node* loads = l.get("pressure");
  if (!loads->is_array_of_tables()) l.expected("pressure", "an array of tables [[loads.pressure]] with parts and p");
  int i = 0;
  for (const auto& node : *loads->as_array()) {
    Section s(node.as_table(), fmt::format("loads.pressure[{}]", i++), origins);
    PressureLoad load;
    load.parts = read_parts(s, "parts", p, true, check);
    const auto pressure = s.state_expression("p", Expression::Kind::SpaceTime);
    load.p = [pressure](const Point& x, double t) { return (*pressure)(x, t); };
    s.finish();
    p.pressure.push_back(std::move(load));
  }
}

void read_loads(Section l, Problem& p, const Origins& origins, bool check) {
  auto load = [&](const char* key, bool& uniform) {
    if (!l.has(key)) return VectorField{};
    auto e = l.state_expressions(key, p.mesh.dim(), Expression::Kind::SpaceTime);
    uniform = std::none_of(e.begin(), e.end(), [](const auto& f) { return f->uses_position(); });
    return vector_field(std::move(e));
  };
  p.f0 = load("f0", p.f0_uniform);
  p.f2 = load("f2", p.f2_uniform);
  read_pressure(l, p, origins, check);
  l.finish();
}

/// `direction`: "normal" (unset) or a fixed non-zero vector.
std::optional<Point> read_contact_direction(Section& ct, int d) {
  if (!ct.has("direction")) return std::nullopt;
  if (ct.get("direction")->is_string()) {
    ct.choice("direction", {"normal"});
    return std::nullopt;
  }
  const auto v = ct.numbers("direction", d);
  Point dir{0, 0, 0};
  for (int i = 0; i < d; ++i) dir[i] = v[i];
  if (std::hypot(dir[0], dir[1], dir[2]) == 0) fail("{}: expected a non-zero vector", ct.where("direction"));
  return dir;
}

/// A unit vector from `key` (d numbers, not all zero).
Point unit_vector(Section& s, const std::string& key, int d) {
  const auto v = s.numbers(key, static_cast<size_t>(d));
  Point u{0, 0, 0};
  for (int i = 0; i < d; ++i) u[i] = v[i];
  const double l = std::hypot(u[0], u[1], u[2]);
  if (l == 0) fail("{}: expected a non-zero vector", s.where(key));
  for (double& c : u) c /= l;
  return u;
}

/// One [[obstacle]]: its shape, its position (formulas in t) and size.
Obstacle read_obstacle(Section& s, int k, int d) {
  Obstacle o;
  o.name = s.string("name", fmt::format("obstacle{}", k + 1));
  const std::string shape = s.choice("shape", {"plane", "sphere", "cylinder"});
  o.shape = shape == "plane" ? Obstacle::Shape::Plane : shape == "sphere" ? Obstacle::Shape::Sphere : Obstacle::Shape::Cylinder;
  const std::string at = o.shape == Obstacle::Shape::Plane ? "point" : "center";
  auto position = s.state_expressions(at, d, Expression::Kind::SpaceTime);
  for (const auto& e : position)
    if (e->uses_position())
      fail("{}: the position of an obstacle is a formula in t only (got {})", s.where(at), quote_formula(e->text()));
  o.position = vector_field(std::move(position));
  if (o.shape == Obstacle::Shape::Plane) {
    o.normal = unit_vector(s, "normal", d);
  } else {
    o.radius = s.number("radius");
    if (!(o.radius > 0)) fail("{}: expected a radius > 0, got {}", s.where("radius"), o.radius);
  }
  if (o.shape == Obstacle::Shape::Cylinder && d == 3) o.axis = unit_vector(s, "axis", d);
  return o;
}

/// `key`: parts of Γ3 (a subset of [boundary] contact), or none when the key is absent.
std::vector<std::string> contact_parts(Section& s, const std::string& key, const Problem& p) {
  if (!s.has(key)) return {};
  const auto parts = s.strings(key);
  if (parts.empty()) fail("{}: expected at least one contact part name", s.where(key));
  for (const auto& part : parts)
    if (std::find(p.contact.parts.begin(), p.contact.parts.end(), part) == p.contact.parts.end())
      fail("{}: {} is not a contact part; [boundary] contact has: {}", s.where(key), quote(part), fmt::join(p.contact.parts, ", "));
  return parts;
}

/// A law's keys as a Section's (located errors; each key read is a known one for finish()).
class SectionKeys final : public LawKeys {
 public:
  explicit SectionKeys(Section& s) : s_(s) {}
  bool has(const std::string& key) override { return s_.has(key); }
  double number(const std::string& key) override { return s_.number(key); }
  double number(const std::string& key, double fallback) override { return s_.number(key, fallback); }
  std::string where(const std::string& key) override { return s_.where(key); }

 private:
  Section& s_;
};

/// A friction law's keys: a number or a formula (mu in x, y, z; friction_bound also in t),
/// registered for the per-step finiteness check.
class SectionFrictionKeys final : public FrictionKeys {
 public:
  explicit SectionFrictionKeys(Section& s) : s_(s) {}
  bool has(const std::string& key) override { return s_.has(key); }
  double number(const std::string& key) override { return s_.number(key); }
  double number(const std::string& key, double fallback) override { return s_.number(key, fallback); }
  std::string where(const std::string& key) override { return s_.has(key) ? s_.where(key) : s_.where_section(); }
  LawField field(const std::string& key, bool time) override {
    std::shared_ptr<const Expression> e =
        s_.state_expression(key, time ? Expression::Kind::SpaceTime : Expression::Kind::Space);
    return [e](const Point& x, double t) { return (*e)(x, t); };
  }
  bool is_number(const std::string& key) override { return s_.get(key) && s_.get(key)->is_number(); }
  bool uses_time(const std::string& key) override {
    return s_.get(key) && s_.get(key)->is_string() && s_.expression(key, Expression::Kind::SpaceTime)->uses_time();
  }

 private:
  Section& s_;
};

/// The friction law of a [contact], [[contact.part]] or [[contact.pair]] table (SPEC §7): friction = "none",
/// "coulomb" (mu) or "tresca" (friction_bound); `inherited` where the table has no friction key.
std::shared_ptr<const FrictionLaw> read_friction_law(Section& s, std::shared_ptr<const FrictionLaw> inherited, int dim) {
  if (!s.has("friction")) {
    for (const std::string& k : friction_keys())
      if (s.has(k))
        fail("{}: {} needs friction = \"{}\" in the same table", s.where(k), k, k == "friction_bound" ? "tresca" : "coulomb");
    return inherited;
  }
  const std::string name = s.choice("friction", friction_law_names(), "none");
  if (name != "none" && dim < 2)
    fail("{}: friction needs a body of dimension 2 or 3 (a 1D bar has no tangential direction)", s.where("friction"));
  SectionFrictionKeys keys(s);
  return make_friction_law(name, keys);
}

/// A contact law: `law`, a name in the registry (contact/registry.cpp; default "signorini"),
/// which reads its own keys (normal-compliance: stiffness c > 0, exponent e ≥ 1).
std::shared_ptr<const ContactLaw> read_contact_law(Section& s) {
  const std::string name = s.choice("law", contact_law_names(), "signorini");
  SectionKeys keys(s);
  return make_contact_law(name, keys);
}

/// [[obstacle]] sections (instead of [contact] gap).
void read_obstacles(Section& top, Problem& p, const Origins& origins, bool gap_given) {
  if (!top.has("obstacle")) return;
  const toml::node* list = top.get("obstacle");
  if (!list->is_array_of_tables()) top.expected("obstacle", "an array of tables [[obstacle]] with shape and position");
  if (gap_given) fail("{}: a case has either [contact] gap or [[obstacle]] sections, not both", top.where("obstacle"));
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("obstacle[{}]", k), origins);
    p.contact.obstacles.push_back(read_obstacle(s, k++, p.mesh.dim()));
    p.contact.obstacles.back().parts = contact_parts(s, "parts", p);
    s.finish();
  }
}

/// Where the keys are that Problem::validate's checks across keys name (Problem::where).
void record_key_locations(Section& top, Problem& p, const Origins& origins) {
  auto record = [&](Section& s, const std::string& key) {
    if (s.has(key)) p.key_locations[s.key_path(key)] = s.where(key);
  };
  auto record_tables = [&](Section& s, const std::string& key) {  // [[key]]: each table's header
    if (!s.has(key) || !s.get(key)->is_array_of_tables()) return;
    int k = 0;
    for (const auto& node : *s.get(key)->as_array()) {
      const std::string path = fmt::format("{}[{}]", s.key_path(key), k++);
      p.key_locations[path] = fmt::format("{}: {}", Section(node.as_table(), path, origins).where_section(), path);
    }
  };
  Section b = top.table("boundary");
  if (b.exists()) p.key_locations["boundary"] = fmt::format("{}: [boundary]", b.where_section());
  for (const char* key : {"contact", "clamped", "symmetry"}) record(b, key);
  record_tables(b, "displacement");
  Section ct = top.table("contact");
  for (const char* key : {"gap", "direction", "friction", "mu", "shear_limit", "friction_bound"}) record(ct, key);
  record_tables(ct, "pair");
  if (p.key_locations.count("contact.pair[0]")) p.key_locations["contact.pair"] = p.key_locations["contact.pair[0]"];
  record_tables(top, "obstacle");
  Section ld = top.table("loads");
  record_tables(ld, "pressure");
  Section dm = top.table("damage");
  record(dm, "kappa");
  if (top.has("obstacle") && top.get("obstacle")->is_array_of_tables()) {  // a plane's normal (contact_rows.cpp)
    int k = 0;
    for (const auto& node : *top.get("obstacle")->as_array()) {
      Section s(node.as_table(), fmt::format("obstacle[{}]", k++), origins);
      record(s, "normal");
    }
  }
  Section tm = top.table("time");
  if (tm.exists()) p.key_locations["time"] = fmt::format("{}: [time]", tm.where_section());
  for (const char* key : {"steps", "dt", "tolerance", "dt_min"}) record(tm, key);
}

/// ν near 1/2 locks P1 elements in plane strain and 3D: λ/μ = 2ν/(1 − 2ν) grows without
/// bound, and linear simplices cannot represent a divergence-free displacement field
/// well (volumetric locking): the body is too stiff, its forces too large. Plane stress
/// does not lock (its λ* = 2λμ/(λ + 2μ) stays below 2μ). Above ν = 0.475 (λ/μ = 19), the
/// threshold above which Abaqus recommends its hybrid elements, a coarse mesh's contact
/// force is measured 11 % above a 4× finer one's (24 % at 0.49, 180 % at 0.499; 0.8 % at
/// ν = 0.3): warn, naming the key.
std::vector<std::string> locking_warnings(Section& top, const Problem& p) {
  constexpr double kNuLocking = 0.475;
  std::vector<std::string> warnings;
  auto check = [&](Section e, const Elasticity& elasticity, const std::string& what) {
    const auto kind = elasticity.kind();
    const double nu = elasticity.poisson();
    if ((kind != Elasticity::Kind::PlaneStrain && kind != Elasticity::Kind::Isotropic) || !(nu > kNuLocking)) return;
    warnings.push_back(fmt::format(
        "{}: nu = {} {}is near 1/2 (lambda/mu = {:.3g}): linear (P1) elements lock in {} (volumetric locking: the body "
        "is too stiff and its forces too large, the more so the closer nu is to 1/2); above nu = {} compare with a finer "
        "mesh, or use a smaller nu",
        e.has("nu") ? e.where("nu") : e.where_section(), nu, what, 2 * nu / (1 - 2 * nu),
        kind == Elasticity::Kind::PlaneStrain ? "plane strain" : "3D", kNuLocking));
  };
  check(top.table("elasticity"), p.elasticity, "");
  if (top.has("material") && top.get("material")->is_array_of_tables()) {
    const auto& list = *top.get("material")->as_array();
    for (std::size_t k = 0; k < p.materials.size() && k < list.size(); ++k) {
      Section m(list[k].as_table(), fmt::format("material[{}]", k), top.origins());
      if (m.table("elasticity").has("nu"))
        check(m.table("elasticity"), p.materials[k].elasticity, fmt::format("of material '{}' ", p.materials[k].name));
    }
  }
  if (top.has("body") && top.get("body")->is_array_of_tables()) {
    const auto& list = *top.get("body")->as_array();
    for (std::size_t k = 0; k < p.bodies.size() && k < list.size(); ++k) {
      Section b(list[k].as_table(), fmt::format("body[{}]", k), top.origins());
      if (b.table("elasticity").has("nu"))
        check(b.table("elasticity"), p.bodies[k].material.elasticity, fmt::format("of body '{}' ", p.bodies[k].name));
    }
  }
  return warnings;
}

/// [[contact.pair]] (SPEC §8): slave and master, boundary parts of two bodies; `search`; a normal
/// law and a friction law, each [contact]'s where the pair gives none; `sliding`.
void read_contact_pairs(Section& ct, Problem& p, const Origins& origins) {
  if (!ct.has("pair")) return;
  const toml::node* list = ct.get("pair");
  if (!list->is_array_of_tables()) ct.expected("pair", "an array of tables [[contact.pair]] with slave and master");
  const bool check = p.mesh.n_cells() > 0 && !p.block;  // the rank that built the whole mesh
  int k = 0;
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("contact.pair[{}]", k++), origins);
    ContactPair pair;
    for (auto [key, part] : {std::pair{"slave", &pair.slave}, std::pair{"master", &pair.master}}) {
      *part = s.string(key);
      if (check && p.mesh.part_size(*part) == 0)
        fail("{}: boundary part {} does not exist in the mesh (or has no facets); the mesh has: {}", s.where(key),
             quote(*part), printable(fmt::format("{}", fmt::join(p.mesh.part_names(), ", ")), 300));
    }
    pair.search = s.number("search", 0.0);
    if (s.has("law")) {
      pair.law = read_contact_law(s);
    } else {  // [contact]'s law; a compliance parameter alone is a forgotten law
      for (const std::string& k : compliance_keys())
        if (s.has(k)) fail("{}: {} needs law = \"normal-compliance\" in the same table", s.where(k), k);
    }
    pair.friction = read_friction_law(s, p.contact.friction, p.mesh.dim());
    pair.large_sliding = s.choice("sliding", {"small", "large"}, "small") == "large";
    if (!(pair.search >= 0) || !std::isfinite(pair.search))
      fail("{}: expected a distance >= 0 (0: the slave part's longest facet edge)", s.where("search"));
    s.finish();
    p.contact.pairs.push_back(std::move(pair));
  }
}

/// Returns whether a gap was given.
bool read_contact(Section ct, Problem& p, const Origins& origins) {
  const auto gap = ct.has("gap") ? ct.state_expression("gap", Expression::Kind::SpaceTime) : nullptr;
  p.contact.gap = [gap](const Point& x, double t) { return gap ? (*gap)(x, t) : 0.0; };
  p.contact.gap_moves = gap && gap->uses_time();
  located(ct.where("gap"), [&] { check_gap(p.mesh, p.contact, p.block.get()); });
  p.contact.direction = read_contact_direction(ct, p.mesh.dim());
  p.contact.law = read_contact_law(ct);
  p.contact.friction = read_friction_law(ct, nullptr, p.mesh.dim());
  if (ct.has("part")) {  // [[contact.part]]: another law on some parts
    const toml::node* list = ct.get("part");
    if (!list->is_array_of_tables())
      ct.expected("part", "an array of tables [[contact.part]] with parts and law (stiffness, exponent)");
    int k = 0;
    for (const auto& node : *list->as_array()) {
      Section s(node.as_table(), fmt::format("contact.part[{}]", k++), origins);
      PartContactLaw pl;
      pl.parts = contact_parts(s, "parts", p);
      if (pl.parts.empty()) s.expected("parts", "the contact parts this law acts on");
      for (const auto& part : pl.parts)
        for (const PartContactLaw& other : p.contact.part_laws)
          if (std::find(other.parts.begin(), other.parts.end(), part) != other.parts.end())
            fail("{}: contact part {} has a law already (an earlier [[contact.part]])", s.where("parts"), quote(part));
      pl.law = read_contact_law(s);
      pl.friction = read_friction_law(s, p.contact.friction, p.mesh.dim());
      s.finish();
      p.contact.part_laws.push_back(std::move(pl));
    }
  }
  read_contact_pairs(ct, p, origins);
  ct.finish();
  return gap != nullptr;
}

/// [time]: T and one of
///   steps = N                    N uniform steps;
///   dt = k                       uniform steps of k (it must divide T);
///   dt = [k1, k2, …]             these steps (adding up to T), or with breakpoints = [b1, …]
///                                one step size per interval [0, b1], [b1, b2], …, [b_last, T];
///   dt = "formula in t"          t_{n+1} = t_n + k(t_n);
///   tolerance = e                error-controlled steps (scheme/time_grid.hpp, StepControl),
///                                with dt_initial, dt_min, dt_max, growth, cut, safety, event_dt,
///                                events, max_rejections; breakpoints: times a step ends at.
void read_time(Section tm, Problem& p, const std::string& file) {
  if (!tm.exists()) fail("{}: missing section [time] (T and steps, dt or tolerance)", file);
  p.final_time = tm.number("T", 1.0);
  located(tm.where("T"), [&] { check_final_time(p.final_time); });
  const int given = tm.has("steps") + tm.has("dt") + tm.has("tolerance");
  if (given != 1)
    fail("{}: give exactly one of steps, dt (a step size, a list or a formula in t) and tolerance (error-controlled "
         "steps)", tm.where_section());
  std::vector<double> breakpoints;
  if (tm.has("breakpoints")) breakpoints = tm.numbers("breakpoints", 0);
  if (!tm.has("tolerance"))
    for (const auto& k : step_control_keys())
      if (tm.has(k)) fail("{}: applies to error-controlled steps only (give tolerance instead of steps or dt)", tm.where(k));
  if (tm.has("steps")) {
    if (!breakpoints.empty()) fail("{}: breakpoints need dt (a step size per interval) or tolerance", tm.where("breakpoints"));
    p.n_steps = tm.integer("steps");
    located(tm.where("steps"), [&] { check_n_steps(p.n_steps); });
  } else if (tm.has("tolerance")) {
    StepControl c;
    c.tolerance = tm.number("tolerance");
    c.dt_initial = tm.number("dt_initial", 0.0);
    c.dt_min = tm.number("dt_min", 0.0);
    c.dt_max = tm.number("dt_max", 0.0);
    c.growth = tm.number("growth", c.growth);
    c.cut = tm.number("cut", c.cut);
    c.safety = tm.number("safety", c.safety);
    c.event_dt = tm.number("event_dt", 0.0);
    c.max_rejections = tm.integer("max_rejections", c.max_rejections);
    if (tm.has("events")) {
      c.contact_events = c.damage_events = false;
      for (const std::string& e : tm.strings("events")) {
        if (e == "contact") c.contact_events = true;
        else if (e == "damage") c.damage_events = true;
        else fail("{}: unknown event {}; expected some of: contact, damage", tm.where("events"), quote(e));
      }
    }
    c.landings = breakpoints;
    located(tm.where_section(), [&] { (void)c.completed(p.final_time); });
    p.step_control = std::move(c);
    p.n_steps = 0;
  } else {
    const toml::node* dt = tm.get("dt");
    if (dt->is_array()) {
      const std::vector<double> k = tm.numbers("dt", 0);
      p.set_fixed_grid(located(tm.where("dt"), [&] {
        return breakpoints.empty() && !tm.has("breakpoints") ? fixed_grid_of_steps(p.final_time, k)
                                                             : fixed_grid_of_intervals(p.final_time, breakpoints, k);
      }));
    } else if (dt->is_string()) {
      if (tm.has("breakpoints")) fail("{}: breakpoints need a list of step sizes in dt", tm.where("breakpoints"));
      const auto k = tm.expression("dt", Expression::Kind::SpaceTime);
      if (k->uses_position()) fail("{}: the step size k(t) is a formula in t only", tm.where("dt"));
      p.set_fixed_grid(located(tm.where("dt"), [&] {
        return fixed_grid_of_formula(p.final_time, [&](double t) { return (*k)({0, 0, 0}, t); });
      }));
    } else {
      const double k = tm.number("dt");
      if (tm.has("breakpoints")) {  // steps of k that end at each breakpoint
        const std::vector<double> each(breakpoints.size() + 1, k);
        p.set_fixed_grid(
            located(tm.where("dt"), [&] { return fixed_grid_of_intervals(p.final_time, breakpoints, each); }));
      } else {
        p.n_steps = located(tm.where("dt"), [&] { return steps_of_time_step(p.final_time, k); });
      }
    }
  }
  tm.finish();
}

// ---------------------------------------------------------------- [output], [solver]

std::vector<std::string> read_fields(Section& out) {
  std::vector<std::string> fields = out.strings("fields");
  for (auto& f : fields) {
    const std::string field = OutputOptions::field(f);  // "damage": the old name of "beta"
    if (field.empty()) {
      const auto& names = OutputOptions::field_names();
      fail("{}: unknown field {}; expected some of: {}{}", out.where("fields"), quote(f), fmt::join(names, ", "),
           did_you_mean(f, std::set<std::string>(names.begin(), names.end())));
    }
    f = field;
  }
  return fields;
}

/// [output] fields may name only fields the case's VTU files can have: a field its files would never
/// hold (VTU files with no array) is refused, located at the key. gap: cases with contact pairs;
/// friction's fields (StateField::friction): a friction law somewhere; contact_lambda: more than
/// one contact unknown per node.
void check_fields_written(Section& out, const std::vector<std::string>& fields, const Problem& p) {
  const bool frictional = p.contact.frictional();
  for (const std::string& f : fields) {
    const auto field = std::ranges::find(state_fields(), f, &StateField::vtu);
    if (f == "gap" && p.contact.pairs.empty())
      fail("{}: the field \"gap\" is written only for cases with contact pairs ([[contact.pair]]); this case has none",
           out.where("fields"));
    if (field != state_fields().end() && field->friction && !frictional)
      fail("{}: the field {} is written only for frictional cases (a friction law in [contact], a [[contact.part]] "
           "or a [[contact.pair]]); this case is frictionless",
           out.where("fields"), quote(f));
    if (f == "contact_lambda" && p.contact.block_size(p.mesh.dim()) == 1)
      fail("{}: the field \"contact_lambda\" is written only where λ has more than one number per contact node "
           "(frictional cases); this case has one, the normal force (see contact_force and contact_pressure)",
           out.where("fields"));
  }
}

std::vector<Point> read_probes(Section& out, int d) {
  std::vector<Point> probes;
  for (const auto& pt : out.array("probes", "an array of points, e.g. [[0.25], [1.0]]")) {
    if (!pt.is_array() || static_cast<int>(pt.as_array()->size()) != d)
      fail("{}: expected each probe to be an array of {} numbers", out.where("probes"), d);
    Point x{0, 0, 0};
    for (int i = 0; i < d; ++i) {
      const toml::node& v = (*pt.as_array())[i];
      if (!v.is_number() || !std::isfinite(number_value(v)))
        fail("{}: expected finite numbers in probe coordinates", out.where("probes"));
      x[i] = number_value(v);
    }
    probes.push_back(x);
  }
  return probes;
}

/// With error-controlled steps, VTU `every` steps of the fixed grid that a tolerance
/// override replaced (the file's steps or dt): the times that grid writes at, so that
/// the run writes as many files as the fixed run. Without such a grid (the file's own
/// steps are error-controlled) the number of steps, and so of files, is not known
/// before the run: refused.
std::vector<double> every_as_times(Section& out, const Problem& p, int every) {
  const Origins& origins = out.origins();
  if (origins.replaced_grid.empty())
    fail("{}: counts the steps of a fixed grid, but [time] tolerance chooses the steps during the run (their number, "
         "and the files', is not known before it): give times = [...] (the steps end at them), or every = 0 (the "
         "final state only)",
         out.where("every"));
  toml::table time = origins.replaced_grid;
  time.insert_or_assign("T", p.final_time);
  if (time.contains("dt") && !p.step_control->landings.empty()) {
    toml::array breakpoints;
    for (double b : p.step_control->landings) breakpoints.push_back(b);
    time.insert_or_assign("breakpoints", breakpoints);
  }
  Problem grid;
  try {
    read_time(Section(&time, "time", origins), grid, origins.file);
  } catch (const Error& e) {
    fail("{}: counts the steps of the fixed grid that {} replaced, which is not valid: {}", out.where("every"),
         origins.of("time.tolerance"), e.what());
  }
  std::vector<double> times;
  for (int n = every; n <= grid.n_steps; n += every) times.push_back(grid.time_at(n));
  return times;
}

/// [output]; by default every tenth of the run.
OutputOptions read_output(Section out, Problem& p) {
  OutputOptions o;
  o.directory = out.string("directory", "");
  if (out.has("every") && out.has("times")) fail("{}: give either every or times, not both", out.where_section());
  // By default every tenth of the run: every N/10 steps, or (error-controlled steps) at t = T/10, 2T/10, …
  const bool controlled = p.step_control.has_value();
  o.every = out.integer("every", controlled ? 0 : std::max(1, p.n_steps / 10));
  if (o.every < 0) fail("{}: expected every >= 0", out.where("every"));
  if (out.has("times")) {
    o.times = out.numbers("times", 0);
    for (double t : o.times)
      if (t < 0 || t > p.final_time) fail("{}: output time {} is outside [0, T = {}]", out.where("times"), t, p.final_time);
  } else if (controlled && !out.has("every")) {
    for (int i = 1; i <= 10; ++i) o.times.push_back(p.final_time * i / 10);
  } else if (controlled && o.every > 0) {
    o.times = every_as_times(out, p, o.every);
    o.every = 0;
  }
  // Error-controlled steps end exactly at the output times.
  if (controlled) p.step_control->landings.insert(p.step_control->landings.end(), o.times.begin(), o.times.end());
  o.vtu = out.boolean("vtu", true);
  if (out.has("fields")) o.fields = read_fields(out);
  check_fields_written(out, o.fields, p);
  o.encoding.compression = vtu_compression(out.choice("compression", {"zlib", "none"}, "zlib"));
  if (out.has("probes")) o.probes = read_probes(out, p.mesh.dim());
  // A probe must lie in the body (on a rank without the mesh: rank 0 checks it; on a block: all ranks
  // together, validate_blocks).
  for (std::size_t i = 0; i < o.probes.size() && p.mesh.n_cells() > 0; ++i) {
    const std::string where = fmt::format("{}[{}]", out.where("probes"), i);
    if (p.block)
      p.block->probes.emplace_back(o.probes[i], where);
    else
      located(where, [&] { (void)locate_point(p.mesh, o.probes[i]); });
  }
  out.finish();
  return o;
}

SolverChoice read_solver(Section sv) {
  SolverChoice s;
  s.contact = sv.choice("contact", kContactSolverNames, kContactSolverNames.front());
  s.damage = sv.choice("damage", {"active-set", "penalty-duality"}, "active-set");
  s.residual_tolerance = sv.positive("tolerance", 1e-8);
  sv.finish();
  return s;
}

/// The TOML text with the overrides applied.
toml::table parse_toml(std::string_view text, const std::vector<KeyOverride>& overrides, Origins& origins) {
  toml::table root;
  try {
    root = toml::parse(text, std::string_view(origins.file));
  } catch (const toml::parse_error& e) {
    fail("{}:{}:{}: invalid TOML: {}", origins.file, e.source().begin.line, e.source().begin.column,
         printable(e.description(), 200));
  }
  apply_overrides(root, overrides, origins);
  return root;
}

/// A value as Case::keys holds it: numbers by value (shortest form that reads back: 1000 and
/// 1000.0 alike), strings in double quotes as given, arrays and inline tables element by element.
std::string key_value(const toml::node& n) {
  if (const auto* v = n.as_integer()) return fmt::format("{}", v->get());
  if (const auto* v = n.as_floating_point()) return fmt::format("{}", v->get());
  if (const auto* v = n.as_boolean()) return v->get() ? "true" : "false";
  if (const auto* v = n.as_string()) return case_key_string(v->get());
  std::string out;
  if (const auto* a = n.as_array()) {
    for (const toml::node& e : *a) out += (out.empty() ? "" : ", ") + key_value(e);
    return "[" + out + "]";
  }
  if (const auto* t = n.as_table()) {
    for (const auto& [k, v] : *t) out += fmt::format("{}{} = {}", out.empty() ? "" : ", ", k.str(), key_value(v));
    return "{" + out + "}";
  }
  std::ostringstream other;  // dates and times
  n.visit([&](auto&& v) { other << v; });
  return other.str();
}

/// Every key of `t` under `prefix` with its value (Case::keys), in the table's order.
void collect_keys(const toml::table& t, const std::string& prefix, CaseKeys& out) {
  for (const auto& [k, v] : t) {
    const std::string key = prefix + std::string(k.str());
    if (const auto* sub = v.as_table()) {
      collect_keys(*sub, key + ".", out);
    } else if (v.is_array_of_tables()) {
      const toml::array& a = *v.as_array();
      for (std::size_t i = 0; i < a.size(); ++i) collect_keys(*a[i].as_table(), fmt::format("{}[{}].", key, i), out);
    } else {
      out.emplace_back(key, key_value(v));
    }
  }
}

/// case.name names the output directory output/<name>: one safe path component
/// (letters, digits, '-', '_', '.'; not "." or ".."), so that no case writes or
/// cleans outside output/. `given`: set by the key (the file's stem otherwise,
/// which is one component already). `where`: the key's location.
void check_case_name(const std::string& name, bool given, const std::string& where) {
  const bool dots = name.empty() || name == "." || name == "..";
  const bool safe = name.size() <= 100 &&
                    std::all_of(name.begin(), name.end(), [](char c) {
                      return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
                    });
  if (dots || (given && !safe))
    fail("{}: expected a name of at most 100 letters, digits, '-', '_' and '.' (not '.' or '..'; it names the output "
         "directory output/<name>), got {}",
         where, given ? quote(name) : "'" + name + "' (the file's stem: give [case] name)");
}

}  // namespace

Case parse_case(std::string_view text, const std::string& name, const fs::path& base_dir,
                const CaseOverrides& overrides, const MeshRequest& mesh_request) {
  Origins origins{name, {}, {}};
  const toml::table root = parse_toml(text, key_overrides(overrides, mesh_request.cells), origins);
  Section top(&root, "", origins);
  Case c;
  Section info = top.table("case");
  c.name = info.string("name", fs::path(name).stem().string());
  check_case_name(c.name, info.has("name"), info.where("name"));
  c.description = info.string("description", "case file " + name);
  const std::string units = info.string("units", "SI");  // for the figures' labels (OutputOptions::units)
  info.finish();

  auto p = std::make_shared<Problem>();
  p->name = c.name;
  const toml::node* contact = root.get("contact");
  const bool pairs = contact && contact->is_table() && contact->as_table()->contains("pair");
  // A block of a generated mesh of one body (MeshRequest::block); otherwise the whole mesh, as
  // without the request. `whole`: this rank holds the whole mesh and checks the case on it.
  MeshRequest request = mesh_request;
  const toml::node* mesh_table = root.get("mesh");
  // A file's mesh by blocks only when refined (`refine`; a value that is not a count is refused by read_mesh).
  const bool refined_file = mesh_table && mesh_table->is_table() && mesh_table->as_table()->contains("file") &&
                            (*mesh_table->as_table())["refine"].value<std::int64_t>().value_or(0) > 0;
  if (request.block && (pairs || root.contains("body") || !mesh_table || !mesh_table->is_table() ||
                        (mesh_table->as_table()->contains("file") && !refined_file)))
    request.block.reset();
  const bool whole = request.build && !request.block;
  p->mesh = read_mesh(top.table("mesh"), base_dir, origins, request, overrides.memory_limit, &p->block);
  std::vector<Section> bodies = read_body_meshes(top, *p, base_dir, origins, request, overrides.memory_limit);
  read_boundary(top.table("boundary"), *p, origins, whole, pairs);
  p->elasticity = read_elasticity(top.table("elasticity"), p->mesh.dim(), name);
  p->law = read_viscoplasticity(top.table("viscoplasticity"), p->elasticity.young());
  read_damage(top.table("damage"), *p);
  read_body_data(bodies, *p);
  read_materials(top, *p, origins, whole);
  read_loads(top.table("loads"), *p, origins, whole);
  read_obstacles(top, *p, origins, read_contact(top.table("contact"), *p, origins));
  read_time(top.table("time"), *p, name);
  c.output = read_output(top.table("output"), *p);
  c.output.units = units;
  c.solvers = read_solver(top.table("solver"));
  top.finish();
  record_key_locations(top, *p, origins);
  if (mesh_request.build) c.warnings = locking_warnings(top, *p);  // once, by the rank that reports
  p->formulas = *origins.formulas;
  // Without the mesh (a rank that did not build it): validated by the rank that has it; a
  // block: by all ranks together (validate_blocks, parallel/block_part.hpp).
  // A message that names a key of the file has its location already.
  if (whole) validate_case(*p, name);
  if (p->block) p->block->source = name;
  c.problem = std::move(p);
  collect_keys(root, "", c.keys);
  return c;
}

void validate_case(const Problem& p, const std::string& name) {
  try {
    p.validate();
  } catch (const Error& e) {
    if (std::string_view(e.what()).starts_with(name + ":")) throw;
    throw Error(name + ": " + e.what());
  }
}

std::string case_description(std::string_view text) {
  try {
    const toml::table t = toml::parse(text);
    return t["case"]["description"].value_or(std::string());
  } catch (const toml::parse_error&) {
    return {};
  }
}

CaseInfo case_info(std::string_view text, const std::string& name, const CaseOverrides& overrides) {
  CaseInfo info{fs::path(name).stem().string(), "case file " + name, ""};
  std::string name_where;  // where an explicit case.name is given
  try {
    Origins origins{name, {}, {}};
    const toml::table t = parse_toml(text, key_overrides(overrides, std::nullopt), origins);
    info.name = t["case"]["name"].value_or(info.name);
    info.description = t["case"]["description"].value_or(info.description);
    info.output_directory = t["output"]["directory"].value_or(std::string());
    if (const toml::node* n = t["case"]["name"].node(); n && n->is_string())
      name_where = n->source().begin.line > 0 ? location(*n, name) + ": case.name" : origins.of("case.name");
  } catch (const std::exception&) {
    // parse_case reports it, with the line and column
  }
  // Before the output directory output/<name> is made (and cleaned): here, not in parse_case only.
  check_case_name(info.name, !name_where.empty(), name_where.empty() ? name : name_where);
  return info;
}

std::string read_text_file(const fs::path& file, std::string_view what) {
  // Opened without blocking, and refused unless regular: a FIFO would wait for a writer for ever.
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  require(fd >= 0, "cannot read {} '{}': {}", what, file.string(), std::strerror(errno));
  struct stat st {};
  const bool stat_ok = ::fstat(fd, &st) == 0;
  const int mode = stat_ok ? static_cast<int>(st.st_mode & S_IFMT) : 0;
  if (!stat_ok || mode != S_IFREG) {
    ::close(fd);
    const char* kind = mode == S_IFIFO ? "a named pipe (FIFO)" : mode == S_IFDIR ? "a directory"
                       : mode == S_IFCHR ? "a character device" : mode == S_IFBLK ? "a block device"
                       : mode == S_IFSOCK ? "a socket" : "not a regular file";
    fail("cannot read {} '{}': it is {}; expected a regular file", what, file.string(), kind);
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string text;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      fail("cannot read {} '{}': {}", what, file.string(), std::strerror(err));
    }
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return text;
}

Case read_case_file(const fs::path& file, const CaseOverrides& overrides, const MeshRequest& mesh) {
  return parse_case(read_text_file(file, "case file"), file.string(), file.parent_path(), overrides, mesh);
}

}  // namespace vpc
