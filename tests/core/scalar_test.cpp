// Every helper of core/scalar.h, instantiated for each scalar type the energies use: a helper that does not
// compile for nested Jets fails this file's build.
#include "core/scalar.h"

#include <catch2/catch.hpp>

using namespace jetshell;

namespace {

using ScalarJ1 = ceres::Jet<double, 3>;
using ScalarJ2 = ceres::Jet<ScalarJ1, 3>;  // Ceres' own nested Jet: constant<T> and V3 still serve it
using S2 = SecondOrderJet<3>;   // the framework's second-order scalar (core/jet_arithmetic.h)

/// The helpers composed into one function of a 3-vector: f(p) = |p|² + 2·|p × q|·(p·q) − 0.5·|p|, q fixed.
template <typename T>
T composite(const T* p) {
  const V3<T> a = load3(p);
  const V3<T> q{{constant<T>(0.3), constant<T>(-1.2), constant<T>(0.7)}};
  const V3<T> s = constant<T>(2.0) * (a + q) - q - q;  // = 2a
  const V3<T> h = 0.5 * s;                              // = a: a plain number times a vector
  const V3<T> c = cross(a, q);
  return squaredNorm(a) + constant<T>(0.5) * dot(s, q) * norm(c) - 0.5 * norm(h - q + q);
}

double compositeValue(const double* p) { return composite(p); }

}  // namespace

TEMPLATE_TEST_CASE("scalar: helpers compile and agree in value for every scalar type", "", double, ScalarJ1, ScalarJ2, S2) {
  const double p[3] = {0.4, 0.9, -0.5};
  TestType pt[3];
  for (int i = 0; i < 3; ++i) pt[i] = constant<TestType>(p[i]);
  const TestType y = composite(pt);
  CHECK(valueOf(y) == Approx(compositeValue(p)).epsilon(1e-15));
  CHECK(valueOf(constant<TestType>(2.5)) == 2.5);
  const V3<TestType> a{{constant<TestType>(1.0), constant<TestType>(2.0), constant<TestType>(2.0)}};
  CHECK(valueOf(norm(a)) == Approx(3.0));
  CHECK(valueOf(squaredNorm(a)) == Approx(9.0));
  const V3<TestType> e = cross(a, a);
  CHECK(valueOf(e[0]) == 0.0);
  CHECK(valueOf((a - a)[2]) == 0.0);
}

TEST_CASE("scalar: first and second Jet derivatives of the helpers match hand derivatives") {
  const double p[3] = {0.4, 0.9, -0.5};
  // norm: ∂|p|/∂p = p/|p|, ∂²|p|/∂p∂p = (I − n nᵀ)/|p|.
  ScalarJ2 x[3];
  for (int i = 0; i < 3; ++i) {
    x[i] = ScalarJ2(ScalarJ1(p[i], i));
    x[i].v[i] = ScalarJ1(1.0);
  }
  const ScalarJ2 r = norm(load3(x));
  const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  for (int i = 0; i < 3; ++i) {
    CHECK(r.a.v[i] == Approx(p[i] / len).epsilon(1e-14));
    CHECK(r.v[i].a == Approx(p[i] / len).epsilon(1e-14));
    for (int j = 0; j < 3; ++j) {
      const double expected = ((i == j ? 1.0 : 0.0) - p[i] * p[j] / (len * len)) / len;
      CHECK(r.v[i].v[j] == Approx(expected).epsilon(1e-13).margin(1e-15));
    }
  }
  // The composite's Jet gradient against central differences (smooth, so 1e-6 steps give ~1e-9).
  ScalarJ1 y[3];
  for (int i = 0; i < 3; ++i) y[i] = ScalarJ1(p[i], i);
  const ScalarJ1 f = composite(y);
  for (int i = 0; i < 3; ++i) {
    double pp[3] = {p[0], p[1], p[2]}, pm[3] = {p[0], p[1], p[2]};
    pp[i] += 1e-6;
    pm[i] -= 1e-6;
    CHECK(f.v[i] == Approx((compositeValue(pp) - compositeValue(pm)) / 2e-6).epsilon(1e-8));
  }
}
