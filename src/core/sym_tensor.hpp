#pragma once
// Symmetric second-order tensor, always stored with all six components so that
// laws are written once for d = 1, 2, 3. In d < 3 the out-of-plane components
// stay zero, except σ33 in plane strain (Elasticity::restrict_stress).
#include <array>
#include <cmath>

namespace vpc {

struct SymTensor {
  // Component order: 11, 22, 33, 23, 13, 12.
  std::array<double, 6> c{};

  static SymTensor zero() { return {}; }
  static SymTensor identity() { return {{1, 1, 1, 0, 0, 0}}; }

  double& operator[](int i) { return c[i]; }
  double operator[](int i) const { return c[i]; }

  /// Component (i, j), 0-based.
  double operator()(int i, int j) const {
    if (i == j) return c[i];
    const int k = 3 - i - j;  // (1,2)->0 -> index 3, (0,2)->1 -> 4, (0,1)->2 -> 5
    return c[3 + k];
  }

  double trace() const { return c[0] + c[1] + c[2]; }

  /// Frobenius product τ : η = Σ τ_ij η_ij.
  double dot(const SymTensor& o) const {
    return c[0] * o.c[0] + c[1] * o.c[1] + c[2] * o.c[2] +
           2.0 * (c[3] * o.c[3] + c[4] * o.c[4] + c[5] * o.c[5]);
  }
  /// Euclidean (Frobenius) norm |τ|, the norm of R(β) in the Perzyna law (4.3).
  double norm() const { return std::sqrt(dot(*this)); }

  SymTensor deviator() const {
    SymTensor d = *this;
    const double m = trace() / 3.0;
    d.c[0] -= m;
    d.c[1] -= m;
    d.c[2] -= m;
    return d;
  }

  /// Von Mises norm: ½[(τ11−τ22)² + (τ22−τ33)² + (τ33−τ11)²] + 3(τ12² + τ23² + τ13²),
  /// which is (4.10) when τ33 = τ13 = τ23 = 0.
  double von_mises() const {
    const double a = c[0] - c[1], b = c[1] - c[2], d = c[2] - c[0];
    const double s = 0.5 * (a * a + b * b + d * d) + 3.0 * (c[3] * c[3] + c[4] * c[4] + c[5] * c[5]);
    return std::sqrt(s > 0 ? s : 0.0);
  }

  SymTensor& operator+=(const SymTensor& o) {
    for (int i = 0; i < 6; ++i) c[i] += o.c[i];
    return *this;
  }
  SymTensor& operator-=(const SymTensor& o) {
    for (int i = 0; i < 6; ++i) c[i] -= o.c[i];
    return *this;
  }
  SymTensor& operator*=(double s) {
    for (auto& v : c) v *= s;
    return *this;
  }
  friend SymTensor operator+(SymTensor a, const SymTensor& b) { return a += b; }
  friend SymTensor operator-(SymTensor a, const SymTensor& b) { return a -= b; }
  friend SymTensor operator*(double s, SymTensor a) { return a *= s; }
  friend SymTensor operator*(SymTensor a, double s) { return a *= s; }
};

using Point = std::array<double, 3>;

/// P_Q onto S_d: zeroes the components a d-dimensional tensor does not have.
inline void restrict_to_dim(SymTensor& s, int d) {
  if (d == 3) return;
  s[2] = s[3] = s[4] = 0;
  if (d == 1) s[1] = s[5] = 0;
}

}  // namespace vpc
