#pragma once
// Per-node state a contact law keeps on Γ3 (issue 49; SPEC §9's bonding field α and worn depth ω
// are such state). A normal or friction law declares its variables (name, numbers per node,
// initial value) and updates its own nodes' values once a step is solved, from what the step
// gave at the node; the values may move the node's gap in the next step (gap_shift). The rest
// is done once for every law: the values are replicated on every process like λ (one value per
// contact node, in the rows' order), copied with the state so that a rejected step rolls them
// back, checkpointed by name, written to the VTU files, viewed from Python and, where the law
// asks, integrated over Γ3 in history.csv (scheme/surface_fields.hpp, io/state_fields.hpp,
// io/checkpoint.cpp).
#include "core/sym_tensor.hpp"

#include <span>
#include <string>
#include <vector>

namespace vpc {

/// One per-node state variable a law declares.
struct SurfaceVariable {
  std::string name;       // its VTU array, Python attribute and checkpoint array: [a-z][a-z0-9_]*
  int width = 1;          // numbers per contact node
  double initial = 0;     // every contact node's value at t_0
  std::string meaning;    // one line for the docs and vpcontact.Fields
  /// history.csv's column of ∫_Γ3 v = Σ_i v_i |Γ3|_i (width 1; "": none).
  std::string history;
  /// The column is the mean instead, ∫ v / ∫ 1 over the nodes whose laws declare v (a share of that
  /// part of Γ3: adhesion's debonded fraction).
  bool history_mean = false;
};

/// What a law's update sees at one of its nodes once the step is solved (forces as the solvers
/// hold them: λ_ν ≥ 0 presses; the gap left g − N u ≥ 0 opens).
struct SurfaceNode {
  double lambda_nu = 0;
  std::span<const double> lambda_tau;  // d − 1 tangential forces (empty without friction)
  std::span<const double> slip_step;   // the step's slip increment along the free tangents (empty without)
  /// |Δu_τ − Δw_τ|: the node's whole tangential slip over the step relative to its partner (the obstacle,
  /// or the master side's mean), slip_step's and that along its prescribed directions (a roller's).
  double slip = 0;
  double gap_left = 0;
  double measure = 0;  // |Γ3|_i
  double k = 0;        // the step's size
  Point x{0, 0, 0};    // the node's position in the reference configuration
  /// k_ν,i: the stiffness of the node's own dofs along its contact direction, Σ_j ν_j² K_jj (K's
  /// diagonal): λ_ν,i / k_ν,i is the node's elastic approach, the scale of a surface-scale
  /// disturbance of its gap (what a lagged per-step update of the gap must stay below).
  double normal_stiffness = 0;
  /// The element size at the node: its tributary measure |Γ3|_i in 2D, √|Γ3|_i in 3D.
  double size = 0;
};

/// What a law's update says of the step at one node, as shares of the law's own limits (0: none).
struct SurfaceUpdate {
  /// Of its largest update in one step (SurfaceHistory::step_limit): above 1 the step is too long for
  /// the law and is rejected; a shorter one (halving, step control) lowers the share.
  double step_share = 0;
  /// Of its warning threshold (SurfaceHistory::warning): above 1 the run warns, once.
  double warn_share = 0;
  /// Where the update lags a rate (adhesion's α over the step with the separation of t_{n−1}): how much
  /// the rate changed over the step, |x'(t_n) − x'_lagged|, in the state's own scale per unit of time.
  /// The step's error estimate takes (k/2) times its L2 mean over Γ3 as the local error of the lag,
  /// as it does β's (scheme/step_control.hpp). 0: nothing lagged.
  double rate_change = 0;
};

/// A law's message and the key of its table it is about ("wear_cap"), where the run locates it.
struct LawText {
  std::string key, text;
};

/// The part of a law that keeps per-node state: none by default.
class SurfaceHistory {
 public:
  virtual ~SurfaceHistory() = default;
  virtual std::vector<SurfaceVariable> surface_state() const { return {}; }
  /// A node's values after the step: values[v] holds the node's numbers of the v-th variable
  /// surface_state() declared (in, its values at t_{n−1}; out, at t_n). Returns the shares of the
  /// law's limits the update used.
  virtual SurfaceUpdate update_surface(const SurfaceNode& /*node*/, std::span<double* const> /*values*/) const {
    return {};
  }
  /// Why the law's data are bad at the contact node x (a formula's value), or no text. Asked once per
  /// node at set-up.
  virtual LawText check_at(const Point& /*x*/) const { return {}; }
  /// In words, the limit that step_share measures and what lowers it, and the threshold of
  /// warn_share and what passing it means (for the step's failure and the run's warning).
  virtual LawText step_limit() const { return {}; }
  virtual LawText warning() const { return {}; }
  /// What the node's state adds to its gap g(t_n) (SPEC §9's worn depth: u_ν ≤ g + ω): step n solves
  /// with the values at t_{n−1}, lagged as the scheme lags the damage source. 0 by default.
  virtual double gap_shift(std::span<const double* const> /*values*/) const { return 0; }

  /// Sets a node's values at t_0 where they depend on the node (they start at each variable's
  /// `initial`): x its position, `gap` its gap g(x, 0). Returns why the node cannot start so (adhesion
  /// bonded across an open gap), or no text. Asked once per node at t_0.
  virtual LawText initial_at(const Point& /*x*/, double /*gap*/, std::span<double* const> /*values*/) const { return {}; }

  /// A bond (SPEC §9's adhesion) that pulls the node back once it separates: its stiffness per unit of
  /// Γ3 for the step of size k that starts from the node's values at t_{n−1} (γ_ν α_n², the bonding
  /// field carried over the step first), and its length L (the separation beyond which it pulls with
  /// a constant force). Step n's contact problem gets the tension branch λ = −a_i min(s, L), a_i the
  /// stiffness times |Γ3|_i (ContactConstraints::bond). 0: no bond.
  virtual double bond(std::span<const double* const> /*values*/, const Point& /*x*/, double /*k*/) const { return 0; }
  virtual double bond_length() const { return 0; }
  /// Its tangential part (SPEC §9's γ_τ, on frictionless rows): the stiffness per unit of Γ3 for the step
  /// (γ_τ α_n²; 0: none), and the bond's tangential stretch v_{n−1} = u_τ − u_τ⁰ at t_{n−1} along the node's
  /// tangents (into `stretch`, d − 1 numbers). Step n's tangential force is then λ_τ = a_τ P_L(Δ + v_{n−1}),
  /// Δ the step's slip increment, P_L the projection onto the disc of radius L.
  virtual double shear_bond(std::span<const double* const> /*values*/, const Point& /*x*/, double /*k*/) const {
    return 0;
  }
  virtual void bond_stretch(std::span<const double* const> /*values*/, std::span<double> /*stretch*/) const {}
};

}  // namespace vpc
