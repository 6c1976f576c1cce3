#include "solvers/contact_capabilities.hpp"

#include "core/error.hpp"
#include "la/backend.hpp"
#include "solvers/contact_frame.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace vpc {

bool dual_only(const ContactLaw& law) { return !law.linear(); }

ContactNeeds contact_needs(const la::Comm& comm, const ContactConstraints& c) {
  ContactNeeds n;
  n.friction = c.frictional();
  bool compliant = false, nonlinear = false, adhesion = false;  // on this rank's rows
  double tension = static_cast<double>(c.laws.size());  // the first law with a row below 0
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(c.law.size()); ++i) {
    const ContactLaw& law = c.law_of(i);
    compliant = compliant || !law.rigid();
    nonlinear = nonlinear || !law.linear();
    adhesion = adhesion || c.bond_length_of(i) > 0;
    if (c.lower_of(i) < 0) tension = std::min(tension, static_cast<double>(c.law[static_cast<std::size_t>(i)]));
  }
  if (const auto k = static_cast<std::size_t>(comm.min(tension)); k < c.laws.size()) n.tension = c.laws[k]->name();
  n.compliant = comm.any(compliant);
  n.adhesion = comm.any(adhesion);
  // The laws are the same list on every rank: each names the law from the list, whether or not it has such a row.
  if (comm.any(nonlinear))
    for (const auto& law : c.laws)
      if (!law->linear()) {
        n.nonlinear = law->kind();
        break;
      }
  n.pair_sides_mixed = !comm.all(masters_apart_from_slaves(c.N, c.node_dofs, c.master_mean));
  n.spread_pairs = c.remote.spread;  // the same on every rank (RemoteRows::spread)
  n.floating = c.floating();         // the same count on every rank
  n.shear_bond = c.shear_bonded;     // the same on every rank (from the case)
  return n;
}

std::string cannot_solve(const std::string& solver, const ContactNeeds& needs) {
  if (needs.floating && needs.friction)
    return fmt::format("contact solver '{}': a body its bonds alone hold (held_by_bond) is solved without friction, "
                       "wear or a tangential bond: the pull-off test balances the normal forces only (remove them, or "
                       "hold the body by prescribed displacements)",
                       solver);

  if (needs.floating && solver != "primal-active-set")
    return fmt::format("contact solver '{}' needs K's inverse, and a body its bonds alone hold (held_by_bond) makes K "
                       "singular: 'primal-active-set' solves it (it factors K with the bonds' springs)",
                       solver);
  // Coulomb's and Tresca's bounds are of a pressing force; with a tension they are not defined.
  if (needs.friction && !needs.tension.empty())
    return fmt::format("contact solver '{}': law = \"{}\" lets a node carry a tension, and friction's bound is not "
                       "defined there; no contact solver solves it with friction (remove friction)",
                       solver, needs.tension);
  if (needs.friction && needs.adhesion && needs.compliant)
    return fmt::format("contact solver '{}': adhesion together with friction is solved with Signorini's normal law; "
                       "a normal compliance law there is not (use law = \"signorini\", or remove the friction)",
                       solver);
  if (needs.adhesion && solver == "penalty-duality")
    return "contact solver 'penalty-duality' solves the Signorini conditions only (a force >= 0); adhesion (a bond "
           "that pulls) needs 'active-set' or 'primal-active-set'";
  if (solver == "primal-active-set") {
    if (!needs.nonlinear.empty())
      return fmt::format("contact solver 'primal-active-set' solves Signorini and linear normal compliance rows; a {} "
                         "needs 'active-set'",
                         needs.nonlinear);
    if (needs.pair_sides_mixed)
      return "contact solver 'primal-active-set': a node is on the slave side of one contact pair row and the master "
             "side of another; --contact-solver active-set solves it";
    if (needs.spread_pairs)
      return "contact solver 'primal-active-set': the rows of contact pairs are spread over the ranks (--spread-pairs: "
             "slave and master nodes owned apart); --contact-solver active-set solves them";
  }
  if (solver == "penalty-duality") {
    if (needs.friction)
      return "contact solver 'penalty-duality' solves frictionless contact only; friction (and wear, which follows "
             "the slip) needs 'active-set' (the dual) or 'primal-active-set'";
    if (needs.compliant)
      return "contact solver 'penalty-duality' solves the Signorini conditions only; normal compliance needs "
             "'active-set'";
    if (!needs.tension.empty())
      return fmt::format("contact solver 'penalty-duality' solves the Signorini conditions only (a force >= 0); law = "
                         "\"{}\" (a force down to a tension) needs 'active-set' or 'primal-active-set'",
                         needs.tension);
    if (needs.spread_pairs)
      return "contact solver 'penalty-duality': the rows of contact pairs are spread over the ranks (--spread-pairs: "
             "slave and master nodes owned apart); --contact-solver active-set solves them";
  }
  return {};
}

void refuse_unsolvable(const std::string& solver, const ContactNeeds& needs) {
  if (std::string why = cannot_solve(solver, needs); !why.empty()) throw CollectiveError(why);
}

ContactSolverPick pick_contact_solver(const std::string& requested, int m, const std::string& linear_solver,
                                      const ContactNeeds& needs, int block) {
  if (needs.floating) {
    if (!la::Backend::is_direct(linear_solver))
      throw CollectiveError(fmt::format("a body its bonds alone hold (held_by_bond) needs a direct linear solver: K is "
                                        "singular without the bonds' springs, which '{}' cannot tell from a slow "
                                        "convergence (--linear-solver cholmod, or mumps on the PETSc engine)",
                                        linear_solver));
    if (requested == "auto")
      return {"primal-active-set", "auto: a body its bonds alone hold (K singular: the primal factors it with the bonds)"};
  }
  if (requested != "auto") return {requested, "as asked"};
  // Where the primal cannot solve it, the dual does (the table's first row solves everything).
  if (!needs.nonlinear.empty()) return {"active-set", "auto: a nonlinear compliance law is solved on the dual"};
  // With friction the dual's unknowns are m × block (λ_ν and the tangential forces of each node); with
  // adhesion and no friction each bonded node's pull besides its force (BondDual): up to 2m.
  const bool pulls = needs.adhesion && block == 1;
  const int n = m * block * (pulls ? 2 : 1);
  const std::string unknowns =
      pulls        ? fmt::format("{} contact unknowns ({} nodes, a bonded node's pull besides its force)", n, m)
      : block == 1 ? fmt::format("{} contact nodes", m)
                   : fmt::format("{} contact unknowns ({} nodes x {})", n, m, block);
  ContactSolverPick pick{"active-set", fmt::format("auto: {} <= {} and a direct solver", unknowns, kDualContactRows)};
  if (!la::Backend::is_direct(linear_solver))
    pick = {"primal-active-set", fmt::format("auto: {} is iterative (the dual's S would take {} solves)", linear_solver, n)};
  else if (n > kDualContactRows)
    pick = {"primal-active-set", fmt::format("auto: {} > {} (the dual's S would be dense {} x {})", unknowns,
                                             kDualContactRows, n, n)};
  if (pick.name == "primal-active-set" && needs.pair_sides_mixed)
    return {"active-set", "auto: a node is on both sides of contact pairs (the primal needs them apart)"};
  if (pick.name == "primal-active-set" && needs.spread_pairs)
    return {"active-set", "auto: a contact pair's rows are spread over the ranks (the primal needs a row's dofs on its rank)"};
  return pick;
}

}  // namespace vpc
