// The C²-smoothed penalty ramp shared by every contact energy, written once for any scalar type.
//
// Input: a penetration p [m] (positive inside the activation band) and the smoothing width δ > 0 [m].
// Output: R(p) [m²], the energy per unit stiffness; r(p) = R'(p) [m], the force per unit stiffness.
//   r(p) = 0 (p ≤ 0),  p²/(2δ) (0 < p < δ),  p − δ/2 (p ≥ δ):   a ramp max(0, p) with a C¹ corner,
//   R(p) = 0,          p³/(6δ),              p²/2 − δp/2 + δ²/6: C², so Newton sees a continuous Hessian.
// Kinks (where R''' jumps) sit at p = 0 and p = δ.
// G(p) = ∫₀ᵖ s r(s) ds is the primitive the Hunt–Crossley damping potential needs:
//   G(p) = 0, p⁴/(8δ), p³/3 − δp²/4 + δ³/24.
#pragma once

#include "core/scalar.h"
#include "core/term.h"

#include <Eigen/Core>
#include <ceres/jet.h>

#include <cmath>

namespace jetshell {

template <typename T>
T contactRamp(const T& p, double delta) {
  const double v = valueOf(p);
  if (v <= 0.0) return constant<T>(0.0);
  if (v < delta) return p * p * p * (1.0 / (6.0 * delta));
  return 0.5 * p * p - (0.5 * delta) * p + delta * delta / 6.0;
}

template <typename T>
T contactRampForce(const T& p, double delta) {
  const double v = valueOf(p);
  if (v <= 0.0) return constant<T>(0.0);
  if (v < delta) return p * p * (0.5 / delta);
  return p - 0.5 * delta;
}

template <typename T>
T contactRampMoment(const T& p, double delta) {
  const double v = valueOf(p);
  if (v <= 0.0) return constant<T>(0.0);
  if (v < delta) return p * p * p * p * (1.0 / (8.0 * delta));
  return p * p * p * (1.0 / 3.0) - (0.25 * delta) * p * p + delta * delta * delta / 24.0;
}

/// The regularized Coulomb friction primitive f₀ (Li et al., IPC 2020) minus its value at zero slip, for a
/// slip length y ≥ 0 given as y² (so zero slip stays differentiable) and the slip regularization ε_v > 0 [m]:
///   f₀(y) = −y³/(3ε_v²) + y²/ε_v   (y < ε_v),   y − ε_v/3   (y ≥ ε_v).
/// Its derivative f₁ = f₀' rises from 0 to 1 over [0, ε_v]: friction force μλ f₁(y) in the slip direction.
///
/// FrictionHessian::Majorizer returns the same value and first derivatives but the second derivatives of the
/// tangent of f₀ as a function of s = y², F(s₀) + F'(s₀)(s − s₀) with F'(s₀) = f₁(y₀)/(2y₀): F is concave in s,
/// so this quadratic in the slip majorizes the potential and touches it at the iterate (the half-quadratic, or
/// IRLS, model of |u|). Its Hessian in the tangent plane is (f₁(y)/y) I: along the slip the secant curvature
/// f₁/y instead of the exact f₀''(y), which is 0 once sliding (y ≥ ε_v). Measured on the T-shirt: with the exact
/// curvature a vertex held by friction just below its Coulomb limit flips its slip from side to side at every
/// Newton iteration (the exact model sees no friction stiffness once it slides, so each full step overshoots,
/// and one vertex does not move the whole shell's line search); the majorizer's model lies above the potential,
/// so its step does not throw a held vertex past its stick region.
/// The price: a secant model converges linearly, slowly where a contact sticks near its Coulomb limit
/// (BENCHMARKS.md, Contact).
template <typename T>
T frictionPrimitive(const T& y2, double epsV, FrictionHessian model = FrictionHessian::Exact) {
  using std::sqrt;
  const double v2 = valueOf(y2);
  if (model == FrictionHessian::Majorizer) {
    // The tangent at s = v2: F(s) and F'(s) = f₁(y)/(2y) from the exact formula below, on one first-order dual.
    const ceres::Jet<double, 1> F = frictionPrimitive(ceres::Jet<double, 1>(v2, 0), epsV);
    return F.v[0] * (y2 - v2) + F.a;
  }
  if (v2 >= epsV * epsV) return sqrt(y2) - epsV / 3.0;
  // y³ = y²·y has zero first and second derivatives at y = 0, where sqrt's derivative is not finite.
  const T cubic = v2 > 1e-300 ? y2 * sqrt(y2) : constant<T>(0.0);
  return y2 * (1.0 / epsV) - cubic * (1.0 / (3.0 * epsV * epsV));
}

/// |u − (n·u) n|²: the squared length of a displacement u's part in the plane normal to the unit vector n, the
/// slip y² that frictionPrimitive takes (point pairs and volume contact alike).
template <typename T>
T tangentialSlipSquared(const V3<T>& u, const Eigen::Vector3d& n) {
  const T un = n[0] * u[0] + n[1] * u[1] + n[2] * u[2];
  V3<T> ut;
  for (int k = 0; k < 3; ++k) ut[k] = u[k] - n[k] * un;
  return squaredNorm(ut);
}

}  // namespace jetshell
