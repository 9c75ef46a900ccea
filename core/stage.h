// A stage: one small templated function of a staged energy, and its local derivatives.
//
// A stage maps N inputs to M outputs (N <= kMaxStageInputs, M <= kMaxStageOutputs) and is written once, for any
// scalar type T (double, Ceres Jets of any nesting depth):
//   struct FaceNormal {
//     static constexpr int kInputs = 6, kOutputs = 3;
//     template <typename T> void operator()(const T* z, T* y, int entity) const;   // entity: whose stage
//   };
// Output of evaluateStage(): StageDerivatives<N, M> = value y (M), Jacobian ∂y/∂z (M×N) and, at order 2, the
// Hessian ∇²y_k (N×N) of each output. They come from Ceres Jets of size N (Jet<double,N> for order 1,
// Jet<Jet<double,N>,N> for order 2; a stage of 3 inputs carries 4 duals, one vector register, kJetWidth in
// core/jet_arithmetic.h), so their cost depends on the stage's inputs only, never on a stencil.
//
// Optional analytic twin, detected at compile time: a stage that also declares
//     void derivatives(const double* z, int entity, int order, StageDerivatives<N, M>& d) const;
// is evaluated by it on DerivativePath::Analytic; stageTwinDiscrepancy() measures it against the Jets (the
// conformance tests call it), so a twin is an optimisation that is always checked, never a second truth. The twin
// of a stage declaring kConstantHessian (below) gives only its value and Jacobian: the framework fills the
// Hessians (twinDerivatives()). A value alone (order 0) is the stage's own call on doubles on every path: a twin
// is asked only for derivatives.
//
// Optional weighted-Hessian twin, detected at compile time: a stage with a twin may also declare
//     void weightedHessian(const double* z, int entity, const double* w, Eigen::Matrix<double, N, N>& C) const;
// C = Σ_k w_k ∇²y_k in closed form, without forming the M Hessians (what a stage graph's exact Hessian needs of
// a shared node, and a composed stage of its outer part). It is used on DerivativePath::Analytic, and
// weightedStageHessian() is the one place that chooses between it and the M Hessians summed;
// stageTwinDiscrepancy() checks it against the same sum of the Jets' Hessians.
//
// Optional pullback twin, detected at compile time: a stage with a twin (or a composed stage whose two parts both
// declare one) may also declare
//     void pullback(const double* z, const double* y, int entity, const double* w, double* zbar) const;
// zbar = J(z)ᵀ w, given the stage's value y at z, without forming J (a unit normal's is (w − n (n·w))/‖c‖). A
// stage graph's gradient alone on DerivativePath::Analytic pulls each Shared node's adjoint back through it
// (core/stage_graph_evaluator.h), so that its forward pass computes values only; stageTwinDiscrepancy() and
// composedStageDiscrepancy() check it against the Jets' Jᵀw.
//
// Optional declaration `static constexpr bool kConstantHessian = true;`: the stage is a polynomial of degree
// at most 2 with fixed coefficients (a bilinear product such as a cross product, a metric or a second
// fundamental form): its Hessians and its Jacobian at z = 0 do not depend on the input, the entity or the
// stage's data. The framework computes them once per stage type (Jets of order 2 on a default-constructed stage
// at z = 0, constantStageHessians()); afterwards the stage runs on doubles only, its Jacobian being
// J(z) = J(0) + [∇²y_k z]_k (no Jets per element). constantHessianDiscrepancy() checks the declaration
// (Hessians and Jacobian) against the Jets at any z.
//
// Optional per-entity quadratic, detected at compile time: a stage of one output that is a quadratic in z for each
// entity (its Hessian depends on the entity and the stage's data, never on z: an energy density quadratic in its
// strain) may declare
//     bool quadraticHessian(int entity, Eigen::Matrix<double, N, N>& H) const;
// returning true with H = ∇²y when its term keeps that Hessian, taken from Jets (never written by hand), up to date.
// Derivatives of order 2 on the Jets then cost those of order 1 (first-order Jets) and the copy; false, or order
// < 2, leaves the stage to its Jets. quadraticHessianDiscrepancy() checks the kept Hessian against the Jets' at z.
//
// Optional declaration `static constexpr bool kAffine = true;`: for each entity the stage is affine in z (its
// coefficients may depend on the entity, e.g. a boundary edge's rule): its Hessians are zero, so derivatives of
// order 2 cost those of order 1 (first-order Jets or the twin) and a chain adds no curvature for it.
// affineDiscrepancy() checks the declaration against the Jets' Hessians at any z.
//
// ComposedStage<Inner, Outer>: Outer ∘ Inner as one stage (for example a face normal 6 → 3 from the cross product
// 6 → 3 and the normalisation 3 → 3), so that a stage graph (core/stage_graph.h) keeps it as one node. Its derivatives come from
// the two stages' own (each on its Jets, twin or constant Hessians) by the chain rule, once per entity:
// J = J_o J_i, ∇²y_k = J_iᵀ ∇²o_k J_i + Σ_m (J_o)_km ∇²i_m, or contracted with output weights w before chaining
// (contractedHessian, what a stage graph's exact Hessian needs). Its Jets (stageDerivativesFromJets) remain the
// reference it is tested against.
#pragma once

#include "core/flatten.h"
#include "core/scalar.h"
#include "core/term.h"

#include <Eigen/Core>
#include <ceres/jet.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

namespace jetshell {

inline constexpr int kMaxStageInputs = 15;
inline constexpr int kMaxStageOutputs = 4;

/// Local derivatives of one stage at one input z. Column-major, fixed size: no allocation.
template <int N, int M>
struct StageDerivatives {
  static_assert(N >= 1 && N <= kMaxStageInputs && M >= 1 && M <= kMaxStageOutputs, "stage size out of range");
  Eigen::Matrix<double, M, 1> value;
  Eigen::Matrix<double, M, N> jacobian;                // ∂y_k/∂z_i at (k, i)
  std::array<Eigen::Matrix<double, N, N>, M> hessians;  // ∇²y_k (symmetric); filled at order 2 only
};

template <typename S>
using StageDerivativesOf = StageDerivatives<S::kInputs, S::kOutputs>;

/// True when stage S declares an analytic twin `derivatives(z, entity, order, d)`.
template <typename S, typename = void>
struct HasStageTwin : std::false_type {};
template <typename S>
struct HasStageTwin<S, std::void_t<decltype(std::declval<const S&>().derivatives(
                           static_cast<const double*>(nullptr), 0, 0, std::declval<StageDerivativesOf<S>&>()))>>
    : std::true_type {};

/// True when stage S declares a weighted-Hessian twin `weightedHessian(z, entity, w, C)`.
template <typename S, typename = void>
struct HasWeightedHessianTwin : std::false_type {};
template <typename S>
struct HasWeightedHessianTwin<S, std::void_t<decltype(std::declval<const S&>().weightedHessian(
                                     static_cast<const double*>(nullptr), 0, static_cast<const double*>(nullptr),
                                     std::declval<Eigen::Matrix<double, S::kInputs, S::kInputs>&>()))>>
    : std::true_type {};

/// True when stage S declares a pullback twin `pullback(z, y, entity, w, zbar)`.
template <typename S, typename = void>
struct HasPullbackTwin : std::false_type {};
template <typename S>
struct HasPullbackTwin<S, std::void_t<decltype(std::declval<const S&>().pullback(
                              static_cast<const double*>(nullptr), static_cast<const double*>(nullptr), 0,
                              static_cast<const double*>(nullptr), static_cast<double*>(nullptr)))>>
    : std::true_type {};

/// True when stage S declares kConstantHessian = true.
template <typename S, typename = void>
struct HasConstantHessian : std::false_type {};
template <typename S>
struct HasConstantHessian<S, std::void_t<decltype(S::kConstantHessian)>> : std::bool_constant<S::kConstantHessian> {};

/// True when stage S declares `quadraticHessian(entity, H)` (a per-entity quadratic, see the top of this file).
template <typename S, typename = void>
struct HasQuadraticHessian : std::false_type {};
template <typename S>
struct HasQuadraticHessian<S, std::void_t<decltype(std::declval<const S&>().quadraticHessian(
                                  0, std::declval<Eigen::Matrix<double, S::kInputs, S::kInputs>&>()))>>
    : std::bool_constant<S::kOutputs == 1> {};

/// True when stage S declares kAffine = true.
template <typename S, typename = void>
struct IsAffineStage : std::false_type {};
template <typename S>
struct IsAffineStage<S, std::void_t<decltype(S::kAffine)>> : std::bool_constant<S::kAffine> {};

/// Value (order 0), + Jacobian (order 1), + Hessians (order 2) of stage s at z, from Ceres Jets of W ≥ N duals
/// (kJetWidth by default; `jetshell bench elements --term stage-jets` compares it with W = N).
template <typename S, int W = kJetWidth<S::kInputs>>
void stageDerivativesFromJets(const S& s, const double* z, int entity, int order, StageDerivativesOf<S>& d) {
  constexpr int N = S::kInputs, M = S::kOutputs;
  static_assert(W >= N, "every input needs a dual");
  if (order <= 0) {
    double y[M];
    s(z, y, entity);
    for (int k = 0; k < M; ++k) d.value[k] = y[k];
  } else if (order == 1) {
    using J1 = ceres::Jet<double, W>;
    J1 zj[N], y[M];
    for (int i = 0; i < N; ++i) zj[i] = J1(z[i], i);
    s(static_cast<const J1*>(zj), y, entity);
    for (int k = 0; k < M; ++k) {
      d.value[k] = y[k].a;
      d.jacobian.row(k) = y[k].v.template head<N>().transpose();
    }
  } else {
    using J2 = SecondOrderJet<N, W>;
    J2 zj[N], y[M];
    for (int i = 0; i < N; ++i) zj[i] = secondOrderVariable<N, W>(z[i], i);
    s(static_cast<const J2*>(zj), y, entity);
    for (int k = 0; k < M; ++k) {
      d.value[k] = y[k].a.a;
      for (int i = 0; i < N; ++i) {
        d.jacobian(k, i) = y[k].a.v[i];
        for (int j = i; j < N; ++j) d.hessians[k](i, j) = d.hessians[k](j, i) = 0.5 * (y[k].v[i].v[j] + y[k].v[j].v[i]);
      }
    }
  }
}

/// stageDerivativesFromJets with every call in it inlined (core/flatten.h): the per-element path of stages whose
/// derivatives come from Jets on every evaluation. One-off uses (constant Hessians, the checks) take the plain
/// function, which compiles several times faster for stages of many inputs.
template <typename S, int W = kJetWidth<S::kInputs>>
JETSHELL_FLATTEN void stageDerivativesFromJetsInlined(const S& s, const double* z, int entity, int order,
                                                      StageDerivativesOf<S>& d) {
  stageDerivativesFromJets<S, W>(s, z, entity, order, d);
}

/// The Hessians of a stage that declares kConstantHessian, computed once per stage type (thread-safe static).
/// `zero` is true when every entry is 0 (a linear stage: no curvature to chain).
template <typename S>
struct ConstantStageHessians {
  std::array<Eigen::Matrix<double, S::kInputs, S::kInputs>, S::kOutputs> hessians;
  bool zero = true;
  Eigen::Matrix<double, S::kOutputs, S::kInputs> jacobianAtZero;
  // The nonzero Hessian entries, (output k, i, j, value): J(z)(k, i) = J(0)(k, i) + Σ value · z_j.
  struct Entry {
    int k, i, j;
    double h;
  };
  std::array<Entry, S::kOutputs * S::kInputs * S::kInputs> entries;
  int numEntries = 0;
};
template <typename S>
const ConstantStageHessians<S>& constantStageHessians() {
  static const ConstantStageHessians<S> h = [] {
    ConstantStageHessians<S> r;
    StageDerivativesOf<S> d;
    const double z[S::kInputs] = {};
    stageDerivativesFromJets(S(), z, 0, 2, d);
    r.hessians = d.hessians;
    r.jacobianAtZero = d.jacobian;
    for (int k = 0; k < S::kOutputs; ++k)
      for (int i = 0; i < S::kInputs; ++i)
        for (int j = 0; j < S::kInputs; ++j)
          if (r.hessians[k](i, j) != 0.0) r.entries[static_cast<std::size_t>(r.numEntries++)] = {k, i, j, r.hessians[k](i, j)};
    r.zero = r.numEntries == 0;
    return r;
  }();
  return h;
}

/// Value and Jacobian of a stage declaring kConstantHessian, on doubles: y = s(z), J(z) = J(0) + [∇²y_k z]_k.
template <typename S>
void constantHessianStageJacobian(const S& s, const double* z, int entity, StageDerivativesOf<S>& d) {
  constexpr int M = S::kOutputs;
  double y[M];
  s(z, y, entity);
  for (int k = 0; k < M; ++k) d.value[k] = y[k];
  const ConstantStageHessians<S>& c = constantStageHessians<S>();
  d.jacobian = c.jacobianAtZero;
  for (int e = 0; e < c.numEntries; ++e) {
    const auto& t = c.entries[static_cast<std::size_t>(e)];
    d.jacobian(t.k, t.i) += t.h * z[t.j];
  }
}

/// max |a − b| relative to b's largest entry (floor 1): how far a derived result is from the Jets' b.
template <typename A, typename B>
double relativeDifference(const A& a, const B& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

/// Largest absolute difference between the Jets' Hessians and Jacobian at z and those the declaration gives
/// (0 for a stage without the declaration): a declaration that does not hold shows here.
template <typename S>
double constantHessianDiscrepancy(const S& s, const double* z, int entity) {
  if constexpr (!HasConstantHessian<S>::value) {
    return 0.0;
  } else {
    StageDerivativesOf<S> jets, fixed;
    stageDerivativesFromJets(s, z, entity, 2, jets);
    constantHessianStageJacobian(s, z, entity, fixed);
    double worst = relativeDifference(fixed.jacobian, jets.jacobian);
    for (int k = 0; k < S::kOutputs; ++k)
      worst = std::max(worst, (jets.hessians[k] - constantStageHessians<S>().hessians[k]).cwiseAbs().maxCoeff());
    return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
  }
}

template <typename Inner, typename Outer>
struct ComposedStage;

/// True when S is a ComposedStage.
template <typename S>
struct IsComposedStage : std::false_type {};
template <typename Inner, typename Outer>
struct IsComposedStage<ComposedStage<Inner, Outer>> : std::true_type {};

template <typename S>
void evaluateStage(const S& s, const double* z, int entity, int order, DerivativePath path, StageDerivativesOf<S>& d);

/// C = Σ_k w_k ∇²y_k of stage s at z on `path`: the weighted-Hessian twin on the analytic path when s declares
/// one, a composed stage's own contraction, else its M Hessians summed. `d`, when given, also receives the value
/// and Jacobian (computed only then): a stage graph's shared node asks for C alone, a composed stage's outer part
/// for both.
template <typename S>
void weightedStageHessian(const S& s, const double* z, int entity, DerivativePath path, const double* w,
                          Eigen::Matrix<double, S::kInputs, S::kInputs>& C, StageDerivativesOf<S>* d = nullptr);

/// Outer ∘ Inner (Inner: N → P, Outer: P → M) as one stage; see the top of this file.
template <typename Inner, typename Outer>
struct ComposedStage {
  static_assert(Inner::kOutputs == Outer::kInputs, "the inner stage's outputs are the outer stage's inputs");
  static constexpr int kInputs = Inner::kInputs, kOutputs = Outer::kOutputs;
  Inner inner;
  Outer outer;
  template <typename T>
  void operator()(const T* z, T* y, int entity) const {
    T mid[Inner::kOutputs];
    inner(z, mid, entity);
    outer(static_cast<const T*>(mid), y, entity);
  }
  /// zbar = J_iᵀ J_oᵀ w by the two parts' pullback twins (declared only when both have one), the inner value
  /// computed again on doubles.
  template <typename I = Inner, typename O = Outer,
            typename = std::enable_if_t<HasPullbackTwin<I>::value && HasPullbackTwin<O>::value>>
  void pullback(const double* z, const double* y, int entity, const double* w, double* zbar) const {
    double mid[Inner::kOutputs], midBar[Inner::kOutputs];
    inner(z, mid, entity);
    outer.pullback(mid, y, entity, w, midBar);
    inner.pullback(z, mid, entity, midBar, zbar);
  }
  /// The chain rule over the two stages' local derivatives, up to `order`, each on `path`.
  void chained(const double* z, int entity, int order, DerivativePath path, StageDerivativesOf<ComposedStage>& d) const {
    constexpr int P = Inner::kOutputs, M = Outer::kOutputs;
    StageDerivativesOf<Inner> i;
    StageDerivativesOf<Outer> o;
    evaluateStage(inner, z, entity, HasConstantHessian<Inner>::value ? std::min(order, 1) : order, path, i);
    evaluateStage(outer, i.value.data(), entity, order, path, o);
    d.value = o.value;
    if (order < 1) return;
    d.jacobian.noalias() = o.jacobian * i.jacobian;
    if (order < 2) return;
    for (int k = 0; k < M; ++k) d.hessians[k].noalias() = i.jacobian.transpose() * (o.hessians[k] * i.jacobian);
    if constexpr (HasConstantHessian<Inner>::value) {
      // The inner stage's few constant Hessian entries (a cross product has 4 per output), not its dense blocks.
      const auto& c = constantStageHessians<Inner>();
      for (int e = 0; e < c.numEntries; ++e) {
        const auto& t = c.entries[static_cast<std::size_t>(e)];
        for (int k = 0; k < M; ++k) d.hessians[k](t.i, t.j) += o.jacobian(k, t.k) * t.h;
      }
    } else {
      for (int k = 0; k < M; ++k)
        for (int m = 0; m < P; ++m)
          if (o.jacobian(k, m) != 0.0) d.hessians[k].noalias() += o.jacobian(k, m) * i.hessians[m];
    }
  }
  /// C = Σ_k w_k ∇²y_k at z, each on `path`, contracted before it is chained (one product through the inner
  /// Jacobian instead of one per output): C = J_iᵀ (Σ_k w_k ∇²o_k) J_i + Σ_m (J_oᵀ w)_m ∇²i_m.
  void contractedHessian(const double* z, int entity, DerivativePath path, const double* w,
                         Eigen::Matrix<double, kInputs, kInputs>& C) const {
    constexpr int P = Inner::kOutputs, M = Outer::kOutputs;
    StageDerivativesOf<Inner> i;
    StageDerivativesOf<Outer> o;
    evaluateStage(inner, z, entity, HasConstantHessian<Inner>::value ? 1 : 2, path, i);
    Eigen::Matrix<double, P, P> X;
    weightedStageHessian(outer, i.value.data(), entity, path, w, X, &o);
    C.noalias() = i.jacobian.transpose() * (X * i.jacobian);
    const Eigen::Matrix<double, P, 1> v = o.jacobian.transpose() * Eigen::Map<const Eigen::Matrix<double, M, 1>>(w);
    if constexpr (HasConstantHessian<Inner>::value) {
      const auto& c = constantStageHessians<Inner>();
      for (int e = 0; e < c.numEntries; ++e) {
        const auto& t = c.entries[static_cast<std::size_t>(e)];
        C(t.i, t.j) += v[t.k] * t.h;
      }
    } else {
      for (int m = 0; m < P; ++m)
        if (v[m] != 0.0) C.noalias() += v[m] * i.hessians[static_cast<std::size_t>(m)];
    }
  }
};

/// A stage's analytic twin up to `order`. A stage declaring kConstantHessian gives its value and Jacobian only:
/// its Hessians are the declared constant ones (constantStageHessians()), filled here.
template <typename S>
void twinDerivatives(const S& s, const double* z, int entity, int order, StageDerivativesOf<S>& d) {
  if constexpr (HasConstantHessian<S>::value) {
    s.derivatives(z, entity, std::min(order, 1), d);
    if (order >= 2) d.hessians = constantStageHessians<S>().hessians;
  } else {
    s.derivatives(z, entity, order, d);
  }
}

/// The stage's derivatives up to `order` on `path`: the analytic twin when there is one and path is
/// Analytic, the Jets otherwise (a composed stage: its parts' derivatives, chained).
template <typename S>
void evaluateStage(const S& s, const double* z, int entity, int order, DerivativePath path, StageDerivativesOf<S>& d) {
  if (order <= 0) {
    // A value alone is the stage itself on doubles, on every path (a twin's or a composition's value is this
    // call): nothing to differentiate, and nothing between it and the caller's loop.
    s(z, d.value.data(), entity);
    return;
  }
  if constexpr (IsAffineStage<S>::value) {
    if (order >= 2) {
      evaluateStage(s, z, entity, 1, path, d);
      for (auto& h : d.hessians) h.setZero();
      return;
    }
  }
  if constexpr (IsComposedStage<S>::value) {
    if (order >= 1) {
      s.chained(z, entity, order, path, d);
      return;
    }
  }
  if constexpr (HasStageTwin<S>::value) {
    if (path == DerivativePath::Analytic) {
      twinDerivatives(s, z, entity, order, d);
      return;
    }
  }
  if constexpr (HasConstantHessian<S>::value) {
    if (order >= 1) {
      constantHessianStageJacobian(s, z, entity, d);
      if (order >= 2) d.hessians = constantStageHessians<S>().hessians;
      return;
    }
  }
  if constexpr (HasQuadraticHessian<S>::value) {
    if (order >= 2 && s.quadraticHessian(entity, d.hessians[0])) {
      stageDerivativesFromJetsInlined(s, z, entity, 1, d);
      return;
    }
  }
  if constexpr (HasConstantHessian<S>::value || IsComposedStage<S>::value) {
    // Reached by no order of these stages (each returns above); the plain function, as the flattened one would
    // compile several times slower for them.
    stageDerivativesFromJets(s, z, entity, order, d);
  } else {
    stageDerivativesFromJetsInlined(s, z, entity, order, d);
  }
}

template <typename S>
void weightedStageHessian(const S& s, const double* z, int entity, DerivativePath path, const double* w,
                          Eigen::Matrix<double, S::kInputs, S::kInputs>& C, StageDerivativesOf<S>* d) {
  if constexpr (IsComposedStage<S>::value) {
    if (d != nullptr) evaluateStage(s, z, entity, 1, path, *d);
    s.contractedHessian(z, entity, path, w, C);
    return;
  } else {
    if constexpr (HasWeightedHessianTwin<S>::value) {
      if (path == DerivativePath::Analytic) {
        if (d != nullptr) evaluateStage(s, z, entity, 1, path, *d);
        s.weightedHessian(z, entity, w, C);
        return;
      }
    }
    StageDerivativesOf<S> own;
    StageDerivativesOf<S>& h = d != nullptr ? *d : own;
    evaluateStage(s, z, entity, 2, path, h);
    C = w[0] * h.hessians[0];
    for (int k = 1; k < S::kOutputs; ++k)
      if (w[k] != 0.0) C.noalias() += w[k] * h.hessians[static_cast<std::size_t>(k)];
  }
}

/// Largest absolute Hessian entry of a stage declaring kAffine, from its Jets at z (0 for any other stage): a
/// declaration that does not hold shows here.
template <typename S>
double affineDiscrepancy(const S& s, const double* z, int entity) {
  if constexpr (!IsAffineStage<S>::value) {
    return 0.0;
  } else {
    StageDerivativesOf<S> jets;
    stageDerivativesFromJets(s, z, entity, 2, jets);
    double worst = 0.0;
    for (int k = 0; k < S::kOutputs; ++k) worst = std::max(worst, jets.hessians[k].cwiseAbs().maxCoeff());
    return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
  }
}

/// Largest relative difference between the Hessian a per-entity quadratic stage keeps (quadraticHessian) and its
/// Jets' at z (0 for any other stage, or when it keeps none): a stale or wrong kept Hessian shows here.
template <typename S>
double quadraticHessianDiscrepancy(const S& s, const double* z, int entity) {
  if constexpr (!HasQuadraticHessian<S>::value) {
    return 0.0;
  } else {
    Eigen::Matrix<double, S::kInputs, S::kInputs> kept;
    if (!s.quadraticHessian(entity, kept)) return 0.0;
    StageDerivativesOf<S> jets;
    stageDerivativesFromJets(s, z, entity, 2, jets);
    const double worst = relativeDifference(kept, jets.hessians[0]);
    return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
  }
}

/// The checks' output weights w_k = 1, −2, 3, … (into w).
template <int M>
void checkWeights(double (&w)[M]) {
  for (int k = 0; k < M; ++k) w[k] = (k % 2 == 0 ? 1.0 : -1.0) * (k + 1);
}

/// The checks' output weights (checkWeights, into w) and the Jets' Σ_k w_k ∇²y_k with them.
template <int N, int M>
Eigen::Matrix<double, N, N> checkWeightedHessian(const StageDerivatives<N, M>& jets, double (&w)[M]) {
  checkWeights(w);
  Eigen::Matrix<double, N, N> sum = Eigen::Matrix<double, N, N>::Zero();
  for (int k = 0; k < M; ++k) sum += w[k] * jets.hessians[static_cast<std::size_t>(k)];
  return sum;
}

/// Largest relative difference between a pullback twin's Jᵀw and the Jets' at z, with the checks' weights w
/// (checkWeights: 1, −2, 3, …); 0 for a stage without one. `jets`: the Jets' derivatives at z.
template <typename S>
double pullbackDiscrepancy(const S& s, const double* z, int entity, const StageDerivativesOf<S>& jets) {
  if constexpr (!HasPullbackTwin<S>::value) {
    return 0.0;
  } else {
    double w[S::kOutputs];
    checkWeights(w);
    Eigen::Matrix<double, S::kInputs, 1> pulled;
    s.pullback(z, jets.value.data(), entity, w, pulled.data());
    const Eigen::Matrix<double, S::kInputs, 1> reference =
        jets.jacobian.transpose() * Eigen::Map<const Eigen::Matrix<double, S::kOutputs, 1>>(w);
    return relativeDifference(pulled, reference);
  }
}

/// Largest relative difference between a composed stage's chained derivatives on `path` and its own Jets at z
/// (value, Jacobian, Hessians, a contracted Hessian and, when declared, its pullback; 0 for any other stage).
template <typename S>
double composedStageDiscrepancy(const S& s, const double* z, int entity, DerivativePath path) {
  if constexpr (!IsComposedStage<S>::value) {
    return 0.0;
  } else {
    StageDerivativesOf<S> jets, chained;
    stageDerivativesFromJets(s, z, entity, 2, jets);
    s.chained(z, entity, 2, path, chained);
    double worst = std::max(relativeDifference(chained.value, jets.value), relativeDifference(chained.jacobian, jets.jacobian));
    for (int k = 0; k < S::kOutputs; ++k) worst = std::max(worst, relativeDifference(chained.hessians[k], jets.hessians[k]));
    // The contracted Hessian, with the check's weights, against the same sum of the Jets'.
    double w[S::kOutputs];
    Eigen::Matrix<double, S::kInputs, S::kInputs> contracted;
    const auto sum = checkWeightedHessian(jets, w);
    s.contractedHessian(z, entity, path, w, contracted);
    worst = std::max({worst, relativeDifference(contracted, sum), pullbackDiscrepancy(s, z, entity, jets)});
    return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
  }
}

/// Largest relative difference between the twin's and the Jets' value, Jacobian and Hessians at z (each
/// relative to the largest Jet entry of its kind, floor 1; the twin's value and Jacobian at order 2 and at order
/// 1), a weighted-Hessian twin's against the Jets' Σ_k w_k ∇²y_k (checkWeightedHessian), and a pullback twin's
/// against their Jᵀw (pullbackDiscrepancy). 0 for a stage without a twin.
template <typename S>
double stageTwinDiscrepancy(const S& s, const double* z, int entity) {
  if constexpr (!HasStageTwin<S>::value) {
    return 0.0;
  } else {
    StageDerivativesOf<S> jets, twin;
    stageDerivativesFromJets(s, z, entity, 2, jets);
    twinDerivatives(s, z, entity, 2, twin);
    double worst = std::max(relativeDifference(twin.value, jets.value), relativeDifference(twin.jacobian, jets.jacobian));
    for (int k = 0; k < S::kOutputs; ++k) worst = std::max(worst, relativeDifference(twin.hessians[k], jets.hessians[k]));
    // A twin may take a shorter way when no Hessian is asked: its first-order value and Jacobian are checked too.
    StageDerivativesOf<S> first;
    twinDerivatives(s, z, entity, 1, first);
    worst = std::max({worst, relativeDifference(first.value, jets.value), relativeDifference(first.jacobian, jets.jacobian)});
    if constexpr (HasWeightedHessianTwin<S>::value) {
      double w[S::kOutputs];
      Eigen::Matrix<double, S::kInputs, S::kInputs> weighted;
      const auto sum = checkWeightedHessian(jets, w);
      s.weightedHessian(z, entity, w, weighted);
      worst = std::max(worst, relativeDifference(weighted, sum));
    }
    worst = std::max(worst, pullbackDiscrepancy(s, z, entity, jets));
    return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
  }
}

}  // namespace jetshell
