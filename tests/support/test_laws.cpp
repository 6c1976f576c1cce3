#include "test_laws.hpp"

#include "contact/registry.hpp"
#include "core/error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>

namespace vpc::test {

EllipticCoulomb::EllipticCoulomb(double mu, double a1, double a2) : mu_(mu), a1_(a1), a2_(a2) {
  require(mu >= 0 && a1 > 0 && a2 > 0 && std::isfinite(mu * a1 * a2), "elliptic-coulomb: mu >= 0 and axes > 0");
}

EllipticCoulomb::EllipticCoulomb(FrictionKeys& keys)
    : EllipticCoulomb(keys.number("mu"), keys.number("axis_1", 1.0), keys.number("axis_2", 1.0)) {}

std::string EllipticCoulomb::describe() const {
  return fmt::format("elliptic Coulomb friction mu = {}, axes {} and {}", mu_, a1_, a2_);
}

double EllipticCoulomb::gauge(const double* l, int t) const {
  double g2 = 0;
  for (int j = 0; j < t; ++j) g2 += (l[j] / axis(j)) * (l[j] / axis(j));
  return std::sqrt(g2);
}

double EllipticCoulomb::dual_gauge(const double* d, int t) const {
  double g2 = 0;
  for (int j = 0; j < t; ++j) g2 += (axis(j) * d[j]) * (axis(j) * d[j]);
  return std::sqrt(g2);
}

double EllipticCoulomb::multiplier(const double* z, int t, double r) const {
  // F(θ) = Σ z_j² A_j / (A_j + θ)² − 1 is convex and decreasing on θ ≥ 0 with F(0) > 0 outside C_r:
  // Newton from 0 increases monotonically to the root.
  double theta = 0;
  for (int it = 0; it < 200; ++it) {
    double F = -1, dF = 0;
    for (int j = 0; j < t; ++j) {
      const double A = r * axis(j) * r * axis(j), D = A + theta;
      F += z[j] * z[j] * A / (D * D);
      dF -= 2 * z[j] * z[j] * A / (D * D * D);
    }
    const double next = theta - F / dF;
    if (!(next > theta) || next - theta <= 1e-16 * next) return std::max(next, theta);
    theta = next;
  }
  return theta;
}

void EllipticCoulomb::project(const double* z, int t, double r, double* p) const {
  if (r == 0) {
    for (int j = 0; j < t; ++j) p[j] = 0;
    return;
  }
  const double theta = multiplier(z, t, r);
  for (int j = 0; j < t; ++j) {
    const double A = r * axis(j) * r * axis(j);
    p[j] = z[j] * A / (A + theta);
  }
}

void EllipticCoulomb::project_derivative(const double* z, int t, double s, double* dp_dz, double* dp_ds) const {
  if (s == 0) {  // C_s = {0}: p = s q + o(s), q the point of C_1 where z·q is largest: q_j = a_j² z_j / |z|_C*
    const double g = dual_gauge(z, t);
    for (int j = 0; j < t; ++j) {
      dp_ds[j] = axis(j) * axis(j) * z[j] / g;
      for (int l = 0; l < t; ++l) dp_dz[j * t + l] = 0;
    }
    return;
  }
  // p_j = z_j A_j / D_j, D_j = A_j + θ, and θ(z, s) from F = Σ z_j² A_j / D_j² − 1 = 0 (implicit function).
  const double theta = multiplier(z, t, s);
  double A[2], D[2], F_theta = 0, F_s = 0;
  for (int j = 0; j < t; ++j) {
    A[j] = s * axis(j) * s * axis(j);
    D[j] = A[j] + theta;
    F_theta -= 2 * z[j] * z[j] * A[j] / (D[j] * D[j] * D[j]);
    F_s += z[j] * z[j] * (2 * A[j] / s) * (theta - A[j]) / (D[j] * D[j] * D[j]);  // ∂A_j/∂s = 2 A_j / s
  }
  const double theta_s = -F_s / F_theta;
  for (int j = 0; j < t; ++j) {
    dp_ds[j] = z[j] * ((2 * A[j] / s) * theta - A[j] * theta_s) / (D[j] * D[j]);
    for (int l = 0; l < t; ++l) {
      const double theta_l = -(2 * z[l] * A[l] / (D[l] * D[l])) / F_theta;
      dp_dz[j * t + l] = (j == l ? A[j] / D[j] : 0.0) - z[j] * A[j] / (D[j] * D[j]) * theta_l;
    }
  }
}

WornCoulomb::WornCoulomb(double mu, double wear, double gap_share) : mu_(mu), wear_(wear), gap_share_(gap_share) {
  require(mu >= 0 && wear >= 0 && gap_share >= 0 && std::isfinite(mu) && std::isfinite(wear) && std::isfinite(gap_share),
          "worn-coulomb: mu >= 0, wear >= 0 and gap_share >= 0");
}

WornCoulomb::WornCoulomb(FrictionKeys& keys)
    : WornCoulomb(keys.number("mu"), keys.number("wear_factor", 1.0), keys.number("gap_share", 0.0)) {}

std::string WornCoulomb::describe() const { return fmt::format("Coulomb friction mu = {} with wear {}", mu_, wear_); }

std::vector<SurfaceVariable> WornCoulomb::surface_state() const {
  return {{"worn", 1, 0.0, "Archard's worn depth Σ wear λ_ν / |Γ3| |Δ| (test law)", "worn_volume"},
          {"slip_path", 2, 0.0, "the slip path Σ |Δ| and the steps that updated it (test law)", ""}};
}

SurfaceUpdate WornCoulomb::update_surface(const SurfaceNode& node, std::span<double* const> values) const {
  double slip = 0;
  for (double d : node.slip_step) slip += d * d;
  slip = std::sqrt(slip);
  *values[0] += wear_ * std::max(node.lambda_nu, 0.0) / node.measure * slip;
  values[1][0] += slip;
  values[1][1] += 1;
  return {};
}

SizedCoulomb::SizedCoulomb(double mu, double min_measure) : mu_(mu), min_measure_(min_measure) {
  require(mu >= 0 && min_measure > 0 && std::isfinite(mu) && std::isfinite(min_measure), "sized-coulomb: mu >= 0, min_measure > 0");
}

SizedCoulomb::SizedCoulomb(FrictionKeys& keys) : SizedCoulomb(keys.number("mu"), keys.number("min_measure")) {}

std::string SizedCoulomb::describe() const {
  return fmt::format("Coulomb friction mu = {} for nodes of |Γ3|_i >= {}", mu_, min_measure_);
}

std::vector<SurfaceVariable> SizedCoulomb::surface_state() const {
  return {{"updates", 1, 0.0, "the steps the node was updated in (test law)", ""}};
}

SurfaceUpdate SizedCoulomb::update_surface(const SurfaceNode& node, std::span<double* const> values) const {
  *values[0] += 1;
  SurfaceUpdate out;
  if (node.lambda_nu > 0) out.step_share = min_measure_ / node.measure;
  return out;
}

LawText SizedCoulomb::step_limit() const {
  return {"min_measure",
          fmt::format("a node in contact with |Γ3|_i below min_measure = {} (a finer mesh than the law's)", min_measure_)};
}

AdhesiveSignorini::AdhesiveSignorini(double strength) : strength_(strength) {
  require(strength >= 0 && std::isfinite(strength), "test-adhesive: strength >= 0");
}

AdhesiveSignorini::AdhesiveSignorini(LawKeys& keys) : strength_(keys.number("strength")) {
  if (!(strength_ >= 0 && std::isfinite(strength_)))
    fail("{}: expected a strength >= 0 (an adhesive traction), got {}", keys.where("strength"), strength_);
}

std::string AdhesiveSignorini::describe() const { return fmt::format("adhesive Signorini, strength = {}", strength_); }

std::string AdhesiveSignorini::conflict(const ContactLaw& other) const {
  if (dynamic_cast<const AdhesiveSignorini*>(&other)) return {};
  return fmt::format("laws are an {} and a {}; parts with different laws cannot share a node", kind(), other.kind());
}

void register_test_laws() {
  static const bool registered =
      register_friction_law("elliptic-coulomb",
                            [](FrictionKeys& keys) -> std::shared_ptr<const FrictionLaw> {
                              return std::make_shared<const EllipticCoulomb>(keys);
                            }) &&
      register_friction_law("worn-coulomb",
                            [](FrictionKeys& keys) -> std::shared_ptr<const FrictionLaw> {
                              return std::make_shared<const WornCoulomb>(keys);
                            }) &&
      register_friction_law("sized-coulomb",
                            [](FrictionKeys& keys) -> std::shared_ptr<const FrictionLaw> {
                              return std::make_shared<const SizedCoulomb>(keys);
                            }) &&
      register_contact_law("test-adhesive", [](LawKeys& keys) -> std::shared_ptr<const ContactLaw> {
        return std::make_shared<const AdhesiveSignorini>(keys);
      });
  (void)registered;
}

}  // namespace vpc::test
