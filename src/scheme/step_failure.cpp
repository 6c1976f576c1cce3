#include "scheme/step_failure.hpp"

#include <fmt/format.h>

#include <cmath>

namespace vpc {

std::string step_failure(const StepReport& r, double tolerance) {
  if (r.contact.pulled_off)  // SPEC §9: the end of a bonded body's equilibrium, located in time
    return fmt::format("pull-off at t = {:.6g}: the remaining bond can no longer hold the body (the contact solver {})",
                       r.t, contact_failure(r.contact, tolerance));
  const std::string contact = contact_failure(r.contact, tolerance);
  const std::string damage = damage_failure(r.damage, tolerance);
  const std::string& surface = r.surface.step_share > 1 ? r.surface.step_text : std::string();
  if (contact.empty() && damage.empty() && surface.empty())  // TimeStepper::step's last check
    return "the displacement or the damage field holds NaN or Inf although both solvers met the tolerance";
  std::string s;
  if (!contact.empty()) s = "the contact solver " + contact;
  if (!damage.empty()) s += (s.empty() ? "" : "; ") + ("the damage solver " + damage);
  if (!surface.empty()) s += (s.empty() ? "" : "; ") + surface;  // a surface law's step limit (SPEC §9's wear cap)
  return s;
}

bool halving_can_help(const StepReport& r, double tolerance) {
  if (r.contact.pulled_off) return false;  // the load, not the step, decides: a shorter step meets it as well
  const ContactResiduals& c = r.contact.residuals;
  const bool contact_solved = r.contact.converged && std::isfinite(c.max());
  return !contact_solved || !damage_failure(r.damage, tolerance).empty() || contact_failure(r.contact, tolerance).empty() ||
         r.surface.step_share > 1;
}

}  // namespace vpc
