#pragma once
// A case: a Problem plus how to run it (solvers) and what to write (output).
// Case files produce one (the built-in cases are case files compiled in).
#include "adapt/adapt_spec.hpp"
#include "io/run_output.hpp"
#include "problem/problem.hpp"
#include "scheme/time_stepper.hpp"

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vpc {

/// Every key of a case as read (the file with the command line's overrides applied), each
/// "section.key" (the i-th table of an array of tables: "obstacle[0].radius") with its value in
/// one form (numbers by value: 1000 and 1000.0 alike; strings in double quotes, as given;
/// arrays element by element). What a checkpoint records of its case, so that
/// --resume compares the case key by key (io/checkpoint.hpp: case_changes).
using CaseKeys = std::vector<std::pair<std::string, std::string>>;

/// A string value as CaseKeys holds it.
inline std::string case_key_string(std::string_view s) { return '"' + std::string(s) + '"'; }

/// Whether a case's mesh is built. A rank > 0 of a distributed run does not build
/// it: it receives its part from rank 0 (docs/parallel.md), so no rank but the one
/// that reads it ever holds the whole mesh. Its problem's mesh is then an empty mesh
/// of dimension `dim` (found by rank 0), and the checks that need the mesh (parts
/// exist, β0 and g at the nodes) are rank 0's.
struct MeshRequest {
  bool build = true;
  int dim = 0;
  std::optional<int> cells;  // `--n`: cells per edge of a generated mesh (unset: the case's own),
                             // checked by the case file's mesh.cells rules
  /// Under MPI: build rank `rank`'s block of a generated mesh of one body, of `ranks` blocks
  /// (Problem::block), whether or not `build`; a mesh read from a file, or of several bodies or
  /// with contact pairs, is built as without it (issue 30).
  struct Block {
    int rank = 0, ranks = 1;
  };
  std::optional<Block> block = std::nullopt;
  /// With `block`, a refined file's mesh as rank 0 read it (mesh_bytes, sent by the engine): taken
  /// instead of reading the file, so that the file is read and a .geo meshed once.
  std::shared_ptr<const Mesh> coarse = nullptr;
};

struct Case {
  std::string name;
  std::string description;
  std::shared_ptr<Problem> problem;
  /// The problem's contact rows on its whole mesh, built by its validation as it was read
  /// (Problem::validate) and taken by its set-up (the solver plan, the cut into parts); null
  /// where it was not validated here (a rank without the mesh, a block: validate_blocks). Built
  /// from the problem as read: a caller that changes its mesh, boundary or contact data resets them.
  ContactRows contact_rows;
  OutputOptions output;  // an empty directory means output/<name>
  SolverChoice solvers;
  /// [adapt]: mesh adaptivity during the run (nullopt: the mesh stays as read).
  std::optional<AdaptSpec> adapt;
  /// Lines the program prints as warnings: data that is valid but likely to give a poor
  /// answer (ν near 1/2 with P1 elements), each located in the case file.
  std::vector<std::string> warnings;
  /// The case's keys as read (empty for a case made in code).
  CaseKeys keys;
};

}  // namespace vpc
