// The command line's changes to a case's keys (--set, --n, --kappa, --steps, --dt, --every),
// applied to the parsed TOML before any section is read: each value is then checked as the
// file's own would be, its messages naming the option (Origins).
#include "io/case_readers.hpp"

#include "io/case_file.hpp"
#include "contact/friction_law.hpp"
#include "contact/adhesion_law.hpp"
#include "contact/wear_law.hpp"
#include "core/error.hpp"
#include "core/quote.hpp"
#include "material/damage_source.hpp"
#include "material/viscoplastic_law.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <sstream>

namespace vpc::case_file {

namespace {

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

/// The parameters that a change of law, damage source, friction law or wear drops: those of the old
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
  } else if ((last == "contact" || last.starts_with("part[") || last.starts_with("pair[")) && key == "wear") {
    parameters = wear_law_keys;  // `--set contact.wear=none` drops wear_coefficient
    old_name = t["wear"].value_or(std::string("none"));
  } else if ((last == "contact" || last.starts_with("part[") || last.starts_with("pair[")) && key == "adhesion") {
    parameters = adhesion_law_keys;  // `--set contact.adhesion=none` drops bond_stiffness, ...
    old_name = t["adhesion"].value_or(std::string("none"));
  }
  const auto new_name = value.value<std::string>();
  if (!parameters || !new_name || *new_name == old_name) return {};
  const auto kept = parameters(*new_name);
  std::vector<std::string> out;
  for (const auto& p : parameters(old_name))
    if (std::find(kept.begin(), kept.end(), p) == kept.end() && t.contains(p)) out.push_back(p);
  return out;
}

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

}  // namespace

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

namespace {

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

}  // namespace

void apply_overrides(toml::table& root, const std::vector<KeyOverride>& overrides, Origins& origins) {
  for (const auto& ov : overrides) {
    check_generated_cells(root, ov, origins.file);
    const toml::table value = override_value(ov);
    apply_value(root, ov, ov.key, *value.get("v"), origins);
  }
}

}  // namespace vpc::case_file
