#pragma once
// history.csv's columns, declared once: each column's name, meaning, how it is written
// and where its number comes from in a step's report. The file's header and rows
// (io/run_output.cpp) and Python's step reports (python/src/simulation.cpp, as numbers)
// are made from this table, and docs/cases.md's list of the columns is checked against it
// (tests/unit/io/test_history_columns.cpp): a new column is one entry.
#include "scheme/time_stepper.hpp"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace vpc {

/// How a column's numbers are written: a whole number; exactly (17 significant
/// digits, read back bit for bit); a residual (4 significant digits).
enum class ColumnFormat { integer, exact, residual };

struct HistoryColumn {
  std::string_view name;
  ColumnFormat format;
  double (*value)(const StepReport&);  // integers exactly (counts < 2^53)
  std::string_view meaning;            // for docs/cases.md and Python
};

/// The columns every run has, in order.
std::span<const HistoryColumn> history_columns();
/// The columns of a frictional run (contact block > 1), after the per-case ones below.
std::span<const HistoryColumn> friction_columns();
/// After friction_columns, in a run with a bound that acts out of contact (Tresca;
/// FrictionLaw::acts_out_of_contact): n_tresca_open.
std::span<const HistoryColumn> open_friction_columns();
/// Last, in a run with mesh adaptivity ([adapt]).
std::span<const HistoryColumn> adapt_columns();

/// After history_columns, per case (totals over the case's nodes, never per contact node):
/// the force on each obstacle (force_<name>, Problem::contact.obstacles order), then the
/// reaction of each Dirichlet part (dirichlet_parts) in each component it prescribes
/// (reaction_<part>_<x|y|z>; MeshPart::dirichlet_components: every process has them), then
/// ∫_Γ3 of each contact law's per-node state variable that names a column (SurfaceVariable::history).
/// With friction (only: a frictionless run's file is that of before) then
/// friction_columns, the total tangential force (tangential_force_<x|y|z>, d components),
/// that on each obstacle (tangential_force_<name>_<x|y|z>) and, with [[contact.part]]
/// sections, the normal and tangential force of each law entry (force_part_<entry>,
/// tangential_force_part_<entry>_<x|y|z>; contact_law_entry_names).
/// Last, in a run with mesh adaptivity (`adaptive`): cells, unknowns, adaptations (StepReport::mesh_cells).
std::vector<std::string> history_column_names(const Problem& p, const MeshPart& part, bool adaptive = false);

/// The names of ContactSpec::laws()' entries in history.csv: their parts joined by '+'
/// ([contact]'s: the contact parts no [[contact.part]] names; "none" where there are none).
std::vector<std::string> contact_law_entry_names(const ContactSpec& c);

/// One number of a row and how it is written.
struct HistoryValue {
  double value = 0;
  ColumnFormat format = ColumnFormat::exact;
  /// As history.csv writes it.
  std::string text() const;
};

/// A step's numbers, in the order of history_column_names.
std::vector<HistoryValue> history_values(const StepReport& r);

}  // namespace vpc
