// The discrete shell geometry, written once as templated functions of the scalar type (double, Ceres Jets of
// any nesting depth). The membrane and bending energies, the reference state and the derivative checks all
// call these; the staged derivatives differentiate exactly these functions.
//
// Notation follows ../shared/spec/SHELL_MODEL.md: e0 = x1 − x0, e1 = x2 − x0; a = [e_a·e_b];
// n̄_i = m_i / ‖m_i‖² with m_i = ½(n_A + n_B) for the edge opposite vertex i (Kelvin inversion);
// b = 2 [[(n̄1 − n̄0)·e0, −n̄0·e1], [−n̄0·e1, (n̄2 − n̄0)·e1]]. Symmetric 2×2 tensors are (t00, t01, t11).
#pragma once

#include "core/scalar.h"
#include "energies/shell/edge_rules.h"

namespace jetshell {

/// Metric a = (e0·e0, e0·e1, e1·e1).
template <typename T>
void metric(const V3<T>& e0, const V3<T>& e1, T a[3]) {
  a[0] = dot(e0, e0);
  a[1] = dot(e0, e1);
  a[2] = dot(e1, e1);
}

/// Unit normal from the (unnormalized) cross product c = e0 × e1.
template <typename T>
V3<T> unitNormal(const V3<T>& c) {
  const T inv = 1.0 / norm(c);
  return inv * c;
}

/// Kelvin inversion of the mean normal m = ½(n_A + n_B): n̄ = m / ‖m‖².
template <typename T>
V3<T> kelvinInversion(const V3<T>& m) {
  const T inv = 1.0 / squaredNorm(m);
  return inv * m;
}

/// Mid-edge normal of an edge whose two adjacent unit face normals are nA and nB (nB = nA on the boundary).
template <typename T>
V3<T> midEdgeNormal(const V3<T>& nA, const V3<T>& nB) {
  return kelvinInversion(0.5 * (nA + nB));
}

/// Discrete second fundamental form from the face's edge vectors and its three mid-edge normals.
template <typename T>
void secondFundamentalForm(const V3<T>& e0, const V3<T>& e1, const V3<T>& n0, const V3<T>& n1, const V3<T>& n2,
                           T b[3]) {
  b[0] = 2.0 * dot(n1 - n0, e0);
  b[1] = -2.0 * dot(n0, e1);
  b[2] = 2.0 * dot(n2 - n0, e1);
}

/// tr(P t) for symmetric P, t stored as (00, 01, 11).
template <typename T>
T trace(const double P[3], const T t[3]) {
  return P[0] * t[0] + (2.0 * P[1]) * t[1] + P[2] * t[2];
}

/// tr(P t P t) for symmetric P, t.
template <typename T>
T traceOfSquare(const double P[3], const T t[3]) {
  const T pt00 = P[0] * t[0] + P[1] * t[1], pt01 = P[0] * t[1] + P[1] * t[2];
  const T pt10 = P[1] * t[0] + P[2] * t[1], pt11 = P[1] * t[1] + P[2] * t[2];
  return pt00 * pt00 + 2.0 * pt01 * pt10 + pt11 * pt11;
}

/// St. Venant–Kirchhoff membrane energy density W_m = λ/2 (tr ε)² + μ tr(ε²), ε = ½(a − A), traces with A⁻¹.
/// λ and μ are doubles or duals of type T.
template <typename T, typename Q>
T membraneDensity(const T a[3], const double A[3], const double Ainv[3], const Q& lambda, const Q& mu) {
  const T eps[3] = {0.5 * (a[0] - A[0]), 0.5 * (a[1] - A[1]), 0.5 * (a[2] - A[2])};
  const T tr = trace(Ainv, eps);
  return 0.5 * lambda * tr * tr + mu * traceOfSquare(Ainv, eps);
}

/// Bending energy density W_b = ½(α (tr κ)² + β tr(κ²)), κ = B − b, traces with A⁻¹. α and β are doubles or
/// duals of type T.
template <typename T, typename Q>
T bendingDensity(const T b[3], const double B[3], const double Ainv[3], const Q& alpha, const Q& beta) {
  const T kappa[3] = {B[0] - b[0], B[1] - b[1], B[2] - b[2]};
  const T tr = trace(Ainv, kappa);
  return 0.5 * alpha * tr * tr + 0.5 * beta * traceOfSquare(Ainv, kappa);
}

/// G(u, v) = α tr(Pu) tr(Pv) + β tr(PuPv) for symmetric u, v, P (stored as (00, 01, 11)): the symmetric
/// bilinear form of W_b, W_b(κ) = ½ G(κ, κ). α and β are doubles or duals of type T.
template <typename T, typename Q>
T bendingBilinear(const T u[3], const T v[3], const double P[3], const Q& alpha, const Q& beta) {
  const T pu00 = P[0] * u[0] + P[1] * u[1], pu01 = P[0] * u[1] + P[1] * u[2];
  const T pu10 = P[1] * u[0] + P[2] * u[1], pu11 = P[1] * u[1] + P[2] * u[2];
  const T pv00 = P[0] * v[0] + P[1] * v[1], pv01 = P[0] * v[1] + P[1] * v[2];
  const T pv10 = P[1] * v[0] + P[2] * v[1], pv11 = P[1] * v[1] + P[2] * v[2];
  return alpha * (pu00 + pu11) * (pv00 + pv11) + beta * (pu00 * pv00 + pu01 * pv10 + pu10 * pv01 + pu11 * pv11);
}

/// The face's bending density with its boundary edges' rules: W_b(B − b) when no edge is moment-free, else
/// its minimum over the moment-free edges' mid-edge normals (energies/shell/edge_rules.h,
/// minimizedOverMomentFreeEdges), b taken with those normals at a = 0 (the face's own normal).
template <typename T, typename Q>
T ruledBendingDensity(const T b[3], const double B[3], const double Ainv[3], const Q& alpha, const Q& beta,
                      const bool minimized[3]) {
  if (!(minimized[0] || minimized[1] || minimized[2])) return bendingDensity(b, B, Ainv, alpha, beta);
  const T kappa[3] = {B[0] - b[0], B[1] - b[1], B[2] - b[2]};
  return minimizedOverMomentFreeEdges(
      kappa, minimized, [&](const T* u, const T* v) { return bendingBilinear(u, v, Ainv, alpha, beta); });
}

/// How a face's three stencil edges close: boundary[i] marks edge i as a boundary edge, whose missing
/// neighbour's normal comes from rule[i] (energies/shell/edge_rules.h) with the constants data[i].
struct StencilEdges {
  bool boundary[3] = {false, false, false};
  EdgeRule rule[3] = {EdgeRule::PageFree, EdgeRule::PageFree, EdgeRule::PageFree};
  EdgeRuleData data[3];
  /// minimized[i]: edge i is a boundary edge whose rule minimizes its moment out (second_order_free).
  void minimizedEdges(bool minimized[3]) const {
    for (int i = 0; i < 3; ++i) minimized[i] = boundary[i] && minimizesMoment(rule[i]);
  }
};

/// Everything the bending energy of one face sees, from the 6 stencil positions x (18 values: the face's
/// vertices 0,1,2, then the opposite vertices across edges 0,1,2). A boundary edge's opposite vertex is
/// ignored and the missing normal comes from the edge's rule. The bending term's stage graph
/// (energies/shell/bending_graph.cpp) differentiates the same pieces separately; this composite serves the value,
/// the reference state, parameter derivatives and the whole-stencil nested-Jet reference in the checks.
template <typename T>
void stencilSecondFundamentalForm(const T* x, const StencilEdges& edges, T b[3]) {
  const V3<T> p[3] = {load3(x), load3(x + 3), load3(x + 6)};
  const V3<T> e0 = p[1] - p[0], e1 = p[2] - p[0];
  const V3<T> nA = unitNormal(cross(e0, e1));
  V3<T> nbar[3];
  for (int i = 0; i < 3; ++i) {
    if (edges.boundary[i]) {
      nbar[i] = midEdgeNormal(nA, ghostNormal(edges.rule[i], nA, edges.data[i]));
    } else {
      // The neighbour traverses edge i backwards: its vertices in order are (p[i+2], p[i+1], opposite).
      const V3<T>& q0 = p[(i + 2) % 3];
      const V3<T>& q1 = p[(i + 1) % 3];
      const V3<T> q2 = load3(x + 9 + 3 * i);
      nbar[i] = midEdgeNormal(nA, unitNormal(cross(q1 - q0, q2 - q0)));
    }
  }
  secondFundamentalForm(e0, e1, nbar[0], nbar[1], nbar[2], b);
}

/// The same with every boundary edge free (the page's rule).
template <typename T>
void stencilSecondFundamentalForm(const T* x, const bool boundary[3], T b[3]) {
  StencilEdges edges;
  for (int i = 0; i < 3; ++i) edges.boundary[i] = boundary[i];
  stencilSecondFundamentalForm(x, edges, b);
}

}  // namespace jetshell
