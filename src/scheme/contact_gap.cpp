#include "scheme/contact_gap.hpp"

#include "fem/assembly.hpp"
#include "solvers/contact_solver.hpp"

namespace vpc {

bool records_gap(const DiscreteSystem& sys) { return !sys.problem->contact.pairs.empty(); }

Vector rows_gap_left(const DiscreteSystem& sys, const Vector& g, const State& s) {
  return g - sys.contact->N_local * restrict_to_free(sys.part.dofs, s.u);
}

void record_gap(const DiscreteSystem& sys, const Vector& g, State& s) {
  if (!records_gap(sys)) return;
  ContactConstraints c;  // what replicate reads: the rows and their number
  c.m = sys.part.n_contact;
  c.rows = sys.contact->owned_row_numbers();
  s.gap = replicate(sys.part.comm, c, rows_gap_left(sys, g, s));
}

}  // namespace vpc
