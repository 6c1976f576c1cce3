#pragma once
// The elasticity tensor ℰ of (2.1): 1D (σ = Eε), plane stress (4.7), plane strain
// and 3D isotropic. Plane strain keeps only the in-plane components (σ33 is not
// stored), so G and φ act on the in-plane stress with (4.10) as its norm.
#include "core/sym_tensor.hpp"

#include <Eigen/Dense>
#include <string>

namespace vpc {

class Elasticity {
 public:
  enum class Kind { Uniaxial, PlaneStress, PlaneStrain, Isotropic };

  Elasticity(Kind kind, double young, double poisson);
  /// Kind by name: "1d", "plane-stress", "plane-strain", "isotropic".
  static Elasticity from_name(const std::string& name, double young, double poisson);

  Kind kind() const { return kind_; }
  std::string name() const;
  int dim() const;
  double young() const { return E_; }
  double poisson() const { return nu_; }

  /// ℰε.
  SymTensor apply(const SymTensor& eps) const;
  /// ℰ as a matrix on engineering Voigt strains: d = 1: (ε11); d = 2: (ε11, ε22, 2ε12);
  /// d = 3: (ε11, ε22, ε33, 2ε23, 2ε13, 2ε12).
  Eigen::MatrixXd voigt() const;

 private:
  Kind kind_;
  double E_, nu_;
  double lambda_ = 0, mu_ = 0;  // Lamé constants (plane strain, 3D)
};

}  // namespace vpc
