#include "solvers/stick_slip.hpp"

namespace vpc {

std::vector<ContactStatus> stick_slip(const ContactConstraints& c, const Vector& lambda, double slack,
                                      double active_threshold) {
  const int t = c.block - 1;
  const Vector normal = local_normal(c, lambda), tangential = local_tangential(c, lambda);
  std::vector<ContactStatus> status;
  for (Eigen::Index i = 0; i < normal.size(); ++i) {
    const double tn = c.friction_of(i).gauge(tangential.data() + i * t, t);
    // Out of contact only Tresca's given bound leaves a tangential force (Open; else Free).
    status.push_back(normal[i] > active_threshold ? contact_status(normal[i], tn, c.bound(i, normal[i]), slack)
                     : tn > slack                 ? ContactStatus::Open
                                                  : ContactStatus::Free);
  }
  return status;
}

}  // namespace vpc
