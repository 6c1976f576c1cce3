#include "scheme/contact_gap.hpp"

#include "solvers/contact_solver.hpp"

namespace vpc {

bool records_gap(const DiscreteSystem& sys) { return !sys.problem->contact.pairs.empty(); }

void record_gap(const DiscreteSystem& sys, const Vector& g, const Vector& u_free, State& s) {
  if (!records_gap(sys)) return;
  ContactConstraints c;  // what replicate reads: the rows and their number
  c.m = sys.part.n_contact;
  c.rows = sys.part.owned_contact_rows();
  s.gap = replicate(sys.part.comm, c, g - sys.contact.N * u_free);
}

}  // namespace vpc
