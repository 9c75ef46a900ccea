#include "core/math_constants.h"
#include "tools/checks/check_configurations.h"
#include "tools/checks/derivative_check.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

namespace {
}

TEST_CASE("check configurations: each kind has the geometry it promises") {
  for (const CheckMesh& m : makeCheckMeshes()) {
    REQUIRE(m.meanEdgeLength > 0.0);
    const Eigen::VectorXd X = flatten(m.mesh.V);
    for (std::uint64_t seed = 0; seed < 8; ++seed) {
      INFO(m.name << " seed " << seed);
      const ConfigurationGeometry rest = measureGeometry(m, X);
      CHECK(rest.maxStretch == Approx(1.0).epsilon(1e-12));

      const CheckConfiguration stretch = makeCheckConfiguration(m, ConfigurationKind::Stretch, seed);
      CHECK(stretch.geometry.maxStretch > 2.6);
      CHECK(stretch.geometry.maxStretch < 3.5);

      ConfigurationOptions o;
      o.foldMinDelta = o.foldMaxDelta = 0.01;
      const CheckConfiguration fold = makeCheckConfiguration(m, ConfigurationKind::Fold, seed, o);
      // The folded pair is at exactly 180° − δ; other edges may bend less (or, on the grid, be dragged along).
      CHECK(fold.geometry.maxFoldAngle >= kPi - 0.01 - 1e-9);
      CHECK(fold.geometry.maxFoldAngle < kPi);

      const CheckConfiguration degenerate = makeCheckConfiguration(m, ConfigurationKind::Degenerate, seed);
      CHECK(degenerate.geometry.minAspectRatio == Approx(1e-3).epsilon(1e-6));

      const CheckConfiguration rotation = makeCheckConfiguration(m, ConfigurationKind::Rotation, seed);
      CHECK(rotation.geometry.maxStretch < 1.5);
      CHECK(rotation.description.find("rotation by") != std::string::npos);
    }
  }
}

TEST_CASE("check configurations: deterministic per seed, different across seeds") {
  const CheckMesh m = makeCheckMeshes()[1];
  for (ConfigurationKind kind : kConfigurationKinds) {
    INFO(toString(kind));
    const Eigen::VectorXd a = makeCheckConfiguration(m, kind, 42).x;
    CHECK(a == makeCheckConfiguration(m, kind, 42).x);
    CHECK(a != makeCheckConfiguration(m, kind, 43).x);
    CHECK(configurationKindFromString(toString(kind)) == kind);
  }
  CHECK_THROWS_WITH(configurationKindFromString("twist"), Catch::Contains("'twist'"));
}

TEST_CASE("check configurations: rigid motions keep the length scale and the geometry") {
  const CheckMesh m = makeCheckMeshes()[0];
  const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 9).x;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::VectorXd y = rigidlyMoved(x, R, Eigen::Vector3d(5, -2, 1));
  CHECK(configurationLengthScale(y) == Approx(configurationLengthScale(x)).epsilon(1e-13));
  const ConfigurationGeometry gx = measureGeometry(m, x), gy = measureGeometry(m, y);
  CHECK(gy.maxFoldAngle == Approx(gx.maxFoldAngle).epsilon(1e-10));
  CHECK(gy.minAspectRatio == Approx(gx.minAspectRatio).epsilon(1e-10));
  CHECK(gy.maxStretch == Approx(gx.maxStretch).epsilon(1e-10));
}
