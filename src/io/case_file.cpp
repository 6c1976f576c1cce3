// Case files: parse_case reads the TOML (the command line's overrides applied), then the sections
// in their order (the mesh first: the other sections' checks need it; [contact] before
// [[obstacle]]; [time] before [output]). Each section's keys are read in a file of its own
// (io/case_readers.hpp), with the shared machinery of io/case_section.hpp.
#include "io/case_file.hpp"
#include "io/case_readers.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace vpc {

namespace {

namespace fs = std::filesystem;
using namespace case_file;

/// Where the keys are that Problem::validate's checks across keys name (Problem::where).
void record_key_locations(Section& top, Problem& p, const Origins& origins) {
  auto record = [&](Section& s, const std::string& key) {
    if (s.has(key)) p.key_locations[s.key_path(key)] = s.where(key);
  };
  // [[key]]: each table's header, and its `keys` where given.
  auto record_tables = [&](Section& s, const std::string& key, const std::vector<std::string>& keys = {}) {
    if (!s.has(key) || !s.get(key)->is_array_of_tables()) return;
    int k = 0;
    for (const auto& node : *s.get(key)->as_array()) {
      const std::string path = fmt::format("{}[{}]", s.key_path(key), k++);
      Section table(node.as_table(), path, origins);
      p.key_locations[path] = fmt::format("{}: {}", table.where_section(), path);
      for (const std::string& name : keys) record(table, name);
    }
  };
  Section b = top.table("boundary");
  if (b.exists()) p.key_locations["boundary"] = fmt::format("{}: [boundary]", b.where_section());
  for (const char* key : {"contact", "clamped", "symmetry"}) record(b, key);
  record_tables(b, "displacement");
  Section ct = top.table("contact");
  if (ct.exists()) p.key_locations["contact"] = fmt::format("{}: [contact]", ct.where_section());
  for (const char* key : {"gap", "direction", "friction", "mu", "shear_limit", "friction_bound"}) record(ct, key);
  // The wear keys of each law table (the surface laws' messages: surface_fields.cpp, contact_set.cpp).
  std::vector<std::string> law_keys = wear_keys();  // and the adhesion keys
  for (const std::string& key : adhesion_keys()) law_keys.push_back(key);
  for (const std::string& key : law_keys) record(ct, key);
  record_tables(ct, "pair", law_keys);
  record_tables(ct, "part", law_keys);
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
  // [contact] held_by_bond: the bonds may hold a body that nothing clamps (read again, checked, there).
  const toml::node* contact_table = root.get("contact");
  // (a value that is not a boolean counts here, so that [contact]'s reader names the key, not a missing Γ1)
  const toml::node* held = contact_table && contact_table->is_table() ? contact_table->as_table()->get("held_by_bond") : nullptr;
  const bool held_by_bond = held && (!held->is_boolean() || held->value<bool>().value_or(false));
  read_boundary(top.table("boundary"), *p, origins, whole, pairs, held_by_bond);
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
  c.adapt = read_adapt(top.table("adapt"), *p);
  top.finish();
  record_key_locations(top, *p, origins);
  if (mesh_request.build) c.warnings = locking_warnings(top, *p);  // once, by the rank that reports
  p->formulas = *origins.formulas;
  // Without the mesh (a rank that did not build it): validated by the rank that has it; a
  // block: by all ranks together (validate_blocks, parallel/block_part.hpp).
  // A message that names a key of the file has its location already.
  if (whole) c.contact_rows = validate_case(*p, name);
  if (p->block) p->block->source = name;
  c.problem = std::move(p);
  collect_keys(root, "", c.keys);
  return c;
}

ContactRows validate_case(const Problem& p, const std::string& name) {
  try {
    return p.validate();
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
