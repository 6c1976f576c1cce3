#pragma once
// The case file's sections, each read in its own file, in the order parse_case calls them
// (io/case_file.cpp): the keys of a section are read where its object is built. Internal to
// io/: the rest of the program sees io/case_file.hpp. Every message names the file, line,
// column and key path (io/case_section.hpp); docs/cases.md documents every key.
//
// They stay in io/ (not next to the objects they build, in mesh/, material/, contact/ or
// scheme/): a Section is TOML, which only io/ knows, and those modules sit below io/ in the
// module graph (scripts/module_graph.py); the laws' own keys are read by the laws through
// LawKeys (contact/contact_law.hpp) and Parameters (material/parameters.hpp) instead.
#include "adapt/adapt_spec.hpp"
#include "io/case_section.hpp"
#include "problem/problem.hpp"

#include <fmt/ranges.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vpc {
// Only named here (io/case_file.hpp, io/case.hpp, io/run_output.hpp, scheme/solver_choice.hpp),
// so that a section's file compiles only the headers it needs.
struct CaseOverrides;
struct MeshRequest;
struct OutputOptions;
struct SolverChoice;
}  // namespace vpc

namespace vpc::case_file {

// ------------------------------------------------ the command line's overrides (case_overrides.cpp)

/// One key set from the command line.
struct KeyOverride {
  std::vector<std::string> key;  // its path, e.g. {"time", "steps"}
  std::string value;             // TOML; a bare word is taken as a string
  std::string origin;            // for messages: "--set time.steps=50", "--steps 50"
  bool generated_mesh_only = false;  // --n: refused for a mesh file
  std::string key_path() const { return fmt::format("{}", fmt::join(key, ".")); }
};

/// The overrides in the order they apply: --set, then --n, --kappa, --steps, --dt.
std::vector<KeyOverride> key_overrides(const CaseOverrides& o, std::optional<int> cells);

/// Applies the overrides to the parsed table and records their origins. A key that
/// excludes one of the file's (exclusive_keys) replaces it; two overrides that
/// exclude each other are an error.
void apply_overrides(toml::table& root, const std::vector<KeyOverride>& overrides, Origins& origins);

// ------------------------------------------------ [mesh], [[body]] meshes (case_mesh.cpp)

/// [mesh], built, or an empty mesh of the requested dimension (a rank that does not build it),
/// or with a block request (only for a generator: parse_case) the rank's block into `*block`.
Mesh read_mesh(Section m, const std::filesystem::path& base_dir, const Origins& origins, const MeshRequest& request,
               const std::string& memory_limit_option, std::shared_ptr<MeshBlock>* block = nullptr);

/// [[body]] (SPEC §8): each further body's name and [body.mesh] (as [mesh]), appended to
/// p.mesh. Returns the bodies' sections, whose other tables read_body_data reads.
std::vector<Section> read_body_meshes(Section& top, Problem& p, const std::filesystem::path& base_dir,
                                      const Origins& origins, const MeshRequest& request,
                                      const std::string& memory_limit_option);

// ------------------------------------------------ [boundary], [loads] (case_boundary.cpp)

/// The field x, t -> (e[0](x, t), ..., e[d-1](x, t)).
VectorField vector_field(std::vector<std::shared_ptr<const Expression>> e);

/// `pairs`: the case has [[contact.pair]]s, and Γ3 (`contact`) may then be left out.
void read_boundary(Section b, Problem& p, const Origins& origins, bool check, bool pairs, bool held_by_bond = false);
/// [loads]: f0, f2 and [[loads.pressure]].
void read_loads(Section l, Problem& p, const Origins& origins, bool check);

// ------------------------------------------------ materials (case_material.cpp)

Elasticity read_elasticity(Section e, int d, const std::string& file);
/// [viscoplasticity]: G, named, with its parameters (Perzyna's E defaults to ℰ's).
std::shared_ptr<const ViscoplasticLaw> read_viscoplasticity(Section v, double young);
/// [damage]: κ, β0 and the source φ.
void read_damage(Section dm, Problem& p);
/// [[material]]: further materials on regions or on the cells a predicate selects.
void read_materials(Section& top, Problem& p, const Origins& origins, bool build);
/// The [[body]] tables' [body.elasticity], [body.viscoplasticity] and [body.damage].
void read_body_data(std::vector<Section>& sections, Problem& p);
/// Warnings for ν near 1/2 with P1 elements (volumetric locking), each naming its key.
std::vector<std::string> locking_warnings(Section& top, const Problem& p);

// ------------------------------------------------ [contact], [[obstacle]] (case_contact.cpp)

/// [contact] with [[contact.part]] and [[contact.pair]]; returns whether a gap was given.
bool read_contact(Section ct, Problem& p, const Origins& origins);
/// [[obstacle]] sections (instead of [contact] gap).
void read_obstacles(Section& top, Problem& p, const Origins& origins, bool gap_given);

// ------------------------------------------------ [time] (case_time.cpp)

/// The keys of [time] that only error-controlled steps (`tolerance`) take.
const std::vector<std::string>& step_control_keys();
/// [time]: T and one of steps, dt (a size, a list or a formula in t) and tolerance.
void read_time(Section tm, Problem& p, const std::string& file);

// ------------------------------------------------ [output], [solver] (case_output.cpp)

/// [output]; by default every tenth of the run.
OutputOptions read_output(Section out, Problem& p);
SolverChoice read_solver(Section sv);

// ------------------------------------------------ [adapt] (case_adapt.cpp)

/// [adapt]: mesh adaptivity (nullopt without the section); refused, located, for a problem that
/// cannot be adapted (check_adaptable, adapt/mesh_adaptivity.hpp).
std::optional<AdaptSpec> read_adapt(Section a, const Problem& p);

}  // namespace vpc::case_file
