// Derivatives of an energy with respect to its parameters, from dual numbers seeded on the parameters.
//
// Input: a templated element energy f(xe, pe, e) -> T over the element's 3K coordinates xe and the term's P
// parameters pe (both of the same scalar type T), a stencil table (K vertex ids per element, -1 = absent),
// positions x (3N) and parameter values p (P).
// Output, accumulated into ParameterDerivatives (core/term.h): ∂E/∂p (P) and ∂²E/∂x∂p (3N × P).
// Scalar: SecondOrderJet<3K, P> (core/jet_arithmetic.h): the outer duals are seeded on the coordinates, the inner
// ones on the parameters, so E.a.v = ∂E/∂p and E.v[i].v[j] = ∂²E/∂x_i∂p_j. Cost per element ≈ (3K + 1)(P + 1) times
// the double energy: cheap for the few parameters a term has. No finite differences, no hand derivatives.
#pragma once

#include "core/scalar.h"
#include "core/stencil.h"
#include "core/term.h"

#include <Eigen/Core>
#include <ceres/jet.h>

#include <string>
#include <vector>

namespace jetshell {

/// Sizes out for ndof coordinates and P parameters and zeroes it.
inline void resetParameterDerivatives(ParameterDerivatives& out, Eigen::Index ndof, int numParameters) {
  out.energy = Eigen::VectorXd::Zero(numParameters);
  out.mixed = Eigen::MatrixXd::Zero(ndof, numParameters);
}

/// Adds ∂E/∂p and ∂²E/∂x∂p of Σ_e f(x_e, p, e) over the elements of table (width K) to out (sized by
/// resetParameterDerivatives). Serial: parameter derivatives serve fitting and checks, not the inner loop.
template <int K, int P, typename F>
void addParameterDerivatives(const StencilTable& table, const Eigen::VectorXd& x, const double* p, const F& f,
                             ParameterDerivatives& out) {
  static_assert(P > 0, "a term without parameters has no parameter derivatives");
  constexpr int M = 3 * K;
  using J1 = InnerJet<P>;
  using J2 = SecondOrderJet<M, P>;
  J2 pj[P];
  for (int j = 0; j < P; ++j) pj[j] = J2(J1(p[j], j));
  const int ne = table.size();
  for (int e = 0; e < ne; ++e) {
    const int* ids = table.element(e);
    J2 xj[M];
    for (int k = 0; k < K; ++k) {
      for (int c = 0; c < 3; ++c) {
        const int i = 3 * k + c;
        xj[i] = J2(J1(ids[k] >= 0 ? x[3 * ids[k] + c] : 0.0));
        xj[i].v[i] = J1(1.0);
      }
    }
    const J2 E = f(static_cast<const J2*>(xj), static_cast<const J2*>(pj), e);
    for (int j = 0; j < P; ++j) out.energy[j] += E.a.v[j];
    for (int k = 0; k < K; ++k) {
      if (ids[k] < 0) continue;
      for (int c = 0; c < 3; ++c)
        for (int j = 0; j < P; ++j) out.mixed(3 * ids[k] + c, j) += E.v[3 * k + c].v[j];
    }
  }
}

/// Checks a replacement parameter vector's size and finiteness (InputError naming the term and parameter).
void validateParameterValues(const std::string& term, const std::vector<std::string>& names,
                             const std::vector<double>& values);

/// One-vertex stencils 0..n−1 (for per-vertex terms such as loads and masses).
StencilTable vertexStencils(int numVertices);

}  // namespace jetshell
