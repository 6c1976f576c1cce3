#include "material/elasticity.hpp"

#include "core/error.hpp"

#include <cmath>

namespace vpc {

Elasticity::Elasticity(Kind kind, double young, double poisson) : kind_(kind), E_(young), nu_(poisson) {
  require(std::isfinite(young) && young > 0, "elasticity: Young's modulus E must be > 0 (got {})", young);
  if (kind != Kind::Uniaxial)
    require(std::isfinite(poisson) && poisson > -1 && poisson < 0.5,
            "elasticity: Poisson's ratio must lie in (-1, 0.5) (got {})", poisson);
  lambda_ = E_ * nu_ / ((1 + nu_) * (1 - 2 * nu_));
  mu_ = E_ / (2 * (1 + nu_));
}

Elasticity Elasticity::from_name(const std::string& name, double young, double poisson) {
  if (name == "1d") return {Kind::Uniaxial, young, poisson};
  if (name == "plane-stress") return {Kind::PlaneStress, young, poisson};
  if (name == "plane-strain") return {Kind::PlaneStrain, young, poisson};
  if (name == "isotropic" || name == "3d") return {Kind::Isotropic, young, poisson};
  fail("elasticity: unknown kind '{}'; expected one of 1d, plane-stress, plane-strain, isotropic", name);
}

std::string Elasticity::name() const {
  switch (kind_) {
    case Kind::Uniaxial: return "1d";
    case Kind::PlaneStress: return "plane-stress";
    case Kind::PlaneStrain: return "plane-strain";
    default: return "isotropic";
  }
}

int Elasticity::dim() const {
  switch (kind_) {
    case Kind::Uniaxial: return 1;
    case Kind::PlaneStress:
    case Kind::PlaneStrain: return 2;
    default: return 3;
  }
}

SymTensor Elasticity::apply(const SymTensor& e) const {
  SymTensor s;
  switch (kind_) {
    case Kind::Uniaxial: s[0] = E_ * e[0]; break;
    case Kind::PlaneStress: {
      // (4.7): (ℰτ)_ab = Eν/(1−ν²)(τ11 + τ22)δ_ab + E/(1+ν) τ_ab.
      const double a = E_ * nu_ / (1 - nu_ * nu_) * (e[0] + e[1]), b = E_ / (1 + nu_);
      s[0] = a + b * e[0];
      s[1] = a + b * e[1];
      s[5] = b * e[5];
      break;
    }
    case Kind::PlaneStrain: {
      const double a = lambda_ * (e[0] + e[1]);
      s[0] = a + 2 * mu_ * e[0];
      s[1] = a + 2 * mu_ * e[1];
      s[2] = a;  // ε33 = 0: the 3D law gives σ33 = λ(ε11 + ε22)
      s[5] = 2 * mu_ * e[5];
      break;
    }
    case Kind::Isotropic: {
      const double a = lambda_ * e.trace();
      for (int i = 0; i < 3; ++i) s[i] = a + 2 * mu_ * e[i];
      for (int i = 3; i < 6; ++i) s[i] = 2 * mu_ * e[i];
      break;
    }
  }
  return s;
}

int Elasticity::stress_dim() const { return kind_ == Kind::PlaneStrain ? 3 : dim(); }

std::vector<int> Elasticity::stress_components() const {
  switch (kind_) {
    case Kind::Uniaxial: return {0};
    case Kind::PlaneStress: return {0, 1, 5};
    case Kind::PlaneStrain: return {0, 1, 2, 5};
    default: return {0, 1, 2, 3, 4, 5};
  }
}

void Elasticity::restrict_stress(SymTensor& s) const {
  if (kind_ != Kind::PlaneStrain) return restrict_to_dim(s, dim());
  s[3] = s[4] = 0;  // σ13 = σ23 = 0 in plane strain; σ33 is kept
}

Eigen::MatrixXd Elasticity::voigt() const {
  switch (kind_) {
    case Kind::Uniaxial: return Eigen::MatrixXd::Constant(1, 1, E_);
    case Kind::PlaneStress: {
      Eigen::MatrixXd D(3, 3);
      const double c = E_ / (1 - nu_ * nu_);
      D << c, c * nu_, 0, c * nu_, c, 0, 0, 0, c * (1 - nu_) / 2;
      return D;
    }
    case Kind::PlaneStrain: {
      Eigen::MatrixXd D(3, 3);
      D << lambda_ + 2 * mu_, lambda_, 0, lambda_, lambda_ + 2 * mu_, 0, 0, 0, mu_;
      return D;
    }
    default: {
      Eigen::MatrixXd D = Eigen::MatrixXd::Zero(6, 6);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) D(i, j) = lambda_;
        D(i, i) += 2 * mu_;
        D(i + 3, i + 3) = mu_;
      }
      return D;
    }
  }
}

}  // namespace vpc
