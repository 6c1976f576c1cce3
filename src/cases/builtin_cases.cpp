#include "cases/builtin_cases.hpp"

#include "cases/shipped_cases.hpp"
#include "core/error.hpp"
#include "core/quote.hpp"

#include <fmt/ranges.h>

#include <algorithm>

namespace vpc {

std::vector<std::string> builtin_case_names() {
  std::vector<std::string> names;
  for (const auto& s : shipped_cases()) names.emplace_back(s.name);
  return names;
}

bool is_case_file(const std::string& s) {
  return s.size() > 5 && (s.ends_with(".toml") || std::filesystem::is_regular_file(s));
}

CaseSource case_source(const std::string& name_or_file) {
  if (is_case_file(name_or_file))
    return {read_text_file(name_or_file, "case file"), name_or_file,
            std::filesystem::path(name_or_file).parent_path(), false};
  const auto& shipped = shipped_cases();
  const auto it = std::find_if(shipped.begin(), shipped.end(), [&](const auto& s) { return s.name == name_or_file; });
  if (it == shipped.end())
    fail("unknown case {}; built-in cases are: {} (or give a case file, NAME.toml)", quote(name_or_file),
         fmt::join(builtin_case_names(), ", "));
  return {std::string(it->text), std::string(it->name) + ".toml (built-in)", VPC_CASES_DIR, true};
}

Case load_case(const CaseSource& source, const CaseOverrides& overrides, const MeshRequest& mesh) {
  return parse_case(source.text, source.name, source.base_dir, overrides, mesh);
}

Case load_case(const std::string& name_or_file, const CaseOverrides& overrides, const MeshRequest& mesh) {
  return load_case(case_source(name_or_file), overrides, mesh);
}

}  // namespace vpc
