#pragma once
// The state's fields, declared once: each array of State (scheme/state.hpp) and each
// output field made from them, with where it lives (nodes, cells or contact nodes) and
// how many numbers it has there. The checkpoints (io/checkpoint.cpp), the VTU files
// (io/run_output.cpp), the [output] fields a case may name and the Python views
// (python/src/simulation.cpp, vpcontact.Simulation.fields, vpcontact.Fields) are made
// from this table: a new field is one entry (a new stored field also needs its place in
// the checkpoint format, io/checkpoint_file.hpp: kFileArrays, which a test checks).
#include "io/vtu_writer.hpp"
#include "part/mesh_part.hpp"
#include "scheme/state.hpp"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace vpc {

/// Where a field's numbers live. contact_node: State::contact_block numbers per contact
/// node, node after node in the rows' order (the normal force first).
enum class FieldLocation { node, cell, contact_node };
const char* location_name(FieldLocation l);

/// What an output field is made from: the state, the part (mesh, dofs) and its contact nodes
/// (ContactSet::nodes: TimeStepper::contact()).
struct FieldContext {
  const State& state;
  const MeshPart& part;
  std::span<const PartContactNode> contact;
};

struct StateField {
  std::string_view name;    // the State member (u, beta, lambda, sigma, eps, z) or the output field's
  std::string_view python;  // vpcontact.Simulation's attribute ("": none)
  std::string_view vtu;     // the VTU array, as [output] fields names it ("": none)
  FieldLocation location;
  /// Numbers per node, cell or contact node (d: the mesh's dimension).
  int (*components)(const State& s, int d);
  /// A stored field (a member of State: checkpointed, a view in Python): its numbers,
  /// `components` per entity, entity after entity; and setting them. Null: an output field.
  std::span<const double> (*values)(const State& s) = nullptr;
  void (*assign)(State& s, std::span<const double> v) = nullptr;
  /// Its VTU array on the part's mesh (point data for nodes and contact nodes, cell data
  /// for cells); null: not written.
  VtuField (*vtu_field)(const FieldContext& c) = nullptr;
  /// Whether the VTU files have it for this state (null: always, as [output] fields says).
  bool (*in_vtu)(const State& s) = nullptr;
  std::string_view meaning;
  /// Friction's (SPEC §7): the state has it only with friction (contact_block > 1; empty,
  /// or not written, without).
  bool friction = false;

  bool stored() const { return values != nullptr; }
  bool point_data() const { return location != FieldLocation::cell; }
};

/// The normal force of each contact node: the first of λ's numbers per node (λ itself
/// when State::contact_block is 1).
Eigen::VectorXd normal_forces(const State& s);

/// Every field, in the order of the VTU arrays (point data, then cell data, each in this order).
std::span<const StateField> state_fields();
/// The field of this name (StateField::name); throws vpc::Error when there is none.
const StateField& state_field(std::string_view name);

/// The names [output] fields accepts (the VTU arrays), in order.
std::vector<std::string> vtu_field_names();

/// The VTU point and cell arrays of the fields `wanted` (by VTU name; empty: all) that
/// the state has, the contact laws' per-node state (State::surface, by its name; zero off Γ3)
/// after the table's point arrays.
void make_vtu_fields(const FieldContext& c, const std::vector<std::string>& wanted, std::vector<VtuField>& point_data,
                     std::vector<VtuField>& cell_data);

}  // namespace vpc
