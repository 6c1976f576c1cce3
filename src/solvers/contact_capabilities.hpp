#pragma once
// What each contact solver solves, in one table (issue 49): read by auto's choice
// (pick_contact_solver) and by the refusals of a solver asked for what it cannot solve, so that a
// new solver or law changes one row here instead of checks spread over the solvers.
//
//                        friction   compliance   a law that is     a friction set    a node on both    tension (a law's    adhesion (a     rows spread
//                                                not linear        not a disc        sides of pairs    lower bound < 0)    bond, SPEC §9)  over ranks
//   active-set (dual)    yes        yes          yes               yes               yes               yes, frictionless   yes (1)         yes
//   primal-active-set    yes        linear       no                yes               no                yes, frictionless   yes (1)         no
//   penalty-duality      no         no           no                no                yes               no                  no              no
// A tangential bond (γ_τ, on frictionless rows) is solved by both: the dual as a Tresca disc a_τ L with the
// compliance 1/a_τ, the primal as two more tangential states, the bond's spring and its pull beyond L.
// A body only its bonds hold (held_by_bond: K singular, frictionless) is the primal's alone, on a direct
// linear solver: the dual's S and penalty–duality's K + ωNᵀN need K⁻¹ or a factor of K without the rows.
// (1) With friction on Signorini's law only: the bond's pull makes λ_ν < 0, where Coulomb's bound μ max(λ_ν, 0)
// is 0. (Both frictional solvers ask each node's friction law for its set: the dual's Alart–Curnier
// projection, the primal's Hüeber–Stadler–Wohlmuth linearization; primal_friction.hpp. Rows spread
// over ranks: a pair row whose masters other ranks own, given as their remote pieces,
// ContactConstraints::remote; the primal's basis and penalty–duality's NᵀN need a row's dofs on its rank.)
#include "solvers/contact_solver.hpp"

#include <string>
#include <vector>

namespace vpc {

/// What a contact problem asks of its solver, the same on every rank (contact_needs reduces).
struct ContactNeeds {
  bool friction = false;         // a friction law on some row (λ has d numbers a node)
  bool compliant = false;        // some row's normal law is not Signorini
  std::string nonlinear;         // a normal law that is not linear: its kind ("a power-law compliance"); empty: none
  bool pair_sides_mixed = false; // a node on the slave side of one pair row and the master side of another
  std::string tension;           // a normal law whose force goes below 0 at some row (ContactLaw::dual_lower): its name
  bool adhesion = false;         // a row with a bond (ContactConstraints::bond_length: adhesion's tension branch, SPEC §9)
  bool spread_pairs = false;     // the rows are spread (RemoteRows::spread): some rank may hold pieces
  bool floating = false;         // a body only its bonds hold (ContactConstraints::free_motions): K is singular
  bool shear_bond = false;       // a tangential bond (SPEC §9's γ_τ; ContactConstraints::shear_bonded)
};

/// Whether a row with this normal law can only be solved by the dual (the table's "no" of the primal
/// for a law: a normal law that is not linear; every friction law is solved by both): what auto's
/// plan before set-up asks of each row (run/solver_plan.hpp).
bool dual_only(const ContactLaw& law);

/// The needs of `c` (collective: every rank gets the same answer).
ContactNeeds contact_needs(const la::Comm& comm, const ContactConstraints& c);

/// Why `solver` cannot solve `needs`, as the error a user reads (naming the solver that can), or
/// empty where it can. The one place the table above is written.
std::string cannot_solve(const std::string& solver, const ContactNeeds& needs);
/// Throws cannot_solve's message as a vpc::CollectiveError (needs are the same on every rank: the
/// program reports it once and ends every process without an abort); nothing where `solver` can.
void refuse_unsolvable(const std::string& solver, const ContactNeeds& needs);

/// The contact solver for a problem (issue 14): `requested` unless it is "auto" (a solver asked for
/// what it cannot solve is refused: cannot_solve). "auto" takes the dual "active-set" while
/// S = N K⁻¹Nᵀ is cheap (a direct solver and at most kDualContactRows contact unknowns, m × `block`:
/// with friction S is [N; T] K⁻¹ [N; T]ᵀ) or where the primal cannot solve the problem (the table);
/// else "primal-active-set". `why` says which rule decided, for the run's header.
struct ContactSolverPick {
  std::string name;
  std::string why;
};
constexpr int kDualContactRows = 2000;
/// The names a case file ([solver] contact) and --contact-solver accept; the first is the default.
inline const std::vector<std::string> kContactSolverNames = {"auto", "active-set", "primal-active-set",
                                                             "penalty-duality"};
ContactSolverPick pick_contact_solver(const std::string& requested, int m, const std::string& linear_solver,
                                      const ContactNeeds& needs, int block = 1);

}  // namespace vpc
