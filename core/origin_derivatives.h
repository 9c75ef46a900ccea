// Cross derivatives of an energy with a moving origin, along given directions, from dual numbers.
//
// Terms of an incremental potential depend on the current positions x and on an origin y that the time
// integrator sets from the state of earlier steps (a strain or curvature origin, a centre). Sensitivities
// through the time steps need (∂²E/∂x∂y) S for a few directions S of y (one per fitted parameter).
//
// Input: a templated element energy f(xe, ye, e) -> T over the element's 3K coordinates at x and at y (both of
// the same scalar type T), a stencil table (K vertex ids per element, -1 = absent), x and y (3N), the
// directions S (3N × P).
// Output, added into out (3N × P): (∂²E/∂x∂y) S.
// Scalar: SecondOrderJet<3K, P> (core/jet_arithmetic.h): the outer duals are seeded on x, the inner ones carry y's
// tangents (y + S t), so E.v[i].v[j] = Σ_k ∂²E/∂x_i∂y_k S_kj. Cost per element ≈ (3K + 1)(P + 1) times the double
// energy. No finite differences, no hand derivatives.
#pragma once

#include "core/jet_arithmetic.h"
#include "core/mesh.h"
#include "core/stencil.h"

#include <Eigen/Core>
#include <ceres/jet.h>

namespace jetshell {

template <int K, int P, typename F>
void addOriginCrossDerivatives(const StencilTable& table, const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                               const Eigen::MatrixXd& S, const F& f, Eigen::MatrixXd& out) {
  constexpr int M = 3 * K;
  using J1 = InnerJet<P>;
  using J2 = SecondOrderJet<M, P>;
  const int ne = table.size();
  const int cols = static_cast<int>(S.cols());
  for (int e = 0; e < ne; ++e) {
    const int* ids = table.element(e);
    J2 xj[M], yj[M];
    for (int k = 0; k < K; ++k) {
      for (int c = 0; c < 3; ++c) {
        const int i = 3 * k + c;
        const bool present = ids[k] >= 0;
        xj[i] = J2(J1(present ? x[3 * ids[k] + c] : 0.0));
        xj[i].v[i] = J1(1.0);
        J1 yi(present ? y[3 * ids[k] + c] : 0.0);
        if (present)
          for (int j = 0; j < cols; ++j) yi.v[j] = S(3 * ids[k] + c, j);
        yj[i] = J2(yi);
      }
    }
    const J2 E = f(static_cast<const J2*>(xj), static_cast<const J2*>(yj), e);
    for (int k = 0; k < K; ++k) {
      if (ids[k] < 0) continue;
      for (int c = 0; c < 3; ++c)
        for (int j = 0; j < cols; ++j) out(3 * ids[k] + c, j) += E.v[3 * k + c].v[j];
    }
  }
}

/// The same with the inner width P chosen at run time (S.cols() ≤ 8; padded to 1, 2, 4 or 8).
template <int K, typename F>
void addOriginCrossDerivatives(const StencilTable& table, const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                               const Eigen::MatrixXd& S, const F& f, Eigen::MatrixXd& out) {
  const Eigen::Index p = S.cols();
  if (p <= 1) {
    addOriginCrossDerivatives<K, 1>(table, x, y, S, f, out);
  } else if (p <= 2) {
    addOriginCrossDerivatives<K, 2>(table, x, y, S, f, out);
  } else if (p <= 4) {
    addOriginCrossDerivatives<K, 4>(table, x, y, S, f, out);
  } else if (p <= 8) {
    addOriginCrossDerivatives<K, 8>(table, x, y, S, f, out);
  } else {
    throw InputError("origin cross derivatives: at most 8 directions at once");
  }
}

}  // namespace jetshell
