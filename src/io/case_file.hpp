#pragma once
// Case files (TOML): every part of the model of SPEC §1 and how to run it.
// docs/cases.md documents every key. Errors name the file, line and column, the
// key and what was expected; unknown keys are errors with a "did you mean".
#include "io/case.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace vpc {

/// Changes to a case's keys before it is read, from the command line: each is
/// checked as the file's own value would be, and errors name the option.
struct CaseOverrides {
  std::vector<std::string> sets{};   // --set key.path=value (the value in TOML syntax; a bare word is a string)
  std::optional<double> kappa{};     // --kappa: damage.kappa
  std::optional<int> steps{};        // --steps: time.steps
  std::optional<double> time_step{}; // --dt: time.dt
  std::optional<int> every{};        // --every: output.every
  std::string memory_limit{};        // --memory-limit: also what meshing a .geo may take, unless [mesh] memory_limit
};

/// Reads a case file; `overrides` are applied before validation. `mesh` says
/// whether the mesh is built and its cells per edge (--n; see MeshRequest).
Case read_case_file(const std::filesystem::path& file, const CaseOverrides& overrides = {},
                    const MeshRequest& mesh = {});

/// Parses a case from TOML text; `name` stands for the file in messages and
/// relative paths (meshes) are resolved against `base_dir`.
Case parse_case(std::string_view text, const std::string& name, const std::filesystem::path& base_dir,
                const CaseOverrides& overrides = {}, const MeshRequest& mesh = {});

/// What a case says about itself, read without building anything (no mesh):
/// vpcontact prints the header and checks the output directory before set-up.
/// Invalid text gives the defaults (parse_case reports the error).
struct CaseInfo {
  std::string name, description;
  std::string output_directory;  // [output] directory; empty: the default
};
CaseInfo case_info(std::string_view text, const std::string& name, const CaseOverrides& overrides = {});

/// A file's whole text; throws vpc::Error naming `what`, the file and the OS's reason.
std::string read_text_file(const std::filesystem::path& file, std::string_view what);

/// The [case] description of a case file's text, without reading the rest
/// (no meshing); empty if there is none or the text is not valid TOML.
std::string case_description(std::string_view text);

/// Problem::validate, its error located in the case file `name` (as parse_case reports it); returns
/// the contact rows its checks built.
ContactRows validate_case(const Problem& p, const std::string& name);

}  // namespace vpc
