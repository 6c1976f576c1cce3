#pragma once
#include "material/viscoplastic_law.hpp"

namespace vpc {

/// Perzyna law with damage-dependent yield (4.2)–(4.3):
/// G = −E/(2λ) (σ − P_R(β) σ), R(β) = {τ : |τ| ≤ β σ_Y}, |·| the Euclidean norm.
/// (The OCR of (4.3) reads β σ_Y²; the dimensionally consistent β σ_Y is used.)
class PerzynaLaw : public ViscoplasticLaw {
 public:
  explicit PerzynaLaw(const Parameters& p);
  SymTensor rate(const PointState& s) const override;
  std::string describe() const override;
  /// E/(2λ): ∂G/∂σ = −E/(2λ) (I − ∂P), and ∂P of a projection onto a convex set has its
  /// eigenvalues in [0, 1] (far outside R(β), ∂P → 0: G → −E/(2λ) σ). The same for the von Mises variant.
  Lipschitz lipschitz(double beta) const override;

 protected:
  /// Projection onto R(β); the von Mises variant overrides it.
  virtual SymTensor project(const SymTensor& sigma, double radius, int dim) const;
  double E_, lambda_, sigma_y_;
};

/// Von Mises variant: R(β) = {τ : |τ|_VM ≤ β σ_Y}, P the closest point in the
/// von Mises metric: radial return of the deviator in 3D (the mean stress is kept);
/// in d ≤ 2, where (4.10) is a norm on S_d, radial scaling of τ.
class PerzynaVonMisesLaw final : public PerzynaLaw {
 public:
  using PerzynaLaw::PerzynaLaw;
  std::string describe() const override;

 protected:
  SymTensor project(const SymTensor& sigma, double radius, int dim) const override;
};

}  // namespace vpc
