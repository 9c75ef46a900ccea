#include "core/stage.h"

#include <catch2/catch.hpp>

using namespace jetshell;

namespace {

/// y = (z0 z1², sin z0) with no twin.
struct Plain {
  static constexpr int kInputs = 2, kOutputs = 2;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    using std::sin;
    y[0] = z[0] * z[1] * z[1];
    y[1] = sin(z[0]);
  }
};

/// The same with an analytic twin, optionally wrong by `error` in one Hessian entry.
struct Twinned : Plain {
  double error = 0.0;
  void derivatives(const double* z, int, int order, StageDerivatives<2, 2>& d) const {
    d.value << z[0] * z[1] * z[1], std::sin(z[0]);
    d.jacobian << z[1] * z[1], 2.0 * z[0] * z[1], std::cos(z[0]), 0.0;
    if (order < 2) return;
    d.hessians[0] << 0.0, 2.0 * z[1], 2.0 * z[1], 2.0 * z[0] + error;
    d.hessians[1] << -std::sin(z[0]), 0.0, 0.0, 0.0;
  }
};

}  // namespace

TEST_CASE("stage: Jets give value, Jacobian and Hessians of a stage", "[stages]") {
  const double z[2] = {0.7, -1.3};
  StageDerivatives<2, 2> d;
  stageDerivativesFromJets(Plain(), z, 0, 2, d);
  CHECK(d.value[0] == Approx(0.7 * 1.69));
  CHECK(d.jacobian(0, 1) == Approx(2.0 * 0.7 * -1.3));
  CHECK(d.jacobian(1, 0) == Approx(std::cos(0.7)));
  CHECK(d.hessians[0](1, 1) == Approx(1.4));
  CHECK(d.hessians[0](0, 1) == Approx(-2.6));
  CHECK(d.hessians[1](0, 0) == Approx(-std::sin(0.7)));
}

TEST_CASE("stage: an analytic twin is detected, used on the analytic path only, and checked against the Jets",
          "[stages]") {
  STATIC_REQUIRE_FALSE(HasStageTwin<Plain>::value);
  STATIC_REQUIRE(HasStageTwin<Twinned>::value);
  const double z[2] = {0.7, -1.3};
  Twinned good, bad;
  bad.error = 1e-3;
  CHECK(stageTwinDiscrepancy(good, z, 0) <= 1e-15);
  CHECK(stageTwinDiscrepancy(bad, z, 0) >= 1e-4);
  StageDerivatives<2, 2> jets, twin;
  evaluateStage(bad, z, 0, 2, DerivativePath::AutoDiff, jets);
  evaluateStage(bad, z, 0, 2, DerivativePath::Analytic, twin);
  CHECK(jets.hessians[0](1, 1) == Approx(1.4));
  CHECK(twin.hessians[0](1, 1) == Approx(1.4 + 1e-3));
}

namespace {

/// y = (z0 z1, 3 z0 − z1): a polynomial of degree 2, declared so.
struct Bilinear {
  static constexpr int kInputs = 2, kOutputs = 2;
  static constexpr bool kConstantHessian = true;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    y[0] = z[0] * z[1];
    y[1] = constant<T>(3.0) * z[0] - z[1];
  }
};
/// The same declaration on a stage that does not honour it.
struct FalselyConstant : Plain {
  static constexpr bool kConstantHessian = true;
};
/// Constant Hessians but a linear part that moves with the entity: not a fixed polynomial, so the declaration
/// does not hold either (the Jacobian derived from J(0) would be the entity 0's).
struct EntityLinear {
  static constexpr int kInputs = 2, kOutputs = 1;
  static constexpr bool kConstantHessian = true;
  template <typename T>
  void operator()(const T* z, T* y, int entity) const {
    y[0] = constant<T>(1.0 + entity) * z[0] + z[0] * z[1];
  }
};

}  // namespace

TEST_CASE("stage: a composed stage chains its parts' derivatives and equals its own Jets", "[stages]") {
  using Composed = ComposedStage<Plain, Twinned>;
  STATIC_REQUIRE(IsComposedStage<Composed>::value);
  STATIC_REQUIRE_FALSE(IsComposedStage<Plain>::value);
  const double z[2] = {0.7, -1.3};
  Composed good;
  CHECK(composedStageDiscrepancy(good, z, 0, DerivativePath::AutoDiff) <= 1e-14);
  CHECK(composedStageDiscrepancy(good, z, 0, DerivativePath::Analytic) <= 1e-14);
  // The analytic path reaches the outer stage's twin: a wrong twin shows there, and on that path only.
  Composed bad;
  bad.outer.error = 1e-3;
  CHECK(composedStageDiscrepancy(bad, z, 0, DerivativePath::AutoDiff) <= 1e-14);
  CHECK(composedStageDiscrepancy(bad, z, 0, DerivativePath::Analytic) >= 1e-4);
  StageDerivatives<2, 2> d;
  evaluateStage(good, z, 0, 0, DerivativePath::AutoDiff, d);
  CHECK(d.value[1] == Approx(std::sin(0.7 * 1.69)));
}

TEST_CASE("stage: constant Hessians are computed once and a false declaration shows against the Jets", "[stages]") {
  STATIC_REQUIRE(HasConstantHessian<Bilinear>::value);
  STATIC_REQUIRE_FALSE(HasConstantHessian<Plain>::value);
  const double z[2] = {0.7, -1.3};
  StageDerivatives<2, 2> d;
  evaluateStage(Bilinear(), z, 0, 2, DerivativePath::AutoDiff, d);
  CHECK(d.value[0] == Approx(0.7 * -1.3));
  CHECK(d.jacobian(1, 0) == 3.0);
  CHECK(d.hessians[0](0, 1) == 1.0);
  CHECK(d.hessians[0](0, 0) == 0.0);
  CHECK(d.hessians[1].isZero(0.0));
  CHECK_FALSE(constantStageHessians<Bilinear>().zero);
  CHECK(constantHessianDiscrepancy(Bilinear(), z, 0) == 0.0);
  // Plain's y0 = z0 z1² has a Hessian that moves with z: the declaration is caught away from z = 0.
  CHECK(constantHessianDiscrepancy(FalselyConstant(), z, 0) >= 1.0);
  // At order 1 the stage runs on doubles, J(z) = J(0) + [H_k z]_k: the Jets' Jacobian, here exactly.
  StageDerivatives<2, 2> jets;
  stageDerivativesFromJets(Bilinear(), z, 0, 1, jets);
  evaluateStage(Bilinear(), z, 0, 1, DerivativePath::AutoDiff, d);
  CHECK(d.jacobian == jets.jacobian);
  CHECK(d.value == jets.value);
  CHECK(constantHessianDiscrepancy(EntityLinear(), z, 0) == 0.0);
  CHECK(constantHessianDiscrepancy(EntityLinear(), z, 2) >= 1.0);
}
