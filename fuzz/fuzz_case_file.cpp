// Fuzz target: the case-file parser, vpc::parse_case (TOML text -> Case).
//
// The input is a case file. Its comment lines "#set key=value" are also given
// as --set overrides, so that the override syntax is fuzzed too. The case file
// may use the mesh file "m.msh" (a small 2D mesh with parts "contact" and
// "clamped") in the folder it is read from.
//
// A vpc::Error is a correct rejection. Anything else escaping (another
// exception), a crash, a hang, a leak or a sanitizer report is a bug.
//
// Inputs that are valid but slow are skipped (not bugs): generated meshes of
// more than kMaxFuzzCells cells (still below the parser's own limit, which
// rejects larger ones at once and is fuzzed), and, for safety, mesh files other
// than a plain "NAME.msh" in the scratch folder: Gmsh runs a .geo file (or any
// file it does not recognise) as a script, which can exit or run commands.
#include "core/error.hpp"
#include "fuzz_common.hpp"
#include "io/case_file.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace {

constexpr double kMaxFuzzCells = 20000;
constexpr double kParserCellLimit = 1e7;  // src/io/case_file.cpp

const char* kMesh = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 "contact"
1 2 "clamped"
2 3 "body"
$EndPhysicalNames
$Nodes
4
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
4
1 1 2 1 1 1 2
2 1 2 2 3 3 4
3 2 2 3 1 1 2 3
4 2 2 3 1 1 3 4
$EndElements
)";

const std::filesystem::path& case_dir() {
  static const std::filesystem::path dir = [] {
    const auto d = vpc::fuzz::scratch_dir();
    std::ofstream(d / "m.msh") << kMesh;
    return d;
  }();
  return dir;
}

/// The "#set key=value" comment lines, as --set overrides; those touching the
/// mesh are dropped (the checks below see the file's mesh only).
std::vector<std::string> overrides(std::string_view text) {
  std::vector<std::string> out;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(pos, end - pos);
    if (line.substr(0, 5) == "#set ") {
      std::string o(line.substr(5));
      if (o.substr(0, o.find('=')).find("mesh") == std::string::npos) out.push_back(o);
    }
    pos = end + 1;
  }
  return out;
}

/// Whether parsing this case would be safe and fast enough to fuzz (see top).
bool worth_parsing(std::string_view text) {
  toml::table root;
  try {
    root = toml::parse(text);
  } catch (const toml::parse_error&) {
    return true;  // rejected by the parser at once
  }
  const toml::node_view<toml::node> mesh = root["mesh"];
  if (const toml::node* file = mesh["file"].node(); file && file->is_string()) {
    const std::string f = *file->value<std::string>();
    if (f.find('/') != std::string::npos || f.size() < 5 || f.substr(f.size() - 4) != ".msh") return false;
  }
  const std::string gen = mesh["generator"].value_or(std::string());
  const int d = gen == "rectangle" ? 2 : (gen == "box" ? 3 : 1);
  const toml::node* cells = mesh["cells"].node();
  if (!cells) return true;
  double total = 1;
  if (cells->is_integer()) {
    for (int a = 0; a < d; ++a) total *= static_cast<double>(*cells->value_exact<int64_t>());
  } else if (const toml::array* a = cells->as_array()) {
    for (const auto& e : *a)
      if (e.is_number()) total *= std::abs(e.is_integer() ? static_cast<double>(*e.value_exact<int64_t>())
                                                          : *e.value_exact<double>());
  }
  total = std::abs(total) * (d == 3 ? 6 : d);
  return !(total > kMaxFuzzCells && total <= kParserCellLimit);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (!worth_parsing(text)) return -1;  // not added to the corpus
  try {
    const vpc::Case c = vpc::parse_case(text, "fuzz.toml", case_dir(), {.sets = overrides(text)});
    // The data that is evaluated only when a run starts.
    const vpc::Problem& p = *c.problem;
    const vpc::Point x = p.mesh.node(0);
    if (p.f0) (void)p.f0(x, p.final_time);
    if (p.f2) (void)p.f2(x, p.final_time);
  } catch (const vpc::Error&) {
  }
  return 0;
}
