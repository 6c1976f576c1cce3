#pragma once
// Case files (TOML): every part of the model of SPEC §1 and how to run it.
// docs/cases.md documents every key. Errors name the file, line and column, the
// key and what was expected; unknown keys are errors with a "did you mean".
#include "cases/case.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace vpc {

/// Reads a case file. `overrides` are "key.path=value" strings (the value in
/// TOML syntax; a bare word is taken as a string) applied before validation,
/// as `vpcontact run CASE --set key=value`.
/// `mesh` says whether the mesh is built (see MeshRequest).
Case read_case_file(const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                    const MeshRequest& mesh = {});

/// Parses a case from TOML text; `name` stands for the file in messages and
/// relative paths (meshes) are resolved against `base_dir`.
Case parse_case(std::string_view text, const std::string& name, const std::filesystem::path& base_dir,
                const std::vector<std::string>& overrides = {}, const MeshRequest& mesh = {});

/// What a case says about itself, read without building anything (no mesh):
/// vpcontact prints the header and checks the output directory before set-up.
/// Invalid text gives the defaults (parse_case reports the error).
struct CaseInfo {
  std::string name, description;
  std::string output_directory;  // [output] directory; empty: the default
};
CaseInfo case_info(std::string_view text, const std::string& name, const std::vector<std::string>& overrides = {});

/// A file's whole text; throws vpc::Error naming `what`, the file and the OS's reason.
std::string read_text_file(const std::filesystem::path& file, std::string_view what);

/// The [case] description of a case file's text, without reading the rest
/// (no meshing); empty if there is none or the text is not valid TOML.
std::string case_description(std::string_view text);

}  // namespace vpc
