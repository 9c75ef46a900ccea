// Jets that behave like numbers: plain constants and Eigen reductions for every scalar type the framework uses.
//
// Inputs: an energy function written once for a scalar type T, which the framework instantiates with
//   double                     values
//   ceres::Jet<double, N>      first derivatives (N seeded inputs)
//   SecondOrderJet<N, M>       second derivatives: ceres::Jet<InnerJet<M>, N>, N outer and M inner duals
//                              (N = M for Hessians; M = P parameters for ∂²E/∂x∂p)
// Outputs: inside such a function these compile and are exact for each T:
//   - arithmetic with plain numbers: 2.0 * x, x / 3, x + 1.0, 1 - x, x *= 0.5, and comparisons (x < 0.5);
//   - Ceres' math functions, also with one plain number: pow(2.0, x), atan2(x, 1.0), hypot(x, 1.0), fmax(x, 0.0);
//   - Eigen fixed-size algebra on Eigen::Matrix<T, R, C>: a.dot(b), a.norm(), a.squaredNorm(), a.cross(b),
//     v.sum(), (a - b).normalized(), 2.0 * v, v / 3.0, matrix products, trace(), determinant() of 2×2 and 3×3.
// tests/core/jet_arithmetic_test.cpp instantiates each of them for each T and checks values, gradients and
// Hessians against hand derivatives.
//
// The two traps of Ceres 2.1's Jets, and what this header does about each:
//   1. `Jet(const T&)` is explicit, so a nested Jet cannot be built from a number: Jet<Jet<double,M>,N>(0)
//      does not compile, and Eigen's reductions (sum, dot, norm, squaredNorm, normalized, products) all
//      construct `Scalar(0)`. No overload can make that direct-initialisation compile for Ceres' nested type, so
//      the framework's second-order scalar uses a different INNER type: InnerJet<M> is a ceres::Jet<double, M>
//      that also converts implicitly from numbers (and from its base). Jet<InnerJet<M>, N>(0) then compiles, and
//      the outer type stays a plain ceres::Jet, so every Ceres function and operator applies unchanged and
//      returns the same type the user holds (no base/derived mix at the user's level).
//   2. Ceres' mixed operators are `op(const Jet<T,N>&, T)`: T is deduced from both sides, so `x * 2.0` fails
//      for nested Jets (T would be the inner Jet and double at once) and `x / 3` fails even for Jet<double,N>
//      (T = double against int). The operators below take any arithmetic type and scale each level by a
//      double, which is also cheaper than promoting the constant to a Jet. They live in namespace ceres, where
//      argument-dependent lookup finds them for every Jet; they never compete with Ceres' own operators (they
//      are disabled when the constant's type is the Jet's own scalar type).
//   Eigen: NumTraits for InnerJet, and ScalarBinaryOpTraits so that double (and int) scalars multiply and
//   divide matrices of nested Jets.
//
// Decided by experiment (session 5): (a) operators plus Eigen traits on Ceres' own nested type leave every
// reduction uncompilable (Scalar(0)); (b) an implicitly constructible type derived from the OUTER nested Jet
// makes Scalar(0) compile, but every Ceres operator and function returns the base type, so comparisons
// (Ceres' IsJet is false for a derived type), compound assignment with doubles and Eigen's normalized() still
// failed to compile, and user code would hold two types; the inner-derived type needs none of that. Cost:
// identical instruction counts to Ceres' nested Jet on a 12-input hinge energy (callgrind, same code both
// ways); BENCHMARKS.md "Energies as plain math" has the element benchmarks before and after.
#pragma once

#include <Eigen/Core>
#include <ceres/jet.h>

#include <cmath>
#include <limits>
#include <type_traits>

namespace jetshell {

/// A ceres::Jet<double, M> that converts implicitly from numbers and from ceres::Jet<double, M>: the inner Jet
/// of the framework's second-order scalar.
template <int M>
struct InnerJet : ceres::Jet<double, M> {
  using Base = ceres::Jet<double, M>;
  using Base::Base;
  InnerJet() = default;
  InnerJet(const Base& j) : Base(j) {}  // NOLINT: implicit on purpose (results of Ceres' operators)
  template <typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>
  InnerJet(S s) : Base(static_cast<double>(s)) {}  // NOLINT: implicit on purpose (Scalar(0), T(2.0))
};

/// The framework's second-order scalar: N outer duals (seeded on the inputs), M inner duals.
template <int N, int M = N>
using SecondOrderJet = ceres::Jet<InnerJet<M>, N>;

/// Input i of N with value x, seeded for second derivatives: x + ε_i (inner) + δ_i (outer). M ≥ N inner duals
/// (the ones past N stay zero: see kJetWidth).
template <int N, int M = N>
inline SecondOrderJet<N, M> secondOrderVariable(double x, int i) {
  static_assert(M >= N, "every input needs an inner dual");
  SecondOrderJet<N, M> z(InnerJet<M>(x, i));
  z.v[i] = InnerJet<M>(1.0);
  return z;
}

/// The dual width of the Jets that differentiate a small function of N inputs (a stage): N, except 3 → 4, one
/// vector register of doubles, the fourth dual unseeded and always zero. Eigen vectorises a Jet's fixed-size
/// dual part only when its size is a whole number of packets, so a Jet of 3 runs scalar and a Jet of 4 as one
/// vector operation: the shell's stages of 3 inputs take 1.2–2.3× less time on first-order Jets and 1.2–1.8× less
/// on nested ones (inner width 4, outer 3), with the same derivatives to 3e-15 relative (`jetshell bench elements
/// --term stage-jets`); 6 → 8 was slower (BENCHMARKS.md, session 90). Used by the stage evaluators
/// (core/stage.h, core/stage_derivatives.h) and by whole-element Jets (energies/element_energy_term.h: a contact
/// element of one vertex, or of two in difference coordinates, has 3).
template <int N>
inline constexpr int kJetWidth = N == 3 ? 4 : N;

/// First-order Jet for a function of N inputs (input i seeded as dual i of kJetWidth<N>).
template <int N>
using FirstOrderJetOf = ceres::Jet<double, kJetWidth<N>>;

/// Second-order Jet for a function of N inputs: N outer duals, kJetWidth<N> inner ones.
template <int N>
using SecondOrderJetOf = SecondOrderJet<N, kJetWidth<N>>;

// Comparisons of an InnerJet (Ceres' comparisons of the outer Jet reduce to these): by value, like Ceres'.
#define JETSHELL_INNER_JET_COMPARISON(op)                                                             \
  template <int M>                                                                                    \
  inline bool operator op(const InnerJet<M>& f, const InnerJet<M>& g) {                               \
    return f.a op g.a;                                                                                \
  }                                                                                                   \
  template <int M, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>                    \
  inline bool operator op(const InnerJet<M>& f, S s) {                                                \
    return f.a op s;                                                                                  \
  }                                                                                                   \
  template <int M, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>                    \
  inline bool operator op(S s, const InnerJet<M>& f) {                                                \
    return s op f.a;                                                                                  \
  }
JETSHELL_INNER_JET_COMPARISON(<)
JETSHELL_INNER_JET_COMPARISON(<=)
JETSHELL_INNER_JET_COMPARISON(>)
JETSHELL_INNER_JET_COMPARISON(>=)
JETSHELL_INNER_JET_COMPARISON(==)
JETSHELL_INNER_JET_COMPARISON(!=)
#undef JETSHELL_INNER_JET_COMPARISON

// Ceres' classification functions, which its fmax, fmin and fdim call on the inner Jets.
#define JETSHELL_INNER_JET_CLASSIFICATION(name)                                                       \
  template <int M>                                                                                    \
  inline bool name(const InnerJet<M>& f, const InnerJet<M>& g) {                                      \
    return std::name(f.a, g.a);                                                                       \
  }                                                                                                   \
  template <int M, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>                    \
  inline bool name(const InnerJet<M>& f, S s) {                                                       \
    return std::name(f.a, static_cast<double>(s));                                                    \
  }                                                                                                   \
  template <int M, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>                    \
  inline bool name(S s, const InnerJet<M>& f) {                                                       \
    return std::name(static_cast<double>(s), f.a);                                                    \
  }
JETSHELL_INNER_JET_CLASSIFICATION(isless)
JETSHELL_INNER_JET_CLASSIFICATION(isgreater)
JETSHELL_INNER_JET_CLASSIFICATION(islessequal)
JETSHELL_INNER_JET_CLASSIFICATION(isgreaterequal)
JETSHELL_INNER_JET_CLASSIFICATION(islessgreater)
JETSHELL_INNER_JET_CLASSIFICATION(isunordered)
#undef JETSHELL_INNER_JET_CLASSIFICATION

/// True for an arithmetic S that is not the Jet's own scalar type T (those Ceres handles itself).
template <typename T, typename S>
inline constexpr bool kForeignConstant = std::is_arithmetic_v<S> && !std::is_same_v<T, S>;

}  // namespace jetshell

namespace ceres {

// Jet (any nesting) with a plain number of any arithmetic type: each level is scaled or shifted by a double.
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator+(const Jet<T, N>& f, S s) {
  return Jet<T, N>(f.a + static_cast<double>(s), f.v);
}
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator+(S s, const Jet<T, N>& f) {
  return Jet<T, N>(static_cast<double>(s) + f.a, f.v);
}
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator-(const Jet<T, N>& f, S s) {
  return Jet<T, N>(f.a - static_cast<double>(s), f.v);
}
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator-(S s, const Jet<T, N>& f) {
  return Jet<T, N>(static_cast<double>(s) - f.a, -f.v);
}
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator*(const Jet<T, N>& f, S s) {
  const double d = static_cast<double>(s);
  return Jet<T, N>(f.a * d, f.v * d);
}
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator*(S s, const Jet<T, N>& f) {
  return f * static_cast<double>(s);
}
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator/(const Jet<T, N>& f, S s) {
  return f * (1.0 / static_cast<double>(s));
}
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> operator/(S s, const Jet<T, N>& g) {
  return T(static_cast<double>(s)) / g;  // Ceres' scalar / Jet (the constant has no derivative part)
}

// Two-argument functions with one plain number (Ceres 2.1 has none for atan2 and hypot, and its pow(number, Jet)
// takes only the Jet's own scalar type and does not compile for nested Jets of two sizes).
/// b^g = exp(g ln b) for b > 0; 0 for b = 0 (meant for g > 0); NaN for b < 0, where g has no derivative.
template <typename T, int N, typename S, std::enable_if_t<jetshell::kForeignConstant<T, S>, int> = 0>
inline Jet<T, N> pow(S f, const Jet<T, N>& g) {
  const double b = static_cast<double>(f);
  if (b > 0.0) return exp(g * std::log(b));
  return Jet<T, N>(T(b == 0.0 ? 0.0 : std::numeric_limits<double>::quiet_NaN()));
}
template <typename T, int N, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>
inline Jet<T, N> atan2(const Jet<T, N>& g, S f) {
  return atan2(g, Jet<T, N>(T(static_cast<double>(f))));
}
template <typename T, int N, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>
inline Jet<T, N> atan2(S g, const Jet<T, N>& f) {
  return atan2(Jet<T, N>(T(static_cast<double>(g))), f);
}
template <typename T, int N, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>
inline Jet<T, N> hypot(const Jet<T, N>& x, S y) {
  return hypot(x, Jet<T, N>(T(static_cast<double>(y))));
}
template <typename T, int N, typename S, std::enable_if_t<std::is_arithmetic_v<S>, int> = 0>
inline Jet<T, N> hypot(S x, const Jet<T, N>& y) {
  return hypot(Jet<T, N>(T(static_cast<double>(x))), y);
}

namespace internal {
/// An InnerJet's underlying floating-point type is double, as for ceres::Jet<double, M>: this enables Ceres'
/// fmax, fmin and fdim between a second-order Jet and a plain number.
template <int M>
struct UnderlyingScalar<jetshell::InnerJet<M>> {
  using type = double;
};
}  // namespace internal

}  // namespace ceres

namespace Eigen {

template <int M>
struct NumTraits<jetshell::InnerJet<M>> : NumTraits<ceres::Jet<double, M>> {
  using Real = jetshell::InnerJet<M>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  static Real dummy_precision() { return Real(1e-12); }
  static Real epsilon() { return Real(std::numeric_limits<double>::epsilon()); }
  static Real highest() { return Real((std::numeric_limits<double>::max)()); }
  static Real lowest() { return Real(-(std::numeric_limits<double>::max)()); }
};

// Matrices of InnerJets or of second-order Jets times (or divided by) a double or an int.
#define JETSHELL_JET_SCALAR_TRAITS(Number)                                          \
  template <int M, typename Op>                                                     \
  struct ScalarBinaryOpTraits<jetshell::InnerJet<M>, Number, Op> {                  \
    using ReturnType = jetshell::InnerJet<M>;                                       \
  };                                                                                \
  template <int M, typename Op>                                                     \
  struct ScalarBinaryOpTraits<Number, jetshell::InnerJet<M>, Op> {                  \
    using ReturnType = jetshell::InnerJet<M>;                                       \
  };                                                                                \
  template <int N, int M, typename Op>                                              \
  struct ScalarBinaryOpTraits<jetshell::SecondOrderJet<N, M>, Number, Op> {         \
    using ReturnType = jetshell::SecondOrderJet<N, M>;                              \
  };                                                                                \
  template <int N, int M, typename Op>                                              \
  struct ScalarBinaryOpTraits<Number, jetshell::SecondOrderJet<N, M>, Op> {         \
    using ReturnType = jetshell::SecondOrderJet<N, M>;                              \
  };
JETSHELL_JET_SCALAR_TRAITS(double)
JETSHELL_JET_SCALAR_TRAITS(int)
#undef JETSHELL_JET_SCALAR_TRAITS

template <int N, typename Op>
struct ScalarBinaryOpTraits<ceres::Jet<double, N>, int, Op> {
  using ReturnType = ceres::Jet<double, N>;
};
template <int N, typename Op>
struct ScalarBinaryOpTraits<int, ceres::Jet<double, N>, Op> {
  using ReturnType = ceres::Jet<double, N>;
};

}  // namespace Eigen

namespace std {
/// Limits of an InnerJet are those of its value (as for ceres::Jet).
template <int M>
struct numeric_limits<jetshell::InnerJet<M>> : numeric_limits<double> {
  static jetshell::InnerJet<M> epsilon() noexcept { return jetshell::InnerJet<M>(numeric_limits<double>::epsilon()); }
  static jetshell::InnerJet<M> min() noexcept { return jetshell::InnerJet<M>((numeric_limits<double>::min)()); }
  static jetshell::InnerJet<M> max() noexcept { return jetshell::InnerJet<M>((numeric_limits<double>::max)()); }
  static jetshell::InnerJet<M> lowest() noexcept { return jetshell::InnerJet<M>(numeric_limits<double>::lowest()); }
  static jetshell::InnerJet<M> infinity() noexcept { return jetshell::InnerJet<M>(numeric_limits<double>::infinity()); }
  static jetshell::InnerJet<M> quiet_NaN() noexcept { return jetshell::InnerJet<M>(numeric_limits<double>::quiet_NaN()); }
};
}  // namespace std
