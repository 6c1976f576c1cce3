// The case file's reading machinery (io/case_section.hpp): located, typed keys.
#include "io/case_section.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace vpc::case_file {

namespace {

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

}  // namespace

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


std::string Section::where(const std::string& k) {
  const toml::node* n = get(k);
  if (n && n->source().begin.line == 0) return origins_.of(key_path(k));
  if (n) return fmt::format("{}: {}", location(*n, file_), printable(key_path(k)));
  return where_section() + ": " + printable(key_path(k));
}

std::string Section::where_section() const {
  if (t_ && t_->source().begin.line > 0) return location(*t_, file_);
  return file_;
}

void Section::expected(const std::string& k, const std::string& what) {
  const toml::node* n = get(k);
  if (!n) fail("{}: missing key '{}': expected {}", where_section(), key_path(k), what);
  fail("{}: expected {}, got {}", where(k), what, type_name(*n));
}

double Section::number(const std::string& k) {
  const toml::node* n = get(k);
  if (!n || !n->is_number()) expected(k, "a number");
  const double v = number_value(*n);
  if (!std::isfinite(v)) fail("{}: expected a finite number, got {}", where(k), v);
  return v;
}

double Section::positive(const std::string& k, double fallback) {
  const double v = number(k, fallback);
  if (!(v > 0)) fail("{}: expected a number > 0, got {}", where(k), v);
  return v;
}

int Section::integer(const std::string& k) {
  const toml::node* n = get(k);
  if (!n || !n->is_integer()) expected(k, "an integer");
  const int64_t v = *n->value<int64_t>();
  if (v < -(1 << 30) || v > (1 << 30))
    fail("{}: expected an integer between -{} and {}, got {}", where(k), 1 << 30, 1 << 30, v);
  return static_cast<int>(v);
}

std::string Section::string(const std::string& k) {
  const toml::node* n = get(k);
  if (!n || !n->is_string()) expected(k, "a string");
  return *n->value<std::string>();
}

std::string Section::choice(const std::string& k, const std::vector<std::string>& options, const std::string& fallback) {
  if (!has(k) && !fallback.empty()) return fallback;
  const std::string v = string(k);
  if (std::find(options.begin(), options.end(), v) == options.end()) {
    const std::set<std::string> known(options.begin(), options.end());
    fail("{}: unknown value {}; expected one of: {}{}", where(k), quote(v), fmt::join(options, ", "), did_you_mean(v, known));
  }
  return v;
}

bool Section::boolean(const std::string& k, bool fallback) {
  const toml::node* n = get(k);
  if (!n) return fallback;
  if (!n->is_boolean()) expected(k, "true or false");
  return *n->value<bool>();
}

const toml::array& Section::array(const std::string& k, const std::string& what) {
  const toml::node* n = get(k);
  if (!n || !n->is_array()) expected(k, what);
  return *n->as_array();
}

std::vector<std::string> Section::strings(const std::string& k) {
  const toml::node* n = get(k);
  if (n && n->is_string()) return {*n->value<std::string>()};
  std::vector<std::string> out;
  for (const auto& e : array(k, "a string or an array of strings")) {
    if (!e.is_string()) fail("{}: expected an array of strings, got an element that is {}", where(k), type_name(e));
    out.push_back(*e.value<std::string>());
  }
  return out;
}

std::vector<double> Section::numbers(const std::string& k, size_t size) {
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

std::shared_ptr<const Expression> Section::expression(const std::string& k, Expression::Kind kind) {
  const toml::node* n = get(k);
  if (n && n->is_number()) return std::make_shared<Expression>(fmt::format("{:.17g}", number(k)), kind, where(k));
  if (!n || !n->is_string()) expected(k, "a formula (a string such as \"-10*t\") or a number");
  return std::make_shared<Expression>(*n->value<std::string>(), kind, where(k));
}

std::shared_ptr<const Expression> Section::state_expression(const std::string& k, Expression::Kind kind) {
  auto e = expression(k, kind);
  origins_.formulas->push_back(e);
  return e;
}

std::vector<std::shared_ptr<const Expression>> Section::state_expressions(const std::string& k, int d,
                                                                         Expression::Kind kind) {
  auto e = expressions(k, d, kind);
  origins_.formulas->insert(origins_.formulas->end(), e.begin(), e.end());
  return e;
}

std::vector<std::shared_ptr<const Expression>> Section::expressions(const std::string& k, int d, Expression::Kind kind) {
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

Section Section::table(const std::string& k) {
  const toml::node* n = get(k);
  if (n && !n->is_table()) expected(k, "a table");
  return Section(n ? n->as_table() : nullptr, key_path(k), origins_);
}

void Section::finish() const {
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

std::vector<std::string> Section::remaining() const {
  std::vector<std::string> out;
  if (!t_) return out;
  for (const auto& [key, node] : *t_)
    if (!known_.count(std::string(key.str()))) out.emplace_back(key.str());
  return out;
}

}  // namespace vpc::case_file
