#pragma once
// Solvers of the contact inequality (3.9) in matrix form:
//     min ½ uᵀKu − Fᵀu   subject to  N u ≤ g,
// K the constant elastic stiffness on the free dofs, one row of N per contact
// node (its contact direction). The multipliers λ ≥ 0 are the nodal contact
// forces: K u = F − Nᵀλ, λ ⟂ (g − N u) ≥ 0. Neither solver knows about meshes.
//
// Written once over la/ for one process and for many: u, F are this rank's owned
// free dofs; the rows of N are distributed by contact node (a row lives on the rank
// that owns its node, over its owned dofs; entries in dofs another rank owns are that
// rank's remote pieces of the row, ContactConstraints::remote); λ is replicated (m
// numbers, the same on every rank): the dual QP with the dense S = N K⁻¹ Nᵀ is small and
// solved alike on every rank. On one process the rows are 0..m−1 and N is the whole matrix.
#include "contact/contact_law.hpp"
#include "contact/friction_law.hpp"
#include "la/linear_solver.hpp"

#include <Eigen/Dense>

#include <memory>
#include <string>
#include <vector>

namespace vpc {

/// Residuals of the KKT conditions of (3.9), each relative (see contact_residuals).
struct ContactResiduals {
  double equilibrium = 0;           // ‖Ku − F + Nᵀλ‖∞ / max(‖F‖∞, ‖Ku‖∞)
  double penetration = 0;           // max(0, max(Nu − g)) / scale_u
  double negative_force = 0;        // max(0, −min(λ − lower)) / scale_λ (lower: ContactConstraints::lower_of, mostly 0)
  double complementarity = 0;       // max |(λ_i − lower_i) (g − Nu)_i| / (scale_λ scale_u); a bond that pulls: |λ_i − its force| / scale_λ
  // Friction (SPEC §7; 0 without): with Δ_i = T_i u − h_i the slip increment and s_i the bound
  // (ContactConstraints::bound) of node i,
  double friction_bound = 0;        // max(0, max_i |λ_τ,i| − s_i) / scale_λ: |λ_τ| ≤ s
  double stick_slip = 0;            // max_i min((s_i − |λ_τ,i|)₊, scale_λ) |Δ_i| / (scale_λ scale_u): below the bound, no slip
  double slip_direction = 0;        // max_i (|λ_τ,i| |Δ_i| − λ_τ,i·Δ_i) / (scale_λ scale_u): slip along λ_τ
  double force_scale = 0;           // scale_λ (not a residual: max() leaves it out)
  double max() const;
};

struct ContactReport {
  bool converged = false;
  int iterations = 0;
  /// primal-active-set: factorizations of K with the active rows done in this solve (0: the
  /// last one's active set held), and active sets that came back (then it updates monotonically).
  int factorizations = 0;
  int cycles = 0;
  /// Contact nodes with λ_i > active_threshold. The active-set method's λ is exactly 0
  /// off its active set (threshold 0); penalty–duality's multiplier only tends to 0
  /// there, so a node counts as active when λ_i > tolerance · max(‖λ‖∞, ‖F‖∞), the
  /// size below which its own KKT test takes a multiplier for zero.
  int n_active = 0;
  double active_threshold = 0;
  double total_force = 0;  // Σ λ_i (the normal forces)
  /// Friction (0 without): active nodes below their bound (stick) and at it (slip, or about
  /// to), by contact_status; the frictional dissipation Σ λ_τ,i·Δ_i of the step (≥ 0).
  int n_stick = 0, n_slip = 0;
  /// Nodes not in contact (λ_ν = 0) that carry a tangential force: Tresca's given bound acts on
  /// all of Γ3 (ContactStatus::Open), in or out of contact.
  int n_open = 0;
  double dissipation = 0;
  ContactResiduals residuals;
  /// The step has no equilibrium: a body that only its bonds hold (ContactConstraints::free_motions) is
  /// loaded beyond what its rows' forces can balance (the remaining bonds' pull, λ_i ≥ −a_i L_i): a
  /// pull-off (SPEC §9). Not converged; `pull_off_excess` is the unbalanced share of the load on those motions.
  bool pulled_off = false;
  double pull_off_excess = 0;
};

/// Pieces of other ranks' rows (a contact pair's row whose masters another rank owns): over this
/// rank's owned free dofs, the entries of those rows there, with no gap, law or datum (those stay
/// with the row's owner). A row's N u is its owner's part plus every piece's (gap_left); its load
/// Nᵀλ adds each piece's transpose times the row's λ (add_piece_loads). Numbered as
/// ContactConstraints' own rows: `rows[k]` is piece k's global row (0..m−1; its λ at rows[k] × block
/// + j), increasing, none of them this rank's own; N's row k is that row's normal part; with friction
/// T's row k(b − 1) + j is its tangent j's part (T's layout), else T is 0 × 0. Empty in serial and
/// where no row is spread.
struct RemoteRows {
  std::vector<int> rows;
  SparseMatrix N;  // pieces × owned free dofs
  SparseMatrix T;  // pieces × (b − 1) rows × owned free dofs (friction), else 0 × 0
  /// The rows are spread: some rank may hold pieces, the same on every rank, set once
  /// where the constraints are made (part/contact_set.cpp; checked by the dual). The products with
  /// pieces then sum over the ranks; without, they read own rows alone. The primal and
  /// penalty–duality refuse spread rows (contact_needs), pieces or not.
  bool spread = false;
};

/// This process's rows of N (3.9): the contact nodes it owns.
struct ContactConstraints {
  int m = 0;              // rows over all processes
  std::vector<int> rows;  // the global row (0..m-1) of each local row, increasing
  SparseMatrix N;         // local rows × owned free dofs
  Vector gap;             // g of each local row
  /// The contact laws (contact/contact_law.hpp), the same list on every process, and per
  /// local row the index of its law in it and the law's per-node datum (ContactRow::datum: k_i
  /// for normal compliance), whose meaning the solvers ask the law (compliance_of, lower_of).
  /// No laws: Signorini on every row. Linear laws give the dual QP with S + diag(1/k); a law that
  /// is not linear, solve_compliance_dual's Newton (active-set only).
  std::vector<std::shared_ptr<const ContactLaw>> laws;
  std::vector<int> law;  // per local row
  Vector datum;          // per local row
  /// Per local row, its own node's free dofs (owned numbering); a contact pair's row (SPEC §8) has its
  /// other entries at its master nodes'. What tells a pair row's slave from its masters
  /// (masters_apart_from_slaves, contact_basis: solvers/contact_frame.hpp); empty in constraints
  /// made by hand (tests), where every entry of a row is its node's.
  std::vector<std::vector<int>> node_dofs;
  /// Friction on pairs: M of ContactMatrix::master_mean (owned numbering), each slave node's masters'
  /// weighted mean on all its dofs; T's pair rows are then the slip relative to the master,
  /// t_ij·(u_j − M u), and the primal solver's basis moves the whole slave node (contact_basis).
  /// Empty without pairs or without friction.
  SparseMatrix master_mean;
  /// Contact unknowns per row (State::contact_block): λ holds m × block numbers, row after row,
  /// the normal force first. 1 for a normal law; d with friction (SPEC §7): λ_ν then the
  /// d − 1 tangential forces λ_τ along the node's tangents.
  int block = 1;
  /// Law k's entry in a list parallel to `laws` (laws, frictions): nullptr where the list has none
  /// (empty: none given) or the entry is nullptr (a frictionless law's place in frictions); and local
  /// row i's (its law's; none where no laws are given, `law` then empty too).
  template <class Law>
  static const Law* entry(const std::vector<std::shared_ptr<const Law>>& list, std::size_t k) {
    return k < list.size() ? list[k].get() : nullptr;
  }
  template <class Law>
  const Law* entry_of(const std::vector<std::shared_ptr<const Law>>& list, Eigen::Index i) const {
    return list.empty() ? nullptr : entry(list, static_cast<std::size_t>(law[static_cast<std::size_t>(i)]));
  }
  /// The law of local row i (Signorini where there are no laws).
  const ContactLaw& law_of(Eigen::Index i) const {
    const ContactLaw* l = entry_of(laws, i);
    return l ? *l : *signorini_law();
  }
  /// Local row i's compliance 1/k_i (0: rigid) and the lower bound of its force, λ_i ≥ lower_i
  /// (0 but for a law that lets a node carry a tension), from its law at its datum.
  double compliance_of(Eigen::Index i) const { return laws.empty() ? 0.0 : law_of(i).compliance(datum[i]); }
  /// With a bond (adhesion), λ_i ≥ −a_i L_i below the law's own bound.
  double lower_of(Eigen::Index i) const {
    return (laws.empty() ? 0.0 : law_of(i).dual_lower(datum[i])) - bond_of(i) * bond_length_of(i);
  }

  // Adhesion (SPEC §9), per local row: a bond of stiffness a_i = γ_ν α_i² |Γ3|_i (a force per unit of
  // separation; the step's, from the bonding field at the step's start: ContactSolver::set_bond) that
  // holds the node up to the separation L_i (the bond length; set once), beyond which it pulls with
  // −a_i L_i. Below the law's pressing branch (λ_i ≥ 0) the row's graph gets the tension branch
  //   λ_i = −a_i min(s_i, L_i) for a separation s_i = g_i − N_i u > 0,
  // monotone in s (a node that pulls, λ_i < 0, has s_i ≥ 0 and λ_i = bond_force(i, s_i)). Empty: no row is bonded.
  Vector bond, bond_length;
  /// Its tangential part (SPEC §9's γ_τ; frictionless rows: friction_of is the disc of bound 0 there),
  /// per local row and step: a_τ,i = γ_τ α_i² |Γ3|_i and, per tangent (rows × (b − 1)), the bond's stretch
  /// v_{n−1} at the step's start. The row's tangential force is λ_τ,i = a_τ,i P_L(Δ_i + v_{n−1,i}), P_L onto
  /// the disc of radius L_i: Tresca's disc of radius a_τ,i L_i (bound_of) with the compliance 1/a_τ,i
  /// (shear_bond_force). Empty: none. `shear_bonded`: some row may get one (set
  /// at set-up, the same on every rank: the primal solver does not solve it).
  Vector shear_bond, bond_stretch;
  bool shear_bonded = false;
  double shear_bond_of(Eigen::Index i) const { return i < shear_bond.size() ? shear_bond[i] : 0.0; }
  double bond_of(Eigen::Index i) const { return i < bond.size() ? bond[i] : 0.0; }
  double bond_length_of(Eigen::Index i) const { return i < bond_length.size() ? bond_length[i] : 0.0; }
  /// Whether some row can carry a bond (bond_length set at set-up; the same on every rank where made by a part).
  bool adhesive() const { return bond_length.size() > 0 && bond_length.maxCoeff() > 0; }
  /// The bond's force at row i at the separation s0 = g_i − N_i u: −a_i min(s0₊, L_i) (0 without a bond).
  double bond_force(Eigen::Index i, double s0) const {
    return -bond_of(i) * std::min(std::max(s0, 0.0), bond_length_of(i));
  }

  // Friction (block > 1; SPEC §7), per local row i and its tangents j < block − 1:
  /// T: row i(b−1) + j is the unit tangent t_ij on the owned free dofs (set_tangents: the columns
  /// of the node-local reflection Q of contact_reflections other than ν's, so that in w = Qu the
  /// tangential coordinate is one dof, tangent_dof). A node with fewer free tangents (a symmetry
  /// plane) has zero rows and tangent_dof −1 there; its λ_τ,ij is 0. Without friction (b = 1) a row
  /// has no tangents: T has no rows (a builder may leave it 0 × 0) and the loops over them are empty.
  SparseMatrix T;
  std::vector<int> tangent_dof;  // per local row × (b − 1): owned free dof, −1 where none
  /// The bound of the tangential force, s_i = min(tresca_i + μ_i λ_ν,i, limit_i) (|λ_τ,i| ≤ s_i,
  /// Euclidean: a disc in 3D): Coulomb's μ_i (constant), Tresca's g_τ(x_i, t_n) |Γ3|_i as a force
  /// (per step), Coulomb's shear limit τ_max(x_i) |Γ3|_i as a force (constant; +∞ where none; an
  /// empty vector: none anywhere).
  Vector mu, tresca, limit;
  /// h of the slip increment Δ_i = T_i u − h_i (per local row × (b − 1), per step): t_ij·u_{n−1}
  /// plus the obstacle's tangential displacement over the step.
  Vector shift;
  bool frictional() const { return block > 1; }
  /// Other ranks' rows' entries in this rank's owned dofs (RemoteRows; empty in serial).
  RemoteRows remote;
  /// The rigid motions K is singular on, columns over the owned free dofs (the same count on every
  /// rank): bodies that only their bonds hold (`held_by_bond`, SPEC §9; problem/rigid_motions.hpp).
  /// Empty: K is positive definite. The primal solver factors K with its rows' springs then, and a
  /// step has an equilibrium only where the rows' forces, each within its graph (λ_i ≥ lower_of(i)),
  /// balance the load on these motions (equilibrium_on_free_motions): else a pull-off.
  Eigen::MatrixXd free_motions;
  bool floating() const { return free_motions.cols() > 0; }
  /// The friction laws (contact/friction_law.hpp), parallel to `laws` (nullptr: a frictionless law's
  /// place; empty: none), indexed by the row's `law`: each row's block asks its law for its set.
  std::vector<std::shared_ptr<const FrictionLaw>> frictions;
  /// Row i's friction law (the disc where it has none: its bound is 0 there).
  const FrictionLaw& friction_of(Eigen::Index i) const {
    const FrictionLaw* f = entry_of(frictions, i);
    return f ? *f : disc_friction();
  }
  /// Row i's bound's data, and its bound s_i at λ_ν (FrictionBound::at: written there once). A set
  /// without tangents may leave tresca and mu empty, as limit: 0 (its bound is 0, over no tangents).
  FrictionBound bound_of(Eigen::Index i) const {
    const auto at = [i](const Vector& v, double none) { return i < v.size() ? v[i] : none; };
    return {at(tresca, 0.0) + shear_bond_of(i) * bond_length_of(i), at(mu, 0.0),
            at(limit, std::numeric_limits<double>::infinity())};
  }
  double bound(Eigen::Index i, double lambda_nu) const { return bound_of(i).at(lambda_nu); }
  /// Whether row i's bound at λ_ν is its shear limit (then it does not move with λ_ν).
  bool at_limit(Eigen::Index i, double lambda_nu) const {
    bool capped = false;
    bound_of(i).at(lambda_nu, &capped);
    return capped;
  }
};

/// The tangents of friction (ContactConstraints::T, tangent_dof) for c.block − 1 tangents per row:
/// `node_dofs[i]` are the free dofs (owned free numbering) of local row i's node, in order. Rows of
/// N off the axes use contact_reflections' Householder frame of the row's own entries (a pair row's
/// master entries do not turn it); with c.master_mean a pair row's tangents are relative to its
/// masters, t_ij·(I − M). Sets c.T, c.tangent_dof and zero shift and tresca (mu is the caller's).
void set_tangents(ContactConstraints& c, const std::vector<std::vector<int>>& node_dofs);

/// The constraint rows of this rank's contact unknowns, node by node in λ's order: N, or with friction
/// B = [N; T] (per node its normal row, then its tangent rows), then the same of its remote pieces,
/// and each row's place in λ (`places`: rows[k] × block + j, then remote.rows[k] × block + j). Checks
/// friction's data and the pieces of `c`.
SparseMatrix block_rows(const ContactConstraints& c, std::vector<int>& places);
/// g, or with friction [g; h], of those rows (0 on the pieces: the offsets are their owners').
Vector block_offsets(const ContactConstraints& c);

/// g − N u of this rank's rows (the gap left by u), each with the other ranks' pieces of it
/// (collective where spread).
Vector gap_left(const la::Comm& comm, const ContactConstraints& c, const Vector& u);
/// Δ = T u − shift, the slip increments of this rank's rows (rows × (b − 1)): none without friction.
/// The first reads this rank's entries alone (exact where nothing is spread: it requires so); the
/// second adds the other ranks' pieces (collective where spread).
Vector slip_increment(const ContactConstraints& c, const Vector& u);
Vector slip_increment(const la::Comm& comm, const ContactConstraints& c, const Vector& u);
/// y += N_rᵀλ_ν + T_rᵀλ_τ of this rank's pieces of other ranks' rows (λ: m × block, replicated; no
/// communication): with its own rows' Nᵀλ_ν + Tᵀλ_τ, the contact forces' load on its owned free dofs.
void add_piece_loads(const ContactConstraints& c, const Vector& lambda, Vector& y);

/// A contact node's state after a step, for friction's outputs: not in contact (λ_ν = 0),
/// sticking (|λ_τ| below the bound by more than kSlipShare of it and more than `slack`),
/// slipping (at it), or not in contact yet carrying a tangential force above `slack` (Open:
/// Tresca's given bound acts on all of Γ3, in or out of contact).
enum class ContactStatus { Free = 0, Stick = 1, Slip = 2, Open = 3 };
constexpr double kSlipShare = 1e-9;
/// The slack of a row's stick or slip status (stick_slip): this share of the force scale of the
/// friction residuals (ContactResiduals::force_scale). A solver's slip forces are exact only to
/// its friction tolerance (the primal's: 1e-9 of its force scale at the default step tolerance,
/// friction_force_tolerance), so that a row at its bound to within that would count as stick or
/// slip by the solver's last digits (frictional foundation-3d n = 20: 287 or 312 of 441 rows
/// stick with the slip forces settled to 1e-11 or 1e-9 of the force scale; 287 with this slack).
constexpr double kSlipForceShare = 1e-8;
ContactStatus contact_status(double lambda_nu, double tangential_norm, double bound, double slack = 0);

/// Residuals of (3.9) at (u owned, λ replicated), reductions over K.comm(); with a compliant
/// law the gap left is s = ContactLaw::gap_left(g − Nu, λ) = g − Nu + (λ/k)^{1/e} (≥ 0, ⟂ λ).
/// scale_u = max(‖u‖∞, ‖g‖∞, scale_λ / max K_ii), scale_λ = max(‖λ‖∞, ‖F‖∞, ‖Ku‖∞): the last
/// term of scale_u (the displacement a force scale_λ gives a dof against its own stiffness)
/// keeps the scale from vanishing where the exact u is 0 and g = 0 (issue 26: every free node a
/// contact node pressed onto a zero gap), where u's round-off would be measured against itself.
ContactResiduals contact_residuals(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F,
                                   const Vector& u, const Vector& lambda);

/// What failed in a contact solve judged against `tolerance` (SolverChoice::residual_tolerance),
/// for a failed step's message; empty when it converged with every residual within it. Names the
/// residual (equilibrium: KKT stationarity Ku = F − Nᵀλ; penetration and negative force: primal and
/// dual feasibility; complementarity), its value and the tolerance, or the iteration limit, or
/// NaN/Inf; never "converged" for a failure.
std::string contact_failure(const ContactReport& r, double tolerance);

/// For the solvers' implementations (solvers/*.cpp): λ's entries at this rank's rows; m numbers,
/// the same on every rank, from this rank's rows' values; `gap` checked to have one value per
/// row; the report of a solve (n_active counts λ_i > active_threshold, see ContactReport).
Vector local_rows(const ContactConstraints& c, const Vector& lambda);
Vector replicate(const la::Comm& comm, const ContactConstraints& c, const Vector& local);
/// With blocks (m × block numbers in λ): this rank's rows' normal forces (rows numbers) and
/// tangential forces (rows × (block − 1)), and λ (m × block, replicated) from them.
Vector local_normal(const ContactConstraints& c, const Vector& lambda);
Vector local_tangential(const ContactConstraints& c, const Vector& lambda);
Vector replicate_blocks(const la::Comm& comm, const ContactConstraints& c, const Vector& normal,
                        const Vector& tangential);
/// Checks friction's data of a step (sizes, finite, tresca ≥ 0) and stores it in c (set_friction).
void set_friction_data(ContactConstraints& c, const Vector& tresca, const Vector& shift);
/// Adhesion's bonds of a step (SPEC §9), per local row: the normal bond a_i and, where some row has a
/// tangential one, a_τ,i and the stretch v_{n−1} (rows × (b − 1)); shear and stretch empty: none.
struct StepBonds {
  Vector normal, shear, stretch;
};
/// Checks a step's bonds (one per row, finite, >= 0; rows without a bond length 0) and stores them in c.
void set_bond_data(ContactConstraints& c, const StepBonds& bonds);
/// Row i's tangential bond force a_τ P_L(Δ + v_{n−1}) at its slip increment Δ (`slip`: its t numbers); 0 on a row
/// without one. The residuals measure the row's λ_τ against it (the stick-slip residual's place).
Vector shear_bond_force(const ContactConstraints& c, Eigen::Index i, Eigen::Ref<const Vector> slip);
const Vector& checked_gap(const ContactConstraints& c, const Vector& gap);
/// The report of a solve whose unknowns are the normal forces alone (λ: m numbers; a solver of a set
/// without tangents), and of one with the tangential forces too (λ: m × block; friction's stick and
/// slip counts and dissipation as well). The solver that knows its unknowns calls its own.
ContactReport contact_report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                             const Vector& lambda, bool converged, int iterations, double active_threshold = 0);
ContactReport friction_report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                              const Vector& lambda, bool converged, int iterations, double active_threshold = 0);
/// The columns j0 .. j0+nb−1 of Nᵀ (or of [N; T]ᵀ with friction: `rows` places each local row
/// in λ), owned rows: each rank fills the columns of its own constraint rows (zero elsewhere),
/// so a block solve with it is collective.
Eigen::MatrixXd transposed_rows(const SparseMatrix& N, const std::vector<int>& rows, int j0, int nb);

class ContactSolver {
 public:
  virtual ~ContactSolver() = default;
  /// F, u: owned free dofs (u is the warm start on entry); lambda: m numbers (replicated). Collective.
  virtual ContactReport solve(const Vector& F, Vector& u, Vector& lambda) = 0;
  /// Replaces g of this process's rows (ContactConstraints::gap) for the following solves: the gap of
  /// step n, g(t_n), where it changes in time. Nothing set up from K and N depends on g.
  virtual void set_gap(const Vector& gap) = 0;
  /// Friction's data of step n for this process's rows (ContactConstraints::tresca, shift), before
  /// its solve; only for frictional constraints.
  virtual void set_friction(const Vector& tresca, const Vector& shift) = 0;
  /// Adhesion's bonds a_i of step n for this process's rows (ContactConstraints::bond), before its
  /// solve; only for constraints with bond lengths (adhesive()).
  virtual void set_bond(const StepBonds& bonds) = 0;
  /// The constraints it solves, with the step's data (gap, friction's bounds and shift): what the
  /// step reads again after the solve (record_slip: each row's stick/slip status and slip).
  virtual const ContactConstraints& constraints() const = 0;
  virtual std::string name() const = 0;
  /// One line for the run's description, e.g. "one solve per step (K's halves)" / "two solves per step".
  virtual std::string describe() const = 0;
  /// Warm-start state (penalty–duality's multiplier), as m numbers, the same on every rank; empty for
  /// active set, whose warm start is the solution itself: saved in checkpoints so that a resumed run is
  /// bit-identical.
  virtual Vector warm_state() const { return {}; }
  /// A factor the solver holds itself (primal-active-set: of K with its active rows), for reports.
  virtual const la::LinearSolver* own_factor() const { return nullptr; }
  virtual void set_warm_state(const Vector&) {}
};

struct ContactSolverOptions {
  double tolerance = 1e-12;    // penalty–duality stopping tolerance
  int max_iterations = 200000; // penalty–duality; the active-set method stops far earlier
  double omega = 0;            // penalty–duality ω; 0: 1 / (mean compliance N_i K⁻¹ N_iᵀ)
  /// Active set: Y = L⁻¹PNᵀ (or W = K⁻¹Nᵀ without halves) is kept (a step then costs
  /// one solve) while it takes at most this share of the memory of K's factor (where
  /// the backend says it) and 256 MiB (on every rank); else two solves a step.
  double max_cached_share = 0.5;
  /// Primal friction: the slip forces and Coulomb's bound count as settled when an iterate changes
  /// them by at most this share of the force scale (friction_force_tolerance: from the step's).
  double friction_tolerance = 1e-12;

  bool operator==(const ContactSolverOptions&) const = default;
};

/// The primal solver's friction_tolerance for a step's residual tolerance: 1e-1 of it (so that
/// the step's friction residuals stay below its tolerance), at least 1e-12. Frictional
/// foundation-3d n = 40 on CG + GAMG, 2 ranks, 100 steps: 5,403 iterations with 1e-3 of it, 4,539
/// with 1e-2, 3,735 with 1e-1 (docs/performance.md, "Friction"). The stick/slip
/// status of a row at its bound to within this accuracy is kSlipForceShare's.
double friction_force_tolerance(double residual_tolerance);

/// K (assembled, owned rows) and its factor; `make_factor` makes penalty–duality's factor of K + ωNᵀN.
/// "active-set": primal–dual active set on the contact unknowns, the dual QP with
/// S = N K⁻¹ Nᵀ. With a factor that has triangular halves (CHOLMOD, K = PᵀLLᵀP),
/// S = YᵀY with Y = L⁻¹PNᵀ kept sparse, and a step is one solve in two halves; else
/// W = K⁻¹Nᵀ is formed by block solves and kept (a step is one solve, u = u_free − Wλ),
/// or, when too large, a step is two solves. "penalty-duality": the paper's
/// Bermúdez–Moreno iteration on u (cross-check), factor of K + ωNᵀN.
std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, std::shared_ptr<const la::SpdOperator> K,
                                                   std::shared_ptr<const la::LinearSolver> K_factor,
                                                   ContactConstraints constraints, const la::LinearSolverFactory& make_factor,
                                                   const ContactSolverOptions& opt = {});
/// One process, for tests and benchmarks: K and N in Eigen, CHOLMOD.
std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, const SparseMatrix& K,
                                                   const SparseMatrix& N, const Vector& gap,
                                                   const ContactSolverOptions& opt = {});

}  // namespace vpc
