#pragma once
// The elasticity tensor ℰ of (2.1): 1D (σ = Eε), plane stress (4.7), plane strain
// and 3D isotropic. Plane strain (ε33 = ε13 = ε23 = 0) carries the out-of-plane
// stress σ33 = λ(ε11 + ε22) + z33 of the 3D law: G evolves z33 like the in-plane
// components, and G, φ and every norm act on the full 3D tensor. Plane stress has
// σ33 = 0, and (4.10) is then the von Mises norm.
#include "core/sym_tensor.hpp"

#include <Eigen/Dense>
#include <string>
#include <vector>

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

  /// ℰε (plane strain: with σ33 = λ(ε11 + ε22)).
  SymTensor apply(const SymTensor& eps) const;
  /// The dimension of the stress tensors the laws see (PointState::dim): d, except
  /// 3 in plane strain, where σ33 ≠ 0 and the von Mises norm is a 3D one.
  int stress_dim() const;
  /// The components a stress (and G, z) has in this model, in SymTensor order:
  /// 1D 11; plane stress 11, 22, 12; plane strain 11, 22, 33, 12; 3D all six.
  std::vector<int> stress_components() const;
  /// P_Q of step 1: zeroes the components a stress does not have in this model.
  void restrict_stress(SymTensor& s) const;
  /// ℰ as a matrix on engineering Voigt strains: d = 1: (ε11); d = 2: (ε11, ε22, 2ε12);
  /// d = 3: (ε11, ε22, ε33, 2ε23, 2ε13, 2ε12).
  Eigen::MatrixXd voigt() const;

 private:
  Kind kind_;
  double E_, nu_;
  double lambda_ = 0, mu_ = 0;  // Lamé constants (plane strain, 3D)
};

}  // namespace vpc
