// A term defined only by a templated element energy: the framework derives gradient and Hessian with Ceres
// Jets (first order: Jet<double,3K>; second order: Jet<Jet<double,3K>,3K>), assembles in parallel and
// projects. This is how users add energies without hand derivatives (see energies/examples/).
//
// The functor:
//   struct MyEnergy {
//     static constexpr int kVertices = K;           // stencil width
//     template <typename T> T operator()(const T* x, int element) const;  // x: 3K positions of the element
//   };
// Write the energy as plain math: double constants (2.0 * x, x / 3) and Eigen fixed-size algebra (vec3(x + 3),
// a.dot(b), a.cross(b).norm()) work for T = double, Jet<double,3K> and SecondOrderJet<3K> (core/jet_arithmetic.h).
//
// Parameters as differentiable inputs (optional, detected at compile time): a functor that also declares
//     static constexpr int kParameters = P;
//     static constexpr std::array<const char*, P> kParameterNames{{"stiffness", ...}};
//     std::array<double, P> parameters;                                   // current values
//     template <typename T> T operator()(const T* x, const T* p, int element) const;   // p: the P parameters
// gets parameterNames()/parameterValues()/setParameterValues() and evaluateParameterDerivatives() (∂E/∂p and
// ∂²E/∂x∂p from duals seeded on p, core/parameter_derivatives.h). Functors without kParameters keep the
// two-argument form.
//
// The evaluation's options (optional, detected at compile time): a functor with a member
//     EvalOptions options;
// gets the options of each evaluate() call copied there before its elements run, for terms that offer a model
// Hessian beside the exact one (the friction terms read options.frictionHessian). The exact Hessian must stay
// the default options' (EvalOptions{}), which is what the conformance suite and check-derivatives evaluate.
//
// Translation invariance (optional, detected at compile time): a functor of K ≥ 2 vertices whose energy depends
// only on the differences x_k − x_0 may declare
//     static constexpr bool kTranslationInvariant = true;
// Its Jets then carry the 3(K−1) coordinates of vertices 1 … K−1 with vertex 0 held as a constant, and vertex 0's
// gradient and Hessian blocks are completed from the others' sums (the same completion as the stage graphs'
// difference coordinates): for a point pair, second-order Jets over 3 dofs instead of 6. A false declaration gives
// a wrong vertex-0 derivative, which the conformance suite's finite differences in full coordinates catch.
#pragma once

#include "core/assembly.h"
#include "core/element_loop.h"
#include "core/fixed_stencil_term.h"
#include "core/flatten.h"
#include "core/parameter_derivatives.h"
#include "core/psd_projection.h"
#include "core/scalar.h"
#include "core/term.h"

#include <ceres/jet.h>

#include <string>
#include <type_traits>
#include <utility>

namespace jetshell {

/// Elements of up to this many degrees of freedom evaluate their Jets with every call inlined.
inline constexpr int kFlattenedElementDofs = 6;

/// Functor::kParameters, or 0 for a functor without parameters.
template <typename Functor, typename = void>
struct FunctorParameterCount : std::integral_constant<int, 0> {};
template <typename Functor>
struct FunctorParameterCount<Functor, std::void_t<decltype(Functor::kParameters)>>
    : std::integral_constant<int, Functor::kParameters> {};

/// Whether Functor has a member `EvalOptions options` (set before each evaluation).
template <typename Functor, typename = void>
struct FunctorTakesOptions : std::false_type {};
template <typename Functor>
struct FunctorTakesOptions<Functor, std::void_t<decltype(std::declval<Functor&>().options)>>
    : std::is_same<std::decay_t<decltype(std::declval<Functor&>().options)>, EvalOptions> {};

/// Whether Functor declares `static constexpr bool kTranslationInvariant = true` (see the file comment).
template <typename Functor, typename = void>
struct FunctorTranslationInvariant : std::false_type {};
template <typename Functor>
struct FunctorTranslationInvariant<Functor, std::void_t<decltype(Functor::kTranslationInvariant)>>
    : std::bool_constant<Functor::kTranslationInvariant> {};

template <typename Functor>
class ElementEnergyTerm : public FixedStencilTerm {
 public:
  static constexpr int K = Functor::kVertices;
  static constexpr int M = 3 * K;
  static constexpr int P = FunctorParameterCount<Functor>::value;
  /// Derivatives in the difference coordinates of vertices 1 … K−1 (see the file comment).
  static constexpr bool kDifferences = K >= 2 && FunctorTranslationInvariant<Functor>::value;

  ElementEnergyTerm(std::string name, StencilTable stencils, int numVertices, Functor functor,
                    bool zeroAtRest = true, bool rigidInvariant = true)
      : FixedStencilTerm(std::move(name), std::move(stencils), numVertices, zeroAtRest, rigidInvariant),
        functor_(std::move(functor)) {}

  const Functor& functor() const { return functor_; }
  Functor& functor() { return functor_; }

  std::vector<std::string> parameterNames() const override {
    if constexpr (P > 0) {
      return std::vector<std::string>(Functor::kParameterNames.begin(), Functor::kParameterNames.end());
    } else {
      return {};
    }
  }
  std::vector<double> parameterValues() const override {
    if constexpr (P > 0) {
      return std::vector<double>(functor_.parameters.begin(), functor_.parameters.end());
    } else {
      return {};
    }
  }
  void setParameterValues(const std::vector<double>& values) override {
    validateParameterValues(name_, parameterNames(), values);
    if constexpr (P > 0)
      for (int j = 0; j < P; ++j) functor_.parameters[j] = values[static_cast<std::size_t>(j)];
  }
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override {
    resetParameterDerivatives(out, x.size(), P);
    if constexpr (P > 0)
      addParameterDerivatives<K, P>(table_, x, functor_.parameters.data(), functor_, out);
  }

  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override {
    if constexpr (FunctorTakesOptions<Functor>::value) functor_.options = options;
    // Nested-Jet Hessians over 15 or more dofs are costly elements (core/element_loop.h).
    const int parallelMin =
        request.hessian != nullptr && M >= 15 ? kParallelMinCostlyElements : kParallelMinElements;
    return runElementLoop<K>(table_, schedule_, x, request, options.projection, elementEnergy_,
                             [&](int e, const int* ids, bool wantG, bool wantH, Eigen::Matrix<double, M, 1>& g,
                                 Eigen::Matrix<double, M, M>& H) { return element(x, e, ids, wantG, wantH, g, H); },
                             parallelMin);
  }

 private:

  /// The functor's energy with the current parameters as constants of type T (when it has any).
  template <typename T>
  T energy(const T* x, int e) const {
    if constexpr (P > 0) {
      T p[P];
      for (int j = 0; j < P; ++j) p[j] = constant<T>(functor_.parameters[j]);
      return functor_(x, static_cast<const T*>(p), e);
    } else {
      return functor_(x, e);
    }
  }

  double element(const Eigen::VectorXd& x, int e, const int* ids, bool wantG, bool wantH,
                 Eigen::Matrix<double, M, 1>& g, Eigen::Matrix<double, M, M>& H) const {
    double xe[M];
    for (int k = 0; k < K; ++k)
      for (int c = 0; c < 3; ++c) xe[3 * k + c] = ids[k] >= 0 ? x[3 * ids[k] + c] : 0.0;
    // Small elements (point-pair and point-plane contact: 6 and 3 dofs) get the Jet arithmetic inlined
    // (core/flatten.h); for 9 dofs and more the flattened body cost minutes of compile time across the contact
    // terms (BENCHMARKS.md, "Jet arithmetic inlined").
    if constexpr (M <= kFlattenedElementDofs) {
      return derivativesInlined(xe, e, wantG, wantH, g, H);
    } else {
      return derivatives(xe, e, wantG, wantH, g, H);
    }
  }

  JETSHELL_FLATTEN double derivativesInlined(const double* xe, int e, bool wantG, bool wantH,
                                             Eigen::Matrix<double, M, 1>& g, Eigen::Matrix<double, M, M>& H) const {
    return derivatives(xe, e, wantG, wantH, g, H);
  }

  /// Value, and gradient and Hessian when asked, of element e at its positions xe. The Jets carry the
  /// coordinates from S on: all of them, or (difference coordinates) those of vertices 1 … K−1, vertex 0 held as a
  /// constant and its gradient and Hessian blocks completed from the others' afterwards.
  double derivatives(const double* xe, int e, bool wantG, bool wantH, Eigen::Matrix<double, M, 1>& g,
                     Eigen::Matrix<double, M, M>& H) const {
    constexpr int S = kDifferences ? 3 : 0;
    constexpr int R = M - S;
    double value;
    if (wantH) {
      using D2 = SecondOrderJetOf<R>;  // R outer duals, kJetWidth<R> inner (core/jet_arithmetic.h)
      D2 xj[M];
      for (int i = 0; i < S; ++i) xj[i] = constant<D2>(xe[i]);
      for (int i = S; i < M; ++i) xj[i] = secondOrderVariable<R, kJetWidth<R>>(xe[i], i - S);
      const D2 E = energy(static_cast<const D2*>(xj), e);
      Eigen::Matrix<double, R, R> C;
      for (int i = 0; i < R; ++i) {
        g[S + i] = E.a.v[i];
        for (int j = 0; j < R; ++j) C(i, j) = E.v[i].v[j];
      }
      H.template bottomRightCorner<R, R>() = 0.5 * (C + C.transpose());
      if constexpr (S > 0) completeTranslationInvariant(H);
      value = E.a.a;
    } else if (wantG) {
      using D1 = FirstOrderJetOf<R>;
      D1 xj[M];
      for (int i = 0; i < S; ++i) xj[i] = constant<D1>(xe[i]);
      for (int i = S; i < M; ++i) xj[i] = D1(xe[i], i - S);
      const D1 E = energy(static_cast<const D1*>(xj), e);
      g.template tail<R>() = E.v.template head<R>();
      value = E.a;
    } else {
      return energy(static_cast<const double*>(xe), e);
    }
    if constexpr (S > 0) {
      g.template head<3>().setZero();
      for (int k = 1; k < K; ++k) g.template head<3>() -= g.template segment<3>(3 * k);
    }
    return value;
  }

  Functor functor_;
};

}  // namespace jetshell
