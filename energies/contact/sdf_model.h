// The signed distance of a collider as a function of a point, for any scalar type: the second-order Taylor
// model d(x) ≈ d₀ + ∇d·(x − x₀) + ½ (x − x₀)ᵀ ∇²d (x − x₀) around x₀ = the point's value. With duals the point
// is evaluated at x₀ itself, so value, gradient and Hessian are exactly those of the collider's distance there
// (Jets carry at most second derivatives). Input: a sample (energies/contact/volume_shapes.h) taken at x₀.
#pragma once

#include "core/scalar.h"
#include "energies/contact/volume_shapes.h"

namespace jetshell {

template <typename T>
inline Eigen::Vector3d valueOf3(const V3<T>& x) {
  return Eigen::Vector3d(valueOf(x[0]), valueOf(x[1]), valueOf(x[2]));
}

template <typename T>
T signedDistanceModel(const SdfSample& s, const V3<T>& x, const Eigen::Vector3d& x0) {
  V3<T> dx;
  for (int i = 0; i < 3; ++i) dx[i] = x[i] - x0[i];
  T d = constant<T>(s.distance);
  for (int i = 0; i < 3; ++i) {
    d += s.gradient[i] * dx[i];
    for (int j = 0; j < 3; ++j)
      if (s.hessian(i, j) != 0.0) d += (0.5 * s.hessian(i, j)) * dx[i] * dx[j];
  }
  return d;
}

}  // namespace jetshell
