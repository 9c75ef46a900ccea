// Boundary-edge rules of the bending term: how the mid-edge normal of a boundary edge is closed.
//
// The mid-edge normal of a boundary edge is n̄ = kelvinInversion(½(n + n_ghost)), n the face's current unit
// normal and n_ghost the normal of the missing ("ghost") neighbour. A rule is
//   ghostNormal(rule, n, data)  one templated function of n (any scalar type T: double, Jets of any nesting
//                               depth) and per-edge constants fixed when the rule is set (EdgeRuleData: the
//                               face's reference unit normal r, and a unit vector `axis` for rules that need a
//                               direction: a symmetry plane's normal), returning n_ghost; and, for the
//                               moment-free edge only,
//   minimizedOverMomentFreeEdges(κ, minimized, G)  the face's density minimized over the boundary mid-edge
//                               normals' components across its moment-free edges, in closed form.
// The bending term's stage graph (energies/shell/bending_graph.cpp) differentiates both with Jets as stages (the
// ghost as a 3 → 3 stage, the minimized density as the face's 3 → 1 density stage), so a rule needs no derivatives.
//
// The rules:
//   page_free          n_ghost = n: n̄ = n (the page's free edge; first order on twisted and bent patches)
//   reference_clamp    n_ghost = r: the missing neighbour keeps the reference normal (the page's clamp; the
//                      mid-edge normal turns by half the face's rotation: first order, too soft)
//   mirrored_clamp     n_ghost = 2(n·r) r − n: the mean normal stays along r, so n̄ = r/(n·r) (second order)
//   second_order_free  n̄ = n + a·u, u the unit in-plane direction across the edge, a minimized out per face:
//                      the edge carries no moment (M_nn = 0, the free edge's natural condition). The ghost is n
//                      (a = 0); the minimization acts on the face's density (below).
//   symmetry_plane     n_ghost = n − 2(n·p) p, p = axis the plane's unit normal: the mean normal stays in the
//                      plane, as the normal of a symmetric shell on its symmetry plane does.
//
// To add a ghost rule: an enumerator before Count, its name in edgeRuleName(), one case in ghostNormal().
#pragma once

#include "core/scalar.h"

#include <cstdint>
#include <string>

namespace jetshell {

enum class EdgeRule : std::uint8_t {
  PageFree,         // n_ghost = n: the page's free edge (first order)
  ReferenceClamp,   // n_ghost = r: the missing neighbour keeps the reference normal (clamped edge, first order)
  MirroredClamp,    // n_ghost = 2(n·r) r − n: the mean normal stays along r, so n̄ = r/(n·r) (clamped edge)
  SecondOrderFree,  // n̄ = n + a·u with a minimized out per face: no moment across the edge (free edge)
  SymmetryPlane,    // n_ghost = n − 2(n·p) p, p = axis: the mean normal stays in the plane
  Count
};

/// Per-edge constants of a rule.
struct EdgeRuleData {
  double reference[3] = {0.0, 0.0, 1.0};  // r: the face's reference unit normal
  double axis[3] = {0.0, 0.0, 0.0};       // p: a symmetry plane's unit normal (SymmetryPlane only)
};

/// "page_free" | "reference_clamp" | "mirrored_clamp" | "second_order_free" | "symmetry_plane".
inline const char* edgeRuleName(EdgeRule rule) {
  switch (rule) {
    case EdgeRule::PageFree: return "page_free";
    case EdgeRule::ReferenceClamp: return "reference_clamp";
    case EdgeRule::MirroredClamp: return "mirrored_clamp";
    case EdgeRule::SecondOrderFree: return "second_order_free";
    case EdgeRule::SymmetryPlane: return "symmetry_plane";
    case EdgeRule::Count: break;
  }
  return "?";
}

/// The rule named `name`; throws InputError (core/mesh.h) listing the names otherwise.
EdgeRule edgeRuleFromString(const std::string& name);

/// Whether the rule holds reference data or a fixed direction (the energy then sees rigid motions).
inline bool ruleSeesRigidMotion(EdgeRule rule) {
  return rule == EdgeRule::ReferenceClamp || rule == EdgeRule::MirroredClamp || rule == EdgeRule::SymmetryPlane;
}

/// Whether the edge's mid-edge normal is minimized out of the face's density (the moment-free edge).
inline bool minimizesMoment(EdgeRule rule) { return rule == EdgeRule::SecondOrderFree; }

/// The ghost neighbour's normal across a boundary edge of a face with current unit normal n.
template <typename T>
V3<T> ghostNormal(EdgeRule rule, const V3<T>& n, const EdgeRuleData& data) {
  switch (rule) {
    case EdgeRule::ReferenceClamp:
    case EdgeRule::MirroredClamp: {
      const V3<T> r{{constant<T>(data.reference[0]), constant<T>(data.reference[1]), constant<T>(data.reference[2])}};
      if (rule == EdgeRule::ReferenceClamp) return r;
      return (2.0 * dot(n, r)) * r - n;
    }
    case EdgeRule::SymmetryPlane: {
      const V3<T> p{{constant<T>(data.axis[0]), constant<T>(data.axis[1]), constant<T>(data.axis[2])}};
      return n - (2.0 * dot(n, p)) * p;
    }
    case EdgeRule::PageFree:
    case EdgeRule::SecondOrderFree:  // a = 0: the mid-edge normal is the face's
    case EdgeRule::Count: break;
  }
  return n;
}

/// The moment-free edge i of a face changes b = 2[(n̄1 − n̄0)·e0, −n̄0·e1, (n̄2 − n̄0)·e1] (shell_geometry.h) by
/// a·δ_i when its mid-edge normal becomes n + a·u. With u ⟂ edge i in the face's plane, u·e_a are signed
/// heights: edge 0 (x1x2) gives −2a(u·e0, u·e1, u·e1) with u·e0 = u·e1 (u ⟂ e1 − e0), edge 1 (x2x0) gives
/// 2a(u·e0, 0, 0) and edge 2 (x0x1) gives 2a(0, 0, u·e1). Up to a nonzero factor, which the minimization over
/// a absorbs, δ_i is therefore a constant: (1, 1, 1), (1, 0, 0), (0, 0, 1).
inline const double* momentFreeDirection(int i) {
  static constexpr double kDirections[3][3] = {{1.0, 1.0, 1.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};
  return kDirections[i];
}

/// min over a of ½ G(κ − Σ_j a_j δ_j, κ − Σ_j a_j δ_j), j over the edges marked in `minimized` (κ = B − b at
/// a = 0, δ_j = momentFreeDirection(j)), in closed form: ½ G(κ, κ) − ½ gᵀ Q⁻¹ g with g_j = G(κ, δ_j),
/// Q_jk = G(δ_j, δ_k). G(u, v) is the density's symmetric bilinear form on T[3] (W = ½ G(κ, κ)), positive
/// definite for β > 0, so Q is; the result is a quadratic in κ (a Schur complement: PSD where W is).
template <typename T, typename Bilinear>
T minimizedOverMomentFreeEdges(const T kappa[3], const bool minimized[3], const Bilinear& G) {
  T d[3][3];
  int m = 0;
  for (int i = 0; i < 3; ++i) {
    if (!minimized[i]) continue;
    for (int k = 0; k < 3; ++k) d[m][k] = constant<T>(momentFreeDirection(i)[k]);
    ++m;
  }
  T energy = 0.5 * G(kappa, kappa);
  if (m == 0) return energy;
  T g[3], Q[3][3];
  for (int j = 0; j < m; ++j) {
    g[j] = G(kappa, d[j]);
    for (int k = 0; k <= j; ++k) Q[j][k] = Q[k][j] = G(d[j], d[k]);
  }
  // Cholesky-free Gaussian elimination on the (at most 3 × 3) symmetric positive definite Q.
  T y[3];
  for (int j = 0; j < m; ++j) y[j] = g[j];
  for (int c = 0; c < m; ++c)
    for (int r = c + 1; r < m; ++r) {
      const T f = Q[r][c] / Q[c][c];
      for (int k = c; k < m; ++k) Q[r][k] = Q[r][k] - f * Q[c][k];
      y[r] = y[r] - f * y[c];
    }
  T z[3];
  for (int c = m - 1; c >= 0; --c) {
    z[c] = y[c];
    for (int k = c + 1; k < m; ++k) z[c] = z[c] - Q[c][k] * z[k];
    z[c] = z[c] / Q[c][c];
  }
  for (int j = 0; j < m; ++j) energy = energy - 0.5 * g[j] * z[j];
  return energy;
}

}  // namespace jetshell
