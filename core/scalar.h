// Scalar helpers for every scalar type an energy is instantiated with: double, ceres::Jet<double,N> and the
// second-order SecondOrderJet<N,M> of core/jet_arithmetic.h (also Ceres' own nested Jet<Jet<double,M>,N>).
//
// Energy code writes plain constants and Eigen algebra directly (2.0 * x, a.dot(b), a.cross(b).norm(): see
// core/jet_arithmetic.h, included here). What stays here:
//   vec3(p)          the 3-vector stored at p[0..2] as an Eigen vector of T (writable when p is)
//   constant<T>(c)   a constant of type T at any nesting depth (also for Ceres' own nested Jets). In a product,
//                    prefer the plain number: 2.0 * x scales each level of a Jet, constant<T>(2.0) * x is a
//                    full Jet product (for a nested Jet of 3 inputs, 16 products against about 50)
//   valueOf(x)       the plain double value of x
//   V3<T>            a 3-vector as a plain array with dot/cross/norm and a scale by T or by a plain number, from
//                    before Eigen worked for nested Jets; existing stages still use it.
// tests/core/scalar_test.cpp compile-tests every helper for every supported scalar type.
#pragma once

#include "core/jet_arithmetic.h"

#include <Eigen/Core>
#include <ceres/jet.h>

#include <cmath>
#include <type_traits>

namespace jetshell {

template <typename T>
struct ScalarTraits {
  static T constant(double c) { return T(c); }
  static double value(const T& x) { return x; }
};

template <int M>
struct ScalarTraits<InnerJet<M>> {
  static InnerJet<M> constant(double c) { return InnerJet<M>(c); }
  static double value(const InnerJet<M>& x) { return x.a; }
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

/// The 3-vector at p[0..2] as an Eigen vector (a view, no copy): `vec3(x).cross(vec3(x + 3)).norm()`.
template <typename T>
inline Eigen::Map<const Eigen::Matrix<T, 3, 1>> vec3(const T* p) {
  return Eigen::Map<const Eigen::Matrix<T, 3, 1>>(p);
}
/// Writable view: `vec3(y) = a.cross(b).normalized();`.
template <typename T>
inline Eigen::Map<Eigen::Matrix<T, 3, 1>> vec3(T* p) {
  return Eigen::Map<Eigen::Matrix<T, 3, 1>>(p);
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
/// A plain number times a vector of Jets scales each component (no promotion of the number to a Jet).
template <typename T, std::enable_if_t<!std::is_same_v<T, double>, int> = 0>
inline V3<T> operator*(double s, const V3<T>& a) {
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
