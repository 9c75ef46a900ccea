#include "core/stage.h"
#include "core/stage_derivatives.h"

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

/// y = (z0 z1 z2, z2 sin z0): three inputs, carried on Jets of kJetWidth<3> = 4 duals.
struct ThreeInputs {
  static constexpr int kInputs = 3, kOutputs = 2;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    using std::sin;
    y[0] = z[0] * z[1] * z[2];
    y[1] = z[2] * sin(z[0]);
  }
};

/// ThreeInputs' derivatives by hand.
StageDerivatives<3, 2> threeInputsByHand(const double* z) {
  StageDerivatives<3, 2> d;
  const double s = std::sin(z[0]), c = std::cos(z[0]);
  d.value << z[0] * z[1] * z[2], z[2] * s;
  d.jacobian << z[1] * z[2], z[0] * z[2], z[0] * z[1], z[2] * c, 0.0, s;
  d.hessians[0] << 0.0, z[2], z[1], z[2], 0.0, z[0], z[1], z[0], 0.0;
  d.hessians[1] << -z[2] * s, 0.0, c, 0.0, 0.0, 0.0, c, 0.0, 0.0;
  return d;
}

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

TEST_CASE("stage: a stage of 3 inputs on Jets of 4 duals (kJetWidth) gives its exact derivatives, as on 3", "[stages]") {
  STATIC_REQUIRE(kJetWidth<3> == 4);
  STATIC_REQUIRE(kJetWidth<2> == 2);
  STATIC_REQUIRE(kJetWidth<6> == 6);
  const double z[3] = {0.7, -1.3, 2.1};
  const StageDerivatives<3, 2> hand = threeInputsByHand(z);
  for (int order = 1; order <= 2; ++order) {
    StageDerivatives<3, 2> wide, plain;
    stageDerivativesFromJets(ThreeInputs(), z, 0, order, wide);  // kJetWidth<3> = 4 duals
    stageDerivativesFromJets<ThreeInputs, 3>(ThreeInputs(), z, 0, order, plain);
    CHECK(relativeDifference(wide.value, hand.value) <= 1e-15);
    CHECK(relativeDifference(wide.jacobian, hand.jacobian) <= 1e-15);
    CHECK(relativeDifference(plain.jacobian, hand.jacobian) <= 1e-15);
    if (order < 2) continue;
    for (int k = 0; k < 2; ++k) {
      CHECK(relativeDifference(wide.hessians[static_cast<std::size_t>(k)], hand.hessians[static_cast<std::size_t>(k)]) <= 1e-15);
      CHECK(relativeDifference(plain.hessians[static_cast<std::size_t>(k)], hand.hessians[static_cast<std::size_t>(k)]) <= 1e-15);
    }
  }
  // The scalar and vector helpers of core/stage_derivatives.h run on the same width.
  const auto first = [](const auto* x) { return x[0] * x[1] * x[2]; };
  double value = 0.0;
  Eigen::Vector3d gradient;
  Eigen::Matrix3d hessian;
  scalarStageDerivatives<3>(first, z, value, gradient, hessian);
  CHECK(value == Approx(hand.value[0]));
  CHECK(relativeDifference(gradient.transpose(), hand.jacobian.row(0)) <= 1e-15);
  CHECK(relativeDifference(hessian, hand.hessians[0]) <= 1e-15);
  scalarStageGradient<3>(first, z, value, gradient);
  CHECK(relativeDifference(gradient.transpose(), hand.jacobian.row(0)) <= 1e-15);
  const auto vector = [](const auto& x) {
    using std::sin;
    auto y = x;
    y[0] = x[0] * x[1] * x[2];
    y[1] = x[2] * sin(x[0]);
    y[2] = x[1];
    return y;
  };
  Eigen::Vector3d y;
  Eigen::Matrix3d jacobian;
  std::array<Eigen::Matrix3d, 3> hessians;
  vectorStageDerivatives(vector, Eigen::Vector3d(z[0], z[1], z[2]), y, jacobian, hessians);
  CHECK(relativeDifference(jacobian.topRows<2>(), hand.jacobian) <= 1e-15);
  CHECK(relativeDifference(jacobian.row(2), Eigen::RowVector3d(0.0, 1.0, 0.0)) <= 1e-15);
  CHECK(relativeDifference(hessians[1], hand.hessians[1]) <= 1e-15);
  CHECK(hessians[2].cwiseAbs().maxCoeff() == 0.0);
  vectorStageJacobian(vector, Eigen::Vector3d(z[0], z[1], z[2]), y, jacobian);
  CHECK(relativeDifference(jacobian.topRows<2>(), hand.jacobian) <= 1e-15);
}
