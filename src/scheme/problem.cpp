#include "scheme/problem.hpp"

#include "core/error.hpp"

#include <cmath>

namespace vpc {

void Problem::validate() const {
  const std::string where = name.empty() ? "problem" : name;
  require(mesh.n_cells() > 0, "{}: the mesh has no cells", where);
  require(elasticity.dim() == mesh.dim(),
          "{}: elasticity '{}' is for d = {} but the mesh has d = {}", where, elasticity.name(),
          elasticity.dim(), mesh.dim());
  require(std::isfinite(kappa) && kappa >= 0, "{}: kappa (damage diffusion) must be >= 0 (got {})", where, kappa);
  require(std::isfinite(final_time) && final_time > 0, "{}: final time T must be > 0 (got {})", where, final_time);
  require(n_steps >= 1, "{}: the number of time steps must be >= 1 (got {})", where, n_steps);
  require(law != nullptr, "{}: no viscoplastic law G", where);
  require(source != nullptr, "{}: no damage source phi", where);
  require(!clamped.empty(), "{}: no clamped part Γ1 given (meas Γ1 > 0 is required)", where);
  for (const auto& p : clamped)
    require(mesh.part_size(p) > 0, "{}: clamped part '{}' has no boundary facets in the mesh", where, p);
  require(!contact.parts.empty(), "{}: no contact part Γ3 given", where);
  for (const auto& p : contact.parts)
    require(mesh.part_size(p) > 0, "{}: contact part '{}' has no boundary facets in the mesh", where, p);
  for (const auto& p : traction)
    require(mesh.part_size(p) > 0, "{}: traction part '{}' has no boundary facets in the mesh", where, p);
  require(static_cast<bool>(contact.gap), "{}: no gap function g", where);
  if (contact.direction) {
    const Point& v = *contact.direction;
    require(std::hypot(v[0], v[1], v[2]) > 0, "{}: the contact direction must be a non-zero vector", where);
  }
}

}  // namespace vpc
