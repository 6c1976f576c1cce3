#pragma once
// The discrete state (u_n, σ_n, β_n) of Problem 3.1 plus what the scheme carries:
// the viscoplastic history z_n (3.6), ε(u_n) and the contact forces.
#include "core/sym_tensor.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

namespace vpc {

/// One per-node state variable the contact laws declared (contact/surface_state.hpp), replicated
/// like λ: `width` numbers per contact node, node after node in the rows' order.
struct SurfaceField {
  std::string name;
  int width = 1;
  Eigen::VectorXd values;
};

/// Whether two lists of per-node state have the same fields: names, widths and sizes (a snapshot
/// or a checkpoint that fits the state).
inline bool same_fields(const std::vector<SurfaceField>& a, const std::vector<SurfaceField>& b) {
  return std::ranges::equal(a, b, [](const SurfaceField& x, const SurfaceField& y) {
    return x.name == y.name && x.width == y.width && x.values.size() == y.values.size();
  });
}

struct State {
  int n = 0;        // time index
  double t = 0;     // t_n
  Eigen::VectorXd u;             // P1 displacement, full space: node * d + component
  Eigen::VectorXd beta;          // P1 damage, per node
  std::vector<SymTensor> sigma;  // P0 stress σ_n
  std::vector<SymTensor> eps;    // P0 strain ε(u_n)
  std::vector<SymTensor> z;      // P0 history z_n = σ_n − ℰε(u_n)
  /// Contact unknowns per contact node (the contact law's block, src/contact/): λ holds
  /// contact_block numbers per contact node, node after node, the normal force first
  /// (1: the normal force only, every normal law of the paper; 1 + (d − 1) with friction).
  int contact_block = 1;
  Eigen::VectorXd lambda;        // contact forces: contact_block numbers per contact node
  /// Friction (SPEC §7; empty without, contact_block = 1), per contact node (replicated, like λ):
  /// the slip increment Δ_i = T_i u_n − h_i of the last step (contact_block − 1 numbers: along
  /// the node's tangents, ContactConstraints::T), the accumulated slip Σ_n |Δ_i| (a path
  /// length) and the status after the last step (ContactStatus: 0 free, 1 stick, 2 slip).
  Eigen::VectorXd slip_step;
  Eigen::VectorXd slip;
  Eigen::VectorXd contact_status;
  /// With contact pairs (empty without), per contact node (replicated, like λ): the gap left,
  /// g(t_n) − N u_n (scheme/contact_gap.hpp); recomputed from u on a restore, not checkpointed.
  Eigen::VectorXd gap;
  /// The contact laws' per-node state (SurfaceVariable), in the order of declared_surface_state
  /// (scheme/surface_fields.hpp); empty where no law keeps any.
  std::vector<SurfaceField> surface;
  /// The field of this name (nullptr: none).
  const SurfaceField* surface_field(std::string_view name) const {
    for (const SurfaceField& f : surface)
      if (f.name == name) return &f;
    return nullptr;
  }
};

}  // namespace vpc
