#pragma once
// What a step reports (SPEC §2): the solvers' reports, β's range, the stress, the contact
// totals and reactions, the error estimate and whether the step is accepted. Filled by the
// step (scheme/scheme_step.hpp), its checks (scheme/step_checks.hpp) and step-size control
// (scheme/step_control.hpp).
#include "solvers/contact_solver.hpp"
#include "solvers/damage_solver.hpp"

#include <string>
#include <vector>

namespace vpc {

/// The smallest value and where it is. The one rule for min β in the step
/// reports and summary.json of both engines and any rank count: among equal
/// minima (β = 0 or β = 1 at many nodes), the smallest node index in the
/// numbering of the mesh as read (minimum_at, global_minimum_at: scheme/step_checks.hpp).
struct MinimumAt {
  double value = 0;
  int index = -1;
};

/// The contact laws' per-node state at the step (contact/surface_state.hpp, SurfaceUpdate): the largest
/// share of a law's step limit and of its warning threshold over the contact nodes, and where one passes
/// 1, the located text of the law's limit (the same on every process).
struct SurfaceLimits {
  double step_share = 0, warn_share = 0;
  std::string step_text, warn_text;
  /// The L2 mean over Γ3 of the laws' SurfaceUpdate::rate_change: the error estimate's share of the
  /// surface state (k/2 times it, as β's).
  double rate_change = 0;
};

struct StepReport {
  int n = 0;
  double t = 0;
  double k = 0;  // the step's size t_n − t_{n−1}
  /// The estimate of the relative error this step adds (StepControl, problem/time_grid.hpp),
  /// made for every grid; error-controlled steps are chosen by it.
  double error_estimate = 0;
  /// Attempts of this step that were rejected and redone from the state before it
  /// (error-controlled steps: error, event or solver).
  int rejected = 0;
  ContactReport contact;
  DamageReport damage;
  double beta_min = 1, beta_max = 1;
  int beta_min_node = 0;  // by the rule of minimum_at
  double max_von_mises = 0;
  double sigma_norm = 0;  // |σ_n|_{L2}
  /// The contact area: the summed tributary measures of the active contact nodes
  /// (a length in 2D, 1 per node in 1D).
  double contact_area = 0;
  /// With obstacles: the total contact force on each (Problem::contact.obstacles order),
  /// each node's force counted for the obstacle nearest to it at this step.
  std::vector<double> obstacle_force;
  /// Per contact pair (ContactSpec::pairs): Σ λ over its slave nodes, the normal force between the bodies.
  std::vector<double> pair_force;
  /// Friction (SPEC §7; both empty without, and history.csv has no friction columns): the
  /// tangential forces Σ_j λ_τ,j t_j summed over the contact nodes as a vector of d
  /// components (the force on the obstacles; the body gets its opposite), and with
  /// obstacles the same per obstacle (d after d, as obstacle_force counts the nodes).
  std::vector<double> tangential_force, obstacle_tangential_force;
  /// With friction and contact pairs: per pair (ContactSpec::pairs), the tangential force on its
  /// master side (d after d; the slave side gets its opposite).
  std::vector<double> pair_tangential_force;
  /// With friction and [[contact.part]] sections: per law entry of Γ3 ([contact]'s, then the
  /// [[contact.part]]s', as ContactSpec::laws() begins; each node counted for its law), the normal
  /// force and the tangential force (d after d). A pair's rows count for their pair only.
  std::vector<double> part_force, part_tangential_force;
  /// Per variable of the contact laws' per-node state that asks for a history column
  /// (SurfaceVariable::history, in declared order): ∫_Γ3 v = Σ_i v_i |Γ3|_i.
  std::vector<double> surface_integral;
  /// The surface laws' limits (a step whose step_share passes 1 is rejected: halving can help).
  SurfaceLimits surface;
  /// The reaction force on each Dirichlet part (dirichlet_parts order): the force its
  /// supports exert on the body, Σ over the part's nodes of (σ_n, ε(φ)) − F_n, in each
  /// component the part prescribes (DirichletDofs::components), in increasing order. A
  /// dof on several parts counts for the first of them that prescribes it.
  std::vector<double> reaction;
  double seconds_sources = 0, seconds_damage = 0, seconds_contact = 0, seconds_stress = 0;
  /// True when both solvers converged and all residuals are within tolerance.
  bool ok = true;
  /// Sub-steps taken (1, or more after step halving).
  int substeps = 1;
  /// A run with mesh adaptivity ([adapt]; −1 without, and history.csv has no such columns): the cells
  /// and free displacement unknowns of the mesh the step ends on, and the adaptations so far.
  long long mesh_cells = -1, mesh_unknowns = -1;
  int adaptations = -1;
};

/// Adds the step phases' times of `from` to `to` (substeps, rejected attempts).
inline void add_seconds(StepReport& to, const StepReport& from) {
  to.seconds_sources += from.seconds_sources;
  to.seconds_damage += from.seconds_damage;
  to.seconds_contact += from.seconds_contact;
  to.seconds_stress += from.seconds_stress;
}

}  // namespace vpc
