#include "core/mesh.h"
#include "solvers/path_energy.h"
#include "solvers/path_following.h"
#include "solvers/statics.h"
#include "tests/solvers/test_problems.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace jetshell;

namespace {

LoadSteppingOptions pathOptions(PathControl control) {
  LoadSteppingOptions o;
  o.newton = staticNewtonOptions();
  o.initialIncrement = 0.1;
  o.maxIncrement = 0.25;
  o.path.control = control;
  return o;
}

/// The equilibrium at λ by load control (the reference for the other controls).
Eigen::VectorXd loadControlled(double lambda) {
  ShellSystem system(testing::cantileverPlate(6, 2, 0.2), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o;
  o.newton = staticNewtonOptions();
  o.newton.residualTolerance = 1e-9;
  o.targetLoadFactor = lambda;
  o.initialIncrement = 0.1;
  REQUIRE(solveStatics(system, x, o).completed);
  return x;
}

/// A cantilever plate under a tip load by arc length, to a residual of 1e-9, on one thread.
struct CantileverArc {
  testing::SingleThread single;
  ShellSystem system{testing::cantileverPlate(6, 2, 0.2), AnalysisKind::Statics};
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions options = [] {
    LoadSteppingOptions o = pathOptions(PathControl::ArcLength);
    o.newton.residualTolerance = 1e-9;
    return o;
  }();
};

}  // namespace

TEST_CASE("path following: arc length lands on every level crossed and agrees with load control there",
          "[statics][path]") {
  CantileverArc c;
  ShellSystem& system = c.system;
  Eigen::VectorXd& x = c.x;
  LoadSteppingOptions& o = c.options;
  o.levels = {0.5};
  std::vector<LoadStepResult> levels;
  const StaticsResult r = solveStatics(system, x, o, [&](const LoadStepResult& s) {
    if (s.atLevel) levels.push_back(s);
    CHECK(s.summary.converged());
    CHECK(s.negativePivots == 0);  // a cantilever under a tip load stays stable
    CHECK(system.nodalForces->loadFactor() == s.loadFactor);  // what the callback evaluates is at the step's λ
    return true;
  });
  INFO(r.message);
  REQUIRE(r.completed);
  CHECK(r.limitPoints.empty());
  REQUIRE(levels.size() == 2);
  CHECK(levels[0].loadFactor == 0.5);
  CHECK(levels[1].loadFactor == 1.0);
  CHECK(r.loadFactor == 1.0);
  for (std::size_t k = 1; k < r.steps.size(); ++k) CHECK(r.steps[k].pathParameter > r.steps[k - 1].pathParameter);
  // The same equilibria as load control (the shell's tip moves by about 0.3 m).
  CHECK((levels[0].x - loadControlled(0.5)).cwiseAbs().maxCoeff() < 1e-6);
  CHECK((x - loadControlled(1.0)).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("path following: displacement control holds the dof on its levels and finds the load that balances it",
          "[statics][path]") {
  testing::SingleThread single;
  const Eigen::VectorXd reference = loadControlled(1.0);
  ShellSystem system(testing::cantileverPlate(6, 2, 0.2), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  const int tip = 3 * 6 + 2;  // vertex 6 (x = 1, y = 0), component z
  const double X = x[tip];
  LoadSteppingOptions o = pathOptions(PathControl::Displacement);
  o.newton.residualTolerance = 1e-9;
  o.path.controlledDof = tip;
  o.path.displacement = reference[tip] - X;  // the tip deflection load control reaches at λ = 1
  o.levels = {0.5};
  std::vector<double> held;
  const StaticsResult r = solveStatics(system, x, o, [&](const LoadStepResult& s) {
    if (s.atLevel) held.push_back((s.x[tip] - X) / o.path.displacement);
    return true;
  });
  INFO(r.message);
  REQUIRE(r.completed);
  REQUIRE(held.size() == 2);
  CHECK(held[0] == Approx(0.5).epsilon(1e-12));
  CHECK(held[1] == Approx(1.0).epsilon(1e-12));
  CHECK(r.loadFactor == Approx(1.0).epsilon(1e-6));
  CHECK((x - reference).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("path following: bad path options are refused by name", "[statics][path]") {
  testing::SingleThread single;
  ShellSystem system(testing::cantileverPlate(2, 1, 0.1), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = pathOptions(PathControl::Displacement);
  o.path.controlledDof = 2;  // vertex 0 is clamped
  o.path.displacement = 0.1;
  CHECK_THROWS_WITH(solveStatics(system, x, o), Catch::Contains("controlledDof") && Catch::Contains("fixed"));
  o.path.controlledDof = 3 * 2 + 2;
  o.path.displacement = 0.0;
  CHECK_THROWS_WITH(solveStatics(system, x, o), Catch::Contains("displacement"));
  o.path.controlledDof = 999;
  o.path.displacement = 0.1;
  CHECK_THROWS_WITH(solveStatics(system, x, o), Catch::Contains("controlledDof"));
  LoadSteppingOptions a = pathOptions(PathControl::ArcLength);
  a.path.maxSteps = 0;
  CHECK_THROWS_WITH(solveStatics(system, x, a), Catch::Contains("maxSteps"));
  a.path.maxSteps = 10;
  a.path.loadScaling = -1.0;
  CHECK_THROWS_WITH(solveStatics(system, x, a), Catch::Contains("loadScaling"));
  a.path.loadScaling = 1e300;  // finite, but ψ²|q|² is not: refused, not "the loads do not move the shell"
  CHECK_THROWS_WITH(solveStatics(system, x, a), Catch::Contains("loadScaling") && Catch::Contains("too large"));
}

TEST_CASE("path following: a path that runs out of steps says so and keeps its last equilibrium", "[statics][path]") {
  testing::SingleThread single;
  ShellSystem system(testing::cantileverPlate(4, 1, 0.2), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = pathOptions(PathControl::ArcLength);
  o.initialIncrement = o.maxIncrement = 0.05;
  o.path.maxSteps = 3;
  const StaticsResult r = solveStatics(system, x, o);
  CHECK_FALSE(r.completed);
  CHECK_THAT(r.message, Catch::Contains("maxSteps"));
  REQUIRE(r.steps.size() == 3);
  CHECK(x == r.steps.back().x);
  CHECK(r.loadFactor == r.steps.back().loadFactor);
  CHECK(r.loadFactor < 1.0);
}

TEST_CASE("path following: the limit load is the vertex of the parabola through three path points", "[statics][path]") {
  // λ(p) = 2 − (p − 1.2)²: the turn is at p = 1.2, λ = 2.
  const double p[3] = {0.5, 1.0, 2.0};
  double l[3];
  for (int i = 0; i < 3; ++i) l[i] = 2.0 - (p[i] - 1.2) * (p[i] - 1.2);
  CHECK(limitLoadFactor(p, l) == Approx(2.0).epsilon(1e-12));
  // Points on a line have no vertex: the middle value.
  const double m[3] = {0.0, 1.0, 3.0};
  CHECK(limitLoadFactor(p, m) == 1.0);
}

TEST_CASE("path following: the turn between two path points is the Hermite cubic's extremum", "[statics][path]") {
  // λ(p) = 1 + 2p − 3p² + 0.5p³ on [0, 1]: λ' = 2 − 6p + 1.5p² vanishes at p = (6 − √24) / 3 = 0.36701.
  auto lambda = [](double p) { return 1.0 + 2.0 * p - 3.0 * p * p + 0.5 * p * p * p; };
  auto slope = [](double p) { return 2.0 - 6.0 * p + 1.5 * p * p; };
  const double turn = (6.0 - std::sqrt(24.0)) / 3.0;
  CHECK(hermiteTurn(0.0, lambda(0.0), slope(0.0), 1.0, lambda(1.0), slope(1.0), -1.0) ==
        Approx(lambda(turn)).epsilon(1e-12));
  // Shifted and scaled in p: the same turn.
  CHECK(hermiteTurn(2.0, lambda(0.0), slope(0.0) / 4.0, 6.0, lambda(1.0), slope(1.0) / 4.0, -1.0) ==
        Approx(lambda(turn)).epsilon(1e-12));
  // A minimum.
  CHECK(hermiteTurn(0.0, 0.0, -1.0, 2.0, 0.0, 1.0, -1.0) == Approx(-0.5).epsilon(1e-12));
  // Slopes of one sign (no turn inside): the fallback.
  CHECK(hermiteTurn(0.0, 0.0, 1.0, 1.0, 1.0, 1.0, -7.0) == -7.0);
}

TEST_CASE("path following: a bifurcation passed on a symmetric path is reported, a limit point is not one",
          "[statics][path]") {
  testing::SingleThread single;
  // A flat plate compressed to twice its buckling load (testing::compressedPlate): arc length follows the flat path
  // through the bifurcation, where the tangent stiffness gains its first negative eigenvalue without λ turning,
  // when told not to switch branches there (branchSwitching: statics_test.cpp has the switch).
  ShellSystem system(testing::compressedPlate(2.0 * 0.090), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = pathOptions(PathControl::ArcLength);
  o.branchSwitching = false;
  const StaticsResult r = solveStatics(system, x, o);
  INFO(r.message);
  REQUIRE(r.completed);
  CHECK(r.limitPoints.empty());
  REQUIRE(r.bifurcationPoints.size() == 1);
  const BifurcationPoint& b = r.bifurcationPoints[0];
  CHECK(b.negativeBefore == 0);
  CHECK(b.negativeAfter == 1);
  // The continuum's critical load lies between the beam's (E b h³ / 12 for D b: P_cr / P = 0.457) and the plate
  // strip's (0.5); the mesh's own lies within a few percent of that range.
  CHECK(b.loadFactorBefore < 0.5 * 1.05);
  CHECK(b.loadFactorAfter > 0.457 * 0.95);
  CHECK(b.loadFactorBefore < b.loadFactorAfter);
}

namespace {

/// The crumpled sheet by arc length in n level steps, as a scene sets them up (levels k / n, the first increment a
/// quarter of a level).
StaticsResult crumpledByArcLength(int n) {
  ShellSystem system(testing::crumpledSheet(), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = pathOptions(PathControl::ArcLength);
  o.maxIncrement = 1.0 / n;
  o.initialIncrement = 0.25 / n;
  o.path.maxSteps = 400;
  for (int k = 1; k < n; ++k) o.levels.push_back(static_cast<double>(k) / n);
  return solveStatics(system, x, o);
}

}  // namespace

TEST_CASE("path following: arc length cuts a step that jumps to another branch, so long steps find the limit points",
          "[statics][path]") {
  testing::SingleThread single;
  // The crumpled sheet (testing::crumpledSheet). With steps of up to 0.25 and no energy check, arc length jumped
  // between branches and reported turns at λ = 0.068 and −0.101; with steps of up to 0.025, 0.1731 and −0.0504.
  const StaticsResult fine = crumpledByArcLength(40), coarse = crumpledByArcLength(4);
  INFO(fine.message << "\n" << coarse.message);
  REQUIRE(fine.completed);
  REQUIRE(coarse.completed);
  REQUIRE(fine.limitPoints.size() == 2);
  REQUIRE(coarse.limitPoints.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(coarse.limitPoints[i].maximum == (i == 0));
    CHECK(coarse.limitPoints[i].loadFactor == Approx(fine.limitPoints[i].loadFactor).epsilon(0.02));
  }
  // This sheet's turns by 400 steps of at most 0.0025: λ = 0.17389 and −0.05037.
  CHECK(fine.limitPoints[0].loadFactor == Approx(0.17389).epsilon(0.01));
  CHECK(fine.limitPoints[1].loadFactor == Approx(-0.05037).epsilon(0.01));
  // The jumps were cut into steps that follow the path: none is left to report.
  CHECK(coarse.loadJumps.empty());
  CHECK(fine.loadJumps.empty());
  CHECK(coarse.totalCuts > 0);
}

TEST_CASE("path following: the energy identity holds across a limit point and fails across a jump", "[statics][path]") {
  // One dof that snaps through: E = ¼ (z² − 1)² + λ z, equilibria λ = z − z³ (a limit point at z = 1/√3), path
  // parameter p = z (decreasing), start z = 1. ∂E/∂λ = z, and 1 at the start position; dλ/dp = 1 − 3 z².
  auto at = [](double z, double lambda) {
    PathEnergy e;
    e.lambda = lambda;
    e.energy = 0.25 * (z * z - 1.0) * (z * z - 1.0) + lambda * z;
    e.slope = z;
    e.referenceSlope = 1.0;
    e.loadRate = 1.0 - 3.0 * z * z;
    return e;
  };
  auto onPath = [&](double z) { return at(z, z - z * z * z); };
  // A step across the limit point (λ rises to 0.385 and falls back within it): the trapezoid in p errs by O(Δp³),
  // and the loads' work in a step centred on the turn is O(Δp²) (dλ/dp vanishes there), so the ratio falls as Δp.
  double previous = 1.0;
  for (double dz : {0.2, 0.1, 0.05}) {
    const double za = 0.577 + 0.5 * dz, zb = 0.577 - 0.5 * dz;
    const PathMismatch m = tangentMismatch(onPath(za), onPath(zb), zb - za);
    INFO("dz " << dz << ": released " << m.released << ", work " << m.work);
    CHECK(m.work > 0.0);
    const double ratio = std::abs(m.released) / m.work;
    CHECK(ratio < LoadJump::kRatio);
    CHECK(ratio < 0.6 * previous);
    previous = ratio;
  }
  // A step from z = 0.65 that lands on the inverted branch at z = 0.5's λ (z³ − z + λ = 0 at z ≈ −1.15) instead of
  // following the path over the limit point: the mismatch is more than the loads' work (1.13 of it).
  const double lambda = 0.5 - 0.125;
  double zc = -1.1;
  for (int k = 0; k < 50; ++k) zc -= (zc * zc * zc - zc + lambda) / (3.0 * zc * zc - 1.0);
  PathEnergy c = at(zc, lambda);
  c.loadRate = 1.0 - 3.0 * zc * zc;
  const PathMismatch jump = tangentMismatch(onPath(0.65), c, std::abs(zc - 0.65));
  INFO("released " << jump.released << ", work " << jump.work);
  CHECK(std::abs(jump.released) > LoadJump::kRatio * jump.work);
}

TEST_CASE("path following: arc length's landings start from the Hermite cubic through the path points",
          "[statics][path]") {
  // Landing on a level between two path points is a load-controlled correction. From the cubic Hermite
  // interpolant with the tangents dx/dλ = K⁻¹q at both points it starts third-order close (the chord: second).
  // Measured: the 10 landings take 24 Newton iterations (from the chord: 50), the 11 steps 44.
  CantileverArc c;
  c.options.levels = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
  int landings = 0, landingIterations = 0, stepIterations = 0, steps = 0;
  const StaticsResult r = solveStatics(c.system, c.x, c.options, [&](const LoadStepResult& s) {
    REQUIRE(s.summary.converged());
    if (s.atLevel) {
      ++landings;
      landingIterations += s.summary.iterations;
    } else {
      ++steps;
      stepIterations += s.summary.iterations;
    }
    return true;
  });
  INFO(r.message);
  REQUIRE(r.completed);
  INFO("landings " << landings << ": " << landingIterations << " iterations; steps " << steps << ": "
                    << stepIterations);
  CHECK(landings == 10);
  CHECK(landingIterations <= 3 * landings);
  CHECK((c.x - loadControlled(1.0)).cwiseAbs().maxCoeff() < 1e-6);
}
