#pragma once
// The built-in cases are the case files cases/*.toml, compiled into the program
// (shipped_cases.hpp); this finds one by name, or reads a case file.
#include "io/case_file.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace vpc {

std::vector<std::string> builtin_case_names();

/// A case's TOML before anything is built: a case file's, or a built-in case's
/// compiled-in text (whose meshes are found in the source tree's cases/).
struct CaseSource {
  std::string text;
  std::string name;                // for messages: the file, or "NAME.toml (built-in)"
  std::filesystem::path base_dir;  // where its meshes are found
  bool builtin = false;
};

/// Whether `s` names a case file rather than a built-in case: a name ending in
/// .toml, or an existing file.
bool is_case_file(const std::string& s);

/// The source of `name_or_file`; throws vpc::Error for an unknown built-in case,
/// listing them.
CaseSource case_source(const std::string& name_or_file);

/// Reads a case with command-line overrides (parse_case).
Case load_case(const CaseSource& source, const CaseOverrides& overrides = {}, const MeshRequest& mesh = {});
Case load_case(const std::string& name_or_file, const CaseOverrides& overrides = {}, const MeshRequest& mesh = {});

}  // namespace vpc
