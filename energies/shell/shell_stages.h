// The stages of the membrane and bending energies (core/stage.h): each a small templated function of the
// geometry in energies/shell/shell_geometry.h, differentiated by the framework with Jets (or, on the analytic
// path, by its twin from energies/shell/analytic_stages.h, checked against the Jets by the tests). How they
// connect is the stage graph of each term (membrane_term.h, bending_term.h); the chain rule between them is the
// framework's (core/stage_graph_evaluator.h).
//
//   FaceCrossStage        (e0, e1) of a face, its own vertex order      -> c = e0 × e1      6 -> 3, bilinear, twin
//   UnitNormalStage       c                                             -> n = c/‖c‖        3 -> 3, twin
//   FaceNormalStage       (e0, e1): the two above composed (core/stage.h) -> n                6 -> 3
//   EdgeMeanStage         (n_A, n_B) of an edge's faces, the edge's order -> m = ½(n_A + n_B)  6 -> 3, affine, twin;
//                         on a boundary edge (n, n)                     -> m = ½(n + n_ghost(n)), the edge's rule
//   KelvinStage           m                                             -> n̄ = m/‖m‖²      3 -> 3, twin
//   SecondFormStage       (e0, e1, n̄0, n̄1, n̄2) of a face                -> b                15 -> 3, bilinear, twin
//   BendingDensityStage   b                                             -> s·area·W_b(B − b) 3 -> 1, twin
//   MetricStage           (e0, e1)                                      -> a = [e_a·e_b]    6 -> 3, bilinear, twin
//   MembraneDensityStage  a                                             -> s·area·W_m(½(a − A)) 3 -> 1, twin
// The bilinear stages declare kConstantHessian: their Hessians are computed once, not per element; the edge mean
// declares kAffine: no Hessian is ever computed for it. The unit normal and the Kelvin inversion also declare
// weighted-Hessian twins (Σ_k w_k ∇²y_k in closed form, core/stage.h) for the exact Hessian's shared nodes, and
// the face normal's two parts, the edge mean, the Kelvin inversion and the second fundamental form pullback twins
// (Jᵀw without J) for a gradient alone.
#pragma once

#include "core/stage.h"
#include "core/topology.h"
#include "energies/shell/analytic_stages.h"
#include "energies/shell/edge_rules.h"
#include "energies/shell/reference_state.h"
#include "energies/shell/shell_geometry.h"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <vector>

namespace jetshell {

template <typename T>
void store3(const V3<T>& v, T* out) {
  for (int k = 0; k < 3; ++k) out[k] = v[k];
}

struct FaceCrossStage {
  static constexpr int kInputs = 6, kOutputs = 3;
  static constexpr bool kConstantHessian = true;
  template <typename T>
  void operator()(const T* z, T* c, int /*face*/) const {
    store3(cross(load3(z), load3(z + 3)), c);
  }
  /// Twin: ∂c/∂e0 = −[e1]×, ∂c/∂e1 = [e0]× (value and Jacobian; the framework fills the constant Hessians).
  void derivatives(const double* z, int face, int order, StageDerivatives<6, 3>& d) const {
    (*this)(z, d.value.data(), face);
    if (order < 1) return;
    d.jacobian << -analytic::crossMatrix(Eigen::Vector3d(z[3], z[4], z[5])),
        analytic::crossMatrix(Eigen::Vector3d(z[0], z[1], z[2]));
  }
  /// Pullback twin: (∂c/∂e0)ᵀ w = e1 × w, (∂c/∂e1)ᵀ w = w × e0.
  void pullback(const double* z, const double* /*c*/, int /*face*/, const double* w, double* zbar) const {
    const V3<double> e0 = load3(z), e1 = load3(z + 3), wv = load3(w);
    store3(cross(e1, wv), zbar);
    store3(cross(wv, e0), zbar + 3);
  }
};

struct UnitNormalStage {
  static constexpr int kInputs = 3, kOutputs = 3;
  template <typename T>
  void operator()(const T* c, T* n, int /*face*/) const {
    store3(unitNormal(load3(c)), n);
  }
  void derivatives(const double* c, int face, int order, StageDerivatives<3, 3>& d) const {
    if (order <= 0) return (*this)(c, d.value.data(), face);
    if (order == 1) return analytic::unitNormal(Eigen::Vector3d(c[0], c[1], c[2]), d.value, d.jacobian);
    analytic::unitNormal(Eigen::Vector3d(c[0], c[1], c[2]), d.value, d.jacobian, d.hessians);
  }
  /// Pullback twin: Jᵀw = (w − n (n·w))/‖c‖ (J = (I − n nᵀ)/‖c‖ is symmetric).
  void pullback(const double* c, const double* n, int /*face*/, const double* w, double* cbar) const {
    const double inv = 1.0 / std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    const double nw = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
    for (int k = 0; k < 3; ++k) cbar[k] = inv * (w[k] - nw * n[k]);
  }
  void weightedHessian(const double* c, int /*face*/, const double* w, Eigen::Matrix3d& C) const {
    analytic::unitNormalWeightedHessian(Eigen::Vector3d(c[0], c[1], c[2]), Eigen::Vector3d(w[0], w[1], w[2]), C);
  }
};

/// The face normal as one node of a chain (cached per face): derivatives chained from the two stages' own.
using FaceNormalStage = ComposedStage<FaceCrossStage, UnitNormalStage>;

/// The mean normal of an edge, m = ½(n_A + n_B) from its faces' normals in the edge's face order; on a
/// boundary edge m = ½(n + n_ghost(n)) under the edge's rule (energies/shell/edge_rules.h), the second input
/// being the face's normal again (unused). Affine in the normals for every rule: no curvature.
struct EdgeMeanStage {
  static constexpr int kInputs = 6, kOutputs = 3;
  static constexpr bool kAffine = true;
  const std::vector<EdgeRule>* rules = nullptr;  // per edge
  const std::vector<EdgeRuleData>* data = nullptr;
  const Topology* topology = nullptr;  // which edges are on the boundary; null: every edge interior
  bool isBoundary(int edge) const { return topology != nullptr && topology->isBoundaryEdge(edge); }
  template <typename T>
  void operator()(const T* z, T* m, int edge) const {
    const V3<T> n = load3(z);
    if (!isBoundary(edge)) return store3(0.5 * (n + load3(z + 3)), m);
    const auto e = static_cast<std::size_t>(edge);
    store3(0.5 * (n + ghostNormal((*rules)[e], n, (*data)[e])), m);
  }
  /// Twin: on an interior edge ½(n_A + n_B), Jacobian [½I ½I]; a boundary edge's rule is differentiated by its
  /// Jets (few edges, every rule).
  void derivatives(const double* z, int edge, int order, StageDerivatives<6, 3>& d) const {
    if (isBoundary(edge)) return stageDerivativesFromJets(*this, z, edge, order, d);
    for (int k = 0; k < 3; ++k) d.value[k] = 0.5 * (z[k] + z[3 + k]);
    if (order < 1) return;
    d.jacobian.setZero();
    for (int k = 0; k < 3; ++k) d.jacobian(k, k) = d.jacobian(k, 3 + k) = 0.5;
    if (order < 2) return;
    for (auto& h : d.hessians) h.setZero();
  }
  /// Pullback twin: on an interior edge (½w, ½w); a boundary edge's from its rule's Jets.
  void pullback(const double* z, const double* /*m*/, int edge, const double* w, double* zbar) const {
    if (isBoundary(edge)) {
      StageDerivatives<6, 3> d;
      stageDerivativesFromJets(*this, z, edge, 1, d);
      Eigen::Map<Eigen::Matrix<double, 6, 1>>(zbar).noalias() =
          d.jacobian.transpose() * Eigen::Map<const Eigen::Vector3d>(w);
      return;
    }
    for (int k = 0; k < 3; ++k) zbar[k] = zbar[3 + k] = 0.5 * w[k];
  }
};

struct KelvinStage {
  static constexpr int kInputs = 3, kOutputs = 3;
  template <typename T>
  void operator()(const T* m, T* nbar, int /*edge*/) const {
    store3(kelvinInversion(load3(m)), nbar);
  }
  void derivatives(const double* m, int edge, int order, StageDerivatives<3, 3>& d) const {
    if (order <= 0) return (*this)(m, d.value.data(), edge);
    if (order == 1) return analytic::kelvinInversion(Eigen::Vector3d(m[0], m[1], m[2]), d.value, d.jacobian);
    analytic::kelvinInversion(Eigen::Vector3d(m[0], m[1], m[2]), d.value, d.jacobian, d.hessians);
  }
  /// Pullback twin: Jᵀw = w/q − 2 (m·w)/q² m with q = ‖m‖² (J = I/q − 2 m mᵀ/q² is symmetric).
  void pullback(const double* m, const double* /*nbar*/, int /*edge*/, const double* w, double* mbar) const {
    const double inv = 1.0 / (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    const double mw = 2.0 * inv * inv * (m[0] * w[0] + m[1] * w[1] + m[2] * w[2]);
    for (int k = 0; k < 3; ++k) mbar[k] = inv * w[k] - mw * m[k];
  }
  void weightedHessian(const double* m, int /*edge*/, const double* w, Eigen::Matrix3d& C) const {
    analytic::kelvinInversionWeightedHessian(Eigen::Vector3d(m[0], m[1], m[2]), Eigen::Vector3d(w[0], w[1], w[2]), C);
  }
};

struct SecondFormStage {
  static constexpr int kInputs = 15, kOutputs = 3;
  static constexpr bool kConstantHessian = true;
  template <typename T>
  void operator()(const T* z, T* b, int /*face*/) const {
    secondFundamentalForm(load3(z), load3(z + 3), load3(z + 6), load3(z + 9), load3(z + 12), b);
  }
  /// Twin: b00 = 2(n̄1 − n̄0)·e0, b01 = −2 n̄0·e1, b11 = 2(n̄2 − n̄0)·e1, each row's gradient written out (the
  /// framework fills the constant Hessians).
  void derivatives(const double* z, int face, int order, StageDerivatives<15, 3>& d) const {
    (*this)(z, d.value.data(), face);
    if (order < 1) return;
    const Eigen::Map<const Eigen::Vector3d> e0(z), e1(z + 3), n0(z + 6), n1(z + 9), n2(z + 12);
    d.jacobian.setZero();
    d.jacobian.block<1, 3>(0, 0) = 2.0 * (n1 - n0).transpose();
    d.jacobian.block<1, 3>(0, 6) = -2.0 * e0.transpose();
    d.jacobian.block<1, 3>(0, 9) = 2.0 * e0.transpose();
    d.jacobian.block<1, 3>(1, 3) = -2.0 * n0.transpose();
    d.jacobian.block<1, 3>(1, 6) = -2.0 * e1.transpose();
    d.jacobian.block<1, 3>(2, 3) = 2.0 * (n2 - n0).transpose();
    d.jacobian.block<1, 3>(2, 6) = -2.0 * e1.transpose();
    d.jacobian.block<1, 3>(2, 12) = 2.0 * e1.transpose();
  }
  /// Pullback twin: the rows above weighted by w, summed per input.
  void pullback(const double* z, const double* /*b*/, int /*face*/, const double* w, double* zbar) const {
    const double a = 2.0 * w[0], c = 2.0 * w[1], d = 2.0 * w[2];
    for (int k = 0; k < 3; ++k) {
      const double e0 = z[k], e1 = z[3 + k], n0 = z[6 + k], n1 = z[9 + k], n2 = z[12 + k];
      zbar[k] = a * (n1 - n0);
      zbar[3 + k] = d * (n2 - n0) - c * n0;
      zbar[6 + k] = -a * e0 - (c + d) * e1;
      zbar[9 + k] = a * e0;
      zbar[12 + k] = d * e1;
    }
  }
};

struct MetricStage {
  static constexpr int kInputs = 6, kOutputs = 3;
  static constexpr bool kConstantHessian = true;
  template <typename T>
  void operator()(const T* z, T* a, int /*face*/) const {
    metric(load3(z), load3(z + 3), a);
  }
  /// Twin: ∂a00 = (2e0, 0), ∂a01 = (e1, e0), ∂a11 = (0, 2e1) (the framework fills the constant Hessians).
  void derivatives(const double* z, int face, int order, StageDerivatives<6, 3>& d) const {
    (*this)(z, d.value.data(), face);
    if (order < 1) return;
    const Eigen::Map<const Eigen::Vector3d> e0(z), e1(z + 3);
    d.jacobian.setZero();
    d.jacobian.block<1, 3>(0, 0) = 2.0 * e0.transpose();
    d.jacobian.block<1, 3>(1, 0) = e1.transpose();
    d.jacobian.block<1, 3>(1, 3) = e0.transpose();
    d.jacobian.block<1, 3>(2, 3) = 2.0 * e1.transpose();
  }
};

/// Twin of an energy stage: s · stvkQuadratic(P, c1, c2, d) (energies/shell/analytic_stages.h) as a stage result,
/// its Hessian only at order 2.
inline void scaledStvkQuadratic(const double P[3], double c1, double c2, const double d3[3], double s, int order,
                                StageDerivatives<3, 1>& d) {
  double W;
  Eigen::Vector3d w;
  if (order >= 2) {
    analytic::stvkQuadratic(P, c1, c2, d3, W, w, d.hessians[0]);
    d.hessians[0] *= s;
  } else {
    analytic::stvkQuadratic(P, c1, c2, d3, W, w);
  }
  d.value[0] = s * W;
  d.jacobian = s * w.transpose();
}

/// An energy density's Hessian from the per-face quadratics its term keeps: H = s · kept[f], or false when none
/// are kept (the stage then runs its Jets).
inline bool keptQuadratic(const std::vector<Eigen::Matrix3d>* kept, double s, int f, Eigen::Matrix3d& H) {
  if (kept == nullptr) return false;
  H = s * (*kept)[static_cast<std::size_t>(f)];
  return true;
}

/// The energy stages read the face's reference (origin B or A, A⁻¹, area) and scale with `scale`. The bending
/// density of a face with moment-free boundary edges (`minimized`, per face and edge; energies/shell/edge_rules.h)
/// is its minimum over those edges' mid-edge normals, a quadratic in b whose matrix the twin reads from
/// `ruledQuadratic` (per face, without the area scale; BendingTerm keeps both up to date).
struct BendingDensityStage {
  static constexpr int kInputs = 3, kOutputs = 1;
  const ShellReference* ref = nullptr;
  double alpha = 0.0, beta = 0.0, scale = 1.0;
  const std::vector<std::array<bool, 3>>* minimized = nullptr;  // null: no moment-free edge
  const std::vector<Eigen::Matrix3d>* ruledQuadratic = nullptr;
  /// The density is a quadratic in b per face: `quadratic` is every face's W'' without the area scale when
  /// BendingTerm keeps it (its ruled quadratics, from Jets), null otherwise (core/stage.h, per-entity quadratic).
  const std::vector<Eigen::Matrix3d>* quadratic = nullptr;
  bool quadraticHessian(int f, Eigen::Matrix3d& H) const { return keptQuadratic(quadratic, scale * ref->area[f], f, H); }
  const bool* minimizedEdges(int f) const {
    static constexpr bool kNone[3] = {false, false, false};
    return minimized != nullptr ? (*minimized)[static_cast<std::size_t>(f)].data() : kNone;
  }
  template <typename T>
  void operator()(const T* b, T* w, int f) const {
    w[0] = (scale * ref->area[f]) * ruledBendingDensity(b, ref->secondFundamentalForm[f].data(),
                                                        ref->inverseMetric[f].data(), alpha, beta, minimizedEdges(f));
  }
  void derivatives(const double* b, int f, int order, StageDerivatives<3, 1>& d) const {
    if (order <= 0) return (*this)(b, d.value.data(), f);
    const double* B = ref->secondFundamentalForm[f].data();
    const double db[3] = {b[0] - B[0], b[1] - B[1], b[2] - B[2]};
    const bool* m = minimizedEdges(f);
    if (m[0] || m[1] || m[2]) {
      const double s = scale * ref->area[f];
      const Eigen::Matrix3d& Q = (*ruledQuadratic)[static_cast<std::size_t>(f)];
      const Eigen::Vector3d e(db[0], db[1], db[2]), q = Q * e;
      d.value[0] = s * 0.5 * e.dot(q);
      d.jacobian = s * q.transpose();
      if (order >= 2) d.hessians[0] = s * Q;
      return;
    }
    scaledStvkQuadratic(ref->inverseMetric[f].data(), alpha, 0.5 * beta, db, scale * ref->area[f], order, d);
  }
};

struct MembraneDensityStage {
  static constexpr int kInputs = 3, kOutputs = 1;
  const ShellReference* ref = nullptr;
  double lambda = 0.0, mu = 0.0, scale = 1.0;
  /// The density is a quadratic in a per face: `quadratic` is every face's W_m'' without the area scale when
  /// MembraneTerm keeps it (from Jets), null otherwise (core/stage.h, per-entity quadratic).
  const std::vector<Eigen::Matrix3d>* quadratic = nullptr;
  bool quadraticHessian(int f, Eigen::Matrix3d& H) const { return keptQuadratic(quadratic, scale * ref->area[f], f, H); }
  template <typename T>
  void operator()(const T* a, T* w, int f) const {
    w[0] = (scale * ref->area[f]) * membraneDensity(a, ref->metric[f].data(), ref->inverseMetric[f].data(), lambda, mu);
  }
  void derivatives(const double* a, int f, int order, StageDerivatives<3, 1>& d) const {
    if (order <= 0) return (*this)(a, d.value.data(), f);
    const double* A = ref->metric[f].data();
    const double da[3] = {a[0] - A[0], a[1] - A[1], a[2] - A[2]};
    scaledStvkQuadratic(ref->inverseMetric[f].data(), 0.25 * lambda, 0.25 * mu, da, scale * ref->area[f], order, d);
  }
};

}  // namespace jetshell
