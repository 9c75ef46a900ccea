#include "validation/snap_through.h"

#include "tests/solvers/test_problems.h"

#include <catch2/catch.hpp>

using namespace jetshell;
using namespace jetshell::validation;

TEST_CASE("snap-through: arc length passes both limit points of the hinged roof and agrees with displacement control",
          "[validation][path]") {
  testing::SingleThread single;
  RoofOptions o;
  o.resolution = {6, 6};
  const RoofResult r = runHingedRoof(o);
  INFO(formatRoof(r));
  REQUIRE(r.arc.completed);
  REQUIRE(r.displacement.completed);
  CHECK(r.bothLimitsPassed);
  REQUIRE(r.arc.limits.size() == 2);
  REQUIRE(r.displacement.limits.size() == 2);
  // A snap-through: the load turns down, then back up at a larger deflection, and the path ends at λ = 1 past it.
  CHECK(r.arc.limits[0].maximum);
  CHECK_FALSE(r.arc.limits[1].maximum);
  CHECK(r.arc.limits[1].load < r.arc.limits[0].load);
  CHECK(r.arc.limits[1].deflection > r.arc.limits[0].deflection);
  CHECK(r.arc.limits[0].load < o.load);
  // Between the limit points the tangent stiffness is indefinite, and arc length stays on that unstable branch.
  CHECK(r.arc.maxNegativePivots >= 1);
  // The same equilibria at the same deflections (solver tolerance 1e-6 of P), and limit points located within
  // the sampling of the two traces.
  CHECK(r.comparedLimits == 2);  // the path is single-valued in w at this thickness
  CHECK(r.comparedPoints >= 10);
  CHECK(r.curveDifference <= 1e-5);
  CHECK(r.limitLoadDifference <= 0.01);
  CHECK(r.limitDeflectionDifference <= 0.02);
}
