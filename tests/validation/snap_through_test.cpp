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

TEST_CASE("snap-through: displacement control reports the thin roof's snap-back, and arc length follows it",
          "[validation][path]") {
  // The thin roof (h = 6.35) snaps back: past P_max the load point's deflection itself turns back, so displacement
  // control of it jumps to another equilibrium at the same deflection, which it now reports. Arc length follows the
  // path through its four limit points.
  testing::SingleThread single;
  RoofOptions o;
  o.resolution = {8, 8};
  o.thickness = 6.35;
  o.load = 1000.0;
  o.maxDeflection = 35.0;
  const RoofResult r = runHingedRoof(o);
  INFO(formatRoof(r));
  REQUIRE(r.displacement.completed);
  REQUIRE(r.displacement.jumps.size() == 1);
  const LoadJump& j = r.displacement.jumps.front();
  CHECK(j.loadFactorBefore > 0.0);   // from the unstable stretch after P_max ...
  CHECK(j.loadFactorAfter < 0.0);    // ... to a pulled-back equilibrium at the same deflection
  CHECK(j.ratio > LoadJump::kRatio);
  REQUIRE(r.arc.completed);
  CHECK(r.arc.jumps.empty());
  CHECK(r.arc.limits.size() == 4);
}
