#include "material/laws/perzyna.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

namespace vpc {

PerzynaLaw::PerzynaLaw(const Parameters& p)
    : E_(p.get("E")), lambda_(p.get("lambda")), sigma_y_(p.get("sigma_y")) {
  require(E_ > 0, "E must be > 0 (got {})", E_);
  require(lambda_ > 0, "viscosity lambda must be > 0 (got {})", lambda_);
  require(sigma_y_ >= 0, "yield stress sigma_y must be >= 0 (got {})", sigma_y_);
}

SymTensor PerzynaLaw::project(const SymTensor& sigma, double radius, int) const {
  const double n = sigma.norm();
  return n <= radius ? sigma : (radius / n) * sigma;
}

SymTensor PerzynaLaw::rate(const PointState& s) const {
  const double radius = std::max(s.beta, 0.0) * sigma_y_;
  return (-E_ / (2 * lambda_)) * (s.sigma - project(s.sigma, radius, s.dim));
}

Lipschitz PerzynaLaw::lipschitz(double) const { return {E_ / (2 * lambda_), "E/(2 lambda)"}; }

std::string PerzynaLaw::describe() const {
  return fmt::format("perzyna (E = {}, lambda = {}, sigma_y = {})", E_, lambda_, sigma_y_);
}

SymTensor PerzynaVonMisesLaw::project(const SymTensor& sigma, double radius, int dim) const {
  const double vm = sigma.von_mises();
  if (vm <= radius) return sigma;
  if (dim < 3) return (radius / vm) * sigma;
  const double m = sigma.trace() / 3;
  return m * SymTensor::identity() + (radius / vm) * sigma.deviator();
}

std::string PerzynaVonMisesLaw::describe() const {
  return fmt::format("perzyna-von-mises (E = {}, lambda = {}, sigma_y = {})", E_, lambda_, sigma_y_);
}

}  // namespace vpc
