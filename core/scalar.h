// Scalar helpers that work for double, ceres::Jet<double,N> and nested ceres::Jet<ceres::Jet<double,N>,M>.
//
// Ceres 2.1's nested Jets do not mix with plain double constants (`x * 2.0` picks the inner-Jet overload and
// fails; `JJ(2.0)` fails while `JJ(J(2.0))` works), and Eigen reductions on them fail because they construct
// `Scalar(0)`. Energy code therefore writes constants as `constant<T>(2.0)` and uses the reductions below
// instead of Eigen's. tests/core/scalar_test.cpp compile-tests every helper for every supported scalar type.
#pragma once

#include <ceres/jet.h>

#include <cmath>

namespace jetshell {

template <typename T>
struct ScalarTraits {
  static T constant(double c) { return T(c); }
  static double value(const T& x) { return x; }
};

template <typename Inner, int N>
struct ScalarTraits<ceres::Jet<Inner, N>> {
  static ceres::Jet<Inner, N> constant(double c) { return ceres::Jet<Inner, N>(ScalarTraits<Inner>::constant(c)); }
  static double value(const ceres::Jet<Inner, N>& x) { return ScalarTraits<Inner>::value(x.a); }
};

/// A constant of scalar type T (any Jet nesting depth).
template <typename T>
inline T constant(double c) {
  return ScalarTraits<T>::constant(c);
}

/// The plain double value of x (any Jet nesting depth).
template <typename T>
inline double valueOf(const T& x) {
  return ScalarTraits<T>::value(x);
}

/// 3-vectors as plain arrays: no Eigen reductions, so nested Jets work.
template <typename T>
struct V3 {
  T v[3];
  const T& operator[](int i) const { return v[i]; }
  T& operator[](int i) { return v[i]; }
};

template <typename T>
inline V3<T> load3(const T* p) {
  return {{p[0], p[1], p[2]}};
}
template <typename T>
inline V3<T> operator+(const V3<T>& a, const V3<T>& b) {
  return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}};
}
template <typename T>
inline V3<T> operator-(const V3<T>& a, const V3<T>& b) {
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}
template <typename T>
inline V3<T> operator*(const T& s, const V3<T>& a) {
  return {{s * a[0], s * a[1], s * a[2]}};
}
template <typename T>
inline T dot(const V3<T>& a, const V3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <typename T>
inline V3<T> cross(const V3<T>& a, const V3<T>& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
template <typename T>
inline T squaredNorm(const V3<T>& a) {
  return dot(a, a);
}
template <typename T>
inline T norm(const V3<T>& a) {
  using std::sqrt;
  return sqrt(dot(a, a));
}

}  // namespace jetshell
