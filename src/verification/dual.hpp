#pragma once
// Forward-mode automatic differentiation with dual numbers, nested for second
// derivatives: Dual<double> carries one directional derivative, Dual<Dual<double>>
// a second one. The manufactured solutions are written once as templates of the
// scalar type and differentiated exactly (to round-off) with these.
#include <cmath>

namespace vpc {

template <typename T>
struct Dual {
  T v{};  // value
  T d{};  // derivative along the seeded direction
};

template <typename T> Dual<T> operator+(const Dual<T>& a, const Dual<T>& b) { return {a.v + b.v, a.d + b.d}; }
template <typename T> Dual<T> operator-(const Dual<T>& a, const Dual<T>& b) { return {a.v - b.v, a.d - b.d}; }
template <typename T> Dual<T> operator*(const Dual<T>& a, const Dual<T>& b) { return {a.v * b.v, a.v * b.d + a.d * b.v}; }
template <typename T> Dual<T> operator/(const Dual<T>& a, const Dual<T>& b) {
  return {a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)};
}
template <typename T> Dual<T> operator-(const Dual<T>& a) { return {-a.v, -a.d}; }
template <typename T> Dual<T> operator+(const Dual<T>& a, double s) { return {a.v + s, a.d}; }
template <typename T> Dual<T> operator+(double s, const Dual<T>& a) { return {s + a.v, a.d}; }
template <typename T> Dual<T> operator-(const Dual<T>& a, double s) { return {a.v - s, a.d}; }
template <typename T> Dual<T> operator-(double s, const Dual<T>& a) { return {s - a.v, -a.d}; }
template <typename T> Dual<T> operator*(const Dual<T>& a, double s) { return {a.v * s, a.d * s}; }
template <typename T> Dual<T> operator*(double s, const Dual<T>& a) { return {s * a.v, s * a.d}; }
template <typename T> Dual<T> operator/(const Dual<T>& a, double s) { return {a.v / s, a.d / s}; }

template <typename T> Dual<T> sin(const Dual<T>& a) {
  using std::cos, std::sin;
  return {sin(a.v), cos(a.v) * a.d};
}
template <typename T> Dual<T> cos(const Dual<T>& a) {
  using std::cos, std::sin;
  return {cos(a.v), -(sin(a.v) * a.d)};
}
template <typename T> Dual<T> exp(const Dual<T>& a) {
  using std::exp;
  const T e = exp(a.v);
  return {e, e * a.d};
}

/// The value of a (possibly nested) dual number.
inline double value(double x) { return x; }
template <typename T> double value(const Dual<T>& a) { return value(a.v); }

using D1 = Dual<double>;
using D2 = Dual<D1>;

}  // namespace vpc
