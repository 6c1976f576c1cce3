#pragma once
// Friction's data of a step (SPEC §7) and what a step leaves of it in the state: the Tresca
// bounds at t_n, the shift h of the slip increment Δ = T u_n − h (the last position plus the
// obstacle's tangential motion over the step), and after the solve the slip increment, the
// accumulated slip and each node's stick/slip/free status.
#include "scheme/discrete_system.hpp"
#include "scheme/state.hpp"
#include "scheme/step_data.hpp"

#include <memory>

#include <string>

namespace vpc {

/// g_τ(x_i, t) |Γ3|_i at the owned contact rows (Tresca; 0 on other rows). A value that is not
/// a number ≥ 0 is described in `bad` (the first one; else left as is).
Vector friction_bounds(const DiscreteSystem& sys, double t, std::string& bad);

/// h = T (u_{n−1} + w) at the owned rows, per tangent: u_{n−1} the state's displacement (its free
/// dofs: a tangent has no prescribed component) and w, at each contact node, the translation over
/// [s.t, t] of the obstacle nearest along ν at t (0 for a gap formula: a foundation that does not
/// slide). A rotating obstacle's surface motion is not modelled (only translations). On a pair's
/// row w is its masters' prescribed motion over the step, their mortar mean (`u_D`: the prescribed
/// displacement at t, over the part's dofs; empty where none is prescribed).
Vector slip_shift(const DiscreteSystem& sys, const State& s, double t, const Vector& u_D);

/// The translation over [from, to] of the obstacle nearest to contact node `node` along its direction at
/// `to` (0 where there are no obstacles or none lies ahead): the partner's motion of its slip.
Point obstacle_translation(const DiscreteSystem& sys, const PartContactNode& node, double from, double to);

/// Per owned row, the length of the slip of its node along its prescribed directions over a step from
/// `from` to `to` (u_before, u: the part's full displacement at both ends, ghosts current): a roller's or a
/// prescribed motion's component less the obstacle's translation (or, on a pair, its masters' mean motion)
/// there. Friction's T holds the free tangents alone (a prescribed one has no force to bound), so its
/// slip leaves this out; wear follows the whole relative motion (SurfaceNode::slip). Orthogonal to the
/// free tangents: a prescribed direction is orthogonal to ν (Problem::validate).
Vector prescribed_slip(const DiscreteSystem& sys, const Vector& u_before, const Vector& u, double from, double to);

/// After the step's contact solve (u_free: the owned free dofs, λ in s.lambda), with the constraints
/// it solved (ContactSolver::constraints: T, the step's bounds and shift): s.slip_step = Δ = T u − h,
/// s.slip += |Δ|, s.contact_status (stick_slip with `slack`, the contact report's). Collective.
void record_slip(const DiscreteSystem& sys, const ContactConstraints& c, const Vector& u_free, double slack, State& s);

/// Friction's part of a contact step (SPEC §7), chosen once for the run (step_friction): before
/// the solve, the step's Tresca bounds and slip shift to the solver; after it, the slip and the
/// stick/slip statuses into the state (record_slip). Frictionless contact's part does nothing.
class StepFriction {
 public:
  virtual ~StepFriction() = default;
  /// The bounds at data.t (friction_bounds, a bad one refused with the step's data: check_step_data)
  /// and h from s at t_{n−1} (slip_shift) to `contact`. Collective.
  virtual void before_solve(const DiscreteSystem& sys, const State& s, const StepData& data, ContactSolver& contact) const = 0;
  /// record_slip with the constraints `contact` solved and its report's slack. Collective.
  virtual void after_solve(const DiscreteSystem& sys, const ContactSolver& contact, const Vector& u_free,
                           const ContactReport& rep, State& s) const = 0;
};

/// The step's friction for `spec`: Coulomb's or Tresca's on some entry, else none.
std::unique_ptr<const StepFriction> step_friction(const ContactSpec& spec);

}  // namespace vpc
