#include "core/mesh.h"
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

}  // namespace

TEST_CASE("path following: arc length lands on every level crossed and agrees with load control there",
          "[statics][path]") {
  testing::SingleThread single;
  ShellSystem system(testing::cantileverPlate(6, 2, 0.2), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = pathOptions(PathControl::ArcLength);
  o.newton.residualTolerance = 1e-9;
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

TEST_CASE("path following: a bifurcation passed on a symmetric path is reported, a limit point is not one",
          "[statics][path]") {
  testing::SingleThread single;
  // A flat plate compressed to twice its buckling load (testing::compressedPlate): arc length follows the flat path
  // through the bifurcation, where the tangent stiffness gains its first negative eigenvalue without λ turning.
  ShellSystem system(testing::compressedPlate(2.0 * 0.090), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  const StaticsResult r = solveStatics(system, x, pathOptions(PathControl::ArcLength));
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
