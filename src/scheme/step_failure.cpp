#include "scheme/step_failure.hpp"

#include <fmt/format.h>

#include <cmath>

namespace vpc {

std::string step_failure(const StepReport& r, double tolerance) {
  const std::string contact = contact_failure(r.contact, tolerance);
  const std::string damage = damage_failure(r.damage, tolerance);
  if (contact.empty() && damage.empty())  // TimeStepper::step's last check
    return "the displacement or the damage field holds NaN or Inf although both solvers met the tolerance";
  std::string s;
  if (!contact.empty()) s = "the contact solver " + contact;
  if (!damage.empty()) s += (s.empty() ? "" : "; ") + ("the damage solver " + damage);
  return s;
}

bool halving_can_help(const StepReport& r, double tolerance) {
  const ContactResiduals& c = r.contact.residuals;
  const bool contact_solved = r.contact.converged && std::isfinite(c.max());
  return !contact_solved || !damage_failure(r.damage, tolerance).empty() || contact_failure(r.contact, tolerance).empty();
}

}  // namespace vpc
