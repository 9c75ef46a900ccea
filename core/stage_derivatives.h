// Forward-mode derivatives of one small stage of a staged energy (value, Jacobian and Hessians), from its
// templated function, with nested Ceres Jets whose size is the stage's input count (3 for every nonlinear
// stage of the shell energies, carried as 4 duals: kJetWidth, core/jet_arithmetic.h). Between stages the chain
// rule is applied by the term (energies/*_term.cpp), so the cost of nesting never grows with the stencil's dof
// count.
#pragma once

#include "core/flatten.h"
#include "core/scalar.h"

#include <Eigen/Core>
#include <ceres/jet.h>

#include <array>

namespace jetshell {

/// f: T[N] -> T (scalar stage). Fills value, gradient and symmetric Hessian.
template <int N, typename F>
JETSHELL_FLATTEN void scalarStageDerivatives(const F& f, const double* z, double& value, Eigen::Matrix<double, N, 1>& gradient,
                            Eigen::Matrix<double, N, N>& hessian) {
  using J2 = SecondOrderJetOf<N>;
  J2 zj[N];
  for (int i = 0; i < N; ++i) zj[i] = secondOrderVariable<N, kJetWidth<N>>(z[i], i);
  const J2 y = f(zj);
  value = y.a.a;
  for (int i = 0; i < N; ++i) {
    gradient[i] = y.a.v[i];
    for (int j = i; j < N; ++j) hessian(i, j) = hessian(j, i) = y.v[i].v[j];
  }
}

/// f: T[N] -> T (scalar stage): value and gradient only, with first-order Jet<double, N> (a gradient-only
/// evaluation has no use for the Hessian that scalarStageDerivatives' nested Jets carry).
template <int N, typename F>
JETSHELL_FLATTEN void scalarStageGradient(const F& f, const double* z, double& value, Eigen::Matrix<double, N, 1>& gradient) {
  using J1 = FirstOrderJetOf<N>;
  J1 zj[N];
  for (int i = 0; i < N; ++i) zj[i] = J1(z[i], i);
  const J1 y = f(static_cast<const J1*>(zj));
  value = y.a;
  gradient = y.v.template head<N>();
}

/// f: V3<T> -> V3<T> (vector stage with 3 inputs). Fills value, Jacobian J(k, i) = ∂y_k/∂z_i and the
/// Hessian of each output component.
template <typename F>
JETSHELL_FLATTEN void vectorStageDerivatives(const F& f, const Eigen::Vector3d& z, Eigen::Vector3d& value, Eigen::Matrix3d& jacobian,
                            std::array<Eigen::Matrix3d, 3>& hessians) {
  using J2 = SecondOrderJetOf<3>;
  V3<J2> zj;
  for (int i = 0; i < 3; ++i) zj[i] = secondOrderVariable<3, kJetWidth<3>>(z[i], i);
  const V3<J2> y = f(zj);
  for (int k = 0; k < 3; ++k) {
    value[k] = y[k].a.a;
    for (int i = 0; i < 3; ++i) {
      jacobian(k, i) = y[k].a.v[i];
      for (int j = i; j < 3; ++j) hessians[k](i, j) = hessians[k](j, i) = y[k].v[i].v[j];
    }
  }
}

/// f: V3<T> -> V3<T>: value and Jacobian only, with first-order Jet<double,3>.
template <typename F>
JETSHELL_FLATTEN void vectorStageJacobian(const F& f, const Eigen::Vector3d& z, Eigen::Vector3d& value, Eigen::Matrix3d& jacobian) {
  using J1 = FirstOrderJetOf<3>;
  V3<J1> zj;
  for (int i = 0; i < 3; ++i) zj[i] = J1(z[i], i);
  const V3<J1> y = f(zj);
  for (int k = 0; k < 3; ++k) {
    value[k] = y[k].a;
    jacobian.row(k) = y[k].v.template head<3>().transpose();
  }
}

}  // namespace jetshell
