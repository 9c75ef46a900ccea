#include "solvers/statics.h"
#include "energies/shell/boundary_rules.h"
#include "tests/solvers/test_problems.h"
#include "tests/solvers/wells_term.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

TEST_CASE("statics: the path lands on every requested level and the target, in order", "[statics]") {
  testing::SingleThread single;
  ShellSystem system(testing::cantileverPlate(8, 2, 0.5), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = {};
  o.newton = staticNewtonOptions();
  o.levels = {0.7, 0.1, 0.35};
  o.initialIncrement = 0.05;
  o.maxIncrement = 0.2;
  std::vector<double> reached;
  const StaticsResult r = solveStatics(system, x, o, [&](const LoadStepResult& s) {
    if (s.atLevel) reached.push_back(s.loadFactor);
    return true;
  });
  REQUIRE(r.completed);
  REQUIRE(reached.size() == 4);
  CHECK(reached[0] == 0.1);
  CHECK(reached[1] == 0.35);
  CHECK(reached[2] == 0.7);
  CHECK(reached[3] == 1.0);
  for (std::size_t k = 1; k < r.steps.size(); ++k) {
    CHECK(r.steps[k].loadFactor > r.steps[k - 1].loadFactor);
    CHECK(r.steps[k].loadFactor - r.steps[k - 1].loadFactor <= 0.2 + 1e-12);
  }
  CHECK(system.nodalForces->loadFactor() == 1.0);
}

TEST_CASE("statics: the polynomial predictor saves Newton iterations on a large-deflection path", "[statics]") {
  testing::SingleThread single;
  auto iterations = [](int order) {
    ShellSystem system(testing::cantileverPlate(12, 2, 0.2), AnalysisKind::Statics);
    Eigen::VectorXd x = system.restPositions();
    LoadSteppingOptions o = {};
    o.newton = staticNewtonOptions();
    o.initialIncrement = o.maxIncrement = 0.1;
    o.predictorOrder = order;
    const StaticsResult r = solveStatics(system, x, o);
    REQUIRE(r.completed);
    return r.newtonIterations;
  };
  const int without = iterations(0), with = iterations(2);
  INFO("Newton iterations: predictor order 0: " << without << ", order 2: " << with);
  CHECK(with < without);
}

TEST_CASE("statics: load-factor hooks reach other load terms and see every accepted equilibrium", "[statics]") {
  testing::SingleThread single;
  ShellSystem system(testing::cantileverPlate(4, 1, 0.1), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = {};
  o.newton = staticNewtonOptions();
  o.initialIncrement = o.maxIncrement = 0.25;
  double lastSet = -1.0;
  int accepted = 0;
  const StaticsResult r = solveStatics(system, x, o, {},
                                       {{[&](double l) { lastSet = l; }, [&](const Eigen::VectorXd&) { ++accepted; }}});
  REQUIRE(r.completed);
  CHECK(lastSet == 1.0);
  CHECK(accepted == static_cast<int>(r.steps.size()));
}

TEST_CASE("statics: the load factor ramps the weight (a stiff plate under its own weight deflects in proportion)",
          "[statics]") {
  testing::SingleThread single;
  ShellProblem p = testing::cantileverPlate(8, 2, 0.0);
  p.material = ShellMaterialParamsFrom3dIsotropic(1e11, 0.3, 1000.0, 0.01);  // tip deflection ~1 mm: linear
  p.hasGravity = true;
  p.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  ShellSystem system(p, AnalysisKind::Statics);
  REQUIRE(system.gravity != nullptr);
  Eigen::VectorXd x = system.restPositions();
  const int tip = 8;  // (x = 1, y = 0)
  LoadSteppingOptions o = {};
  o.newton = staticNewtonOptions();
  o.levels = {0.5};
  o.initialIncrement = o.maxIncrement = 0.5;
  double half = 0.0;
  const StaticsResult r = solveStatics(system, x, o, [&](const LoadStepResult& s) {
    if (s.atLevel && s.loadFactor == 0.5) half = s.x[3 * tip + 2] - system.restPositions()[3 * tip + 2];
    return true;
  });
  REQUIRE(r.completed);
  const double full = x[3 * tip + 2] - system.restPositions()[3 * tip + 2];
  INFO("tip deflection at lambda = 0.5: " << half << " m, at lambda = 1: " << full << " m");
  REQUIRE(full < -1e-4);
  REQUIRE(full > -1e-2);
  CHECK(half / full == Approx(0.5).epsilon(0.01));
  CHECK(system.gravity->loadFactor() == 1.0);
}

TEST_CASE("statics: the predictor's order drops where the path curves hard, so the increments do not creep",
          "[statics]") {
  // A 1 m cantilever swinging down to hang ~9 m long under 1e6 m/s² gravity (the stress suite's extreme/gravity_1e6
  // with the scene's edge rules): a fixed order-3 predictor started Newton up to 0.43 m off whatever the increment,
  // which shrank to minIncrement (5,013 steps).
  testing::SingleThread single;
  ShellProblem p;
  p.mesh = makeRectangleGrid(1.0, 1.0, 6, 6);
  p.material = ShellMaterialParamsFrom3dIsotropic(1e6, 0.3, 1000.0, 0.01);
  p.gravity = Eigen::Vector3d(0.0, 0.0, -1e6);
  p.clampedVertices.assign(static_cast<std::size_t>(p.mesh.numVertices()), 0);
  for (int j = 0; j <= 6; ++j) {
    p.prescribed.fixVertex(7 * j, p.mesh.V.row(7 * j).transpose());
    p.clampedVertices[static_cast<std::size_t>(7 * j)] = 1;
  }
  ShellSystem system(p, AnalysisKind::Statics);
  for (const auto& bending : system.bendingTerms) applyBoundaryRules(*bending, system.mesh(), p.clampedVertices, {}, {});
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o = {};
  o.newton = staticNewtonOptions();
  o.predictorOrder = 3;
  o.maxIncrement = 0.25;
  o.initialIncrement = 0.0625;
  o.levels = {0.25, 0.5, 0.75};
  const StaticsResult r = solveStatics(system, x, o, [](const LoadStepResult& s) { return s.step < 200; });
  INFO(r.message);
  REQUIRE(r.completed);
  CHECK(r.steps.size() <= 40);
  CHECK(x[3 * 48 + 2] < -5.0);  // the free corner hangs far below the clamp
}

TEST_CASE("statics: invalid levels and options are rejected", "[statics]") {
  ShellSystem system(testing::cantileverPlate(2, 1, 0.1), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o;
  o.levels = {1.5};
  CHECK_THROWS_AS(solveStatics(system, x, o), InputError);
  o.levels = {std::nan("")};
  CHECK_THROWS_AS(solveStatics(system, x, o), InputError);
  o.levels = {};
  o.predictorOrder = 9;
  CHECK_THROWS_AS(solveStatics(system, x, o), InputError);
  o.predictorOrder = 3;
  o.saddleEscapes = -1;
  CHECK_THROWS_AS(solveStatics(system, x, o), InputError);
  o.saddleEscapes = 3;
  o.saddleStep = 0.0;
  CHECK_THROWS_AS(solveStatics(system, x, o), InputError);
}

namespace {

struct SaddleRun {
  StaticsResult result;
  Eigen::VectorXd x;
};

SaddleRun solveSaddleWells(bool check, int escapes) {
  constexpr int n = 2;
  Objective objective(n);
  // Per vertex a saddle at the origin, E = Σ_v ½(x_v² + y_v²) + ¼ε(z_v² − 1)²: z_v = 0 is a maximum along z, z_v = ±1
  // the minima. With every z exactly 0 the gradient's z part is exactly 0, so Newton never leaves z = 0 by itself.
  // ε = 0.1 keeps the shift that makes the system positive definite at z = 0 small enough for Newton to converge
  // in x and y.
  objective.addTerm(std::make_shared<testing::WellsTerm>(n, std::array<double, 3>{0.0, 0.0, 0.1}));
  PhysicalScales scales;
  scales.force = 1.0;
  scales.length = 1.0;
  objective.setScales(scales);
  SaddleRun run;
  run.x = Eigen::VectorXd::Zero(3 * n);
  for (int v = 0; v < n; ++v) run.x[3 * v] = run.x[3 * v + 1] = 0.5 + 0.1 * v;  // in-plane off balance, z = 0
  LoadSteppingOptions o = {};
  o.newton = staticNewtonOptions();
  o.checkStability = check;
  o.saddleEscapes = escapes;
  run.result = solveStatics(objective, LoadFactorHooks{}, run.x, o);
  return run;
}

}  // namespace

TEST_CASE("statics: an equilibrium reached through an indefinite system is checked, and a saddle is left downhill",
          "[statics]") {
  testing::SingleThread single;
  SECTION("no check: Newton stops on the saddle (every z = 0), as it did before the check existed") {
    const SaddleRun r = solveSaddleWells(false, 3);
    REQUIRE(r.result.completed);
    REQUIRE(r.result.steps.size() == 1);
    CHECK(r.result.steps[0].summary.regularizations > 0);  // the system was indefinite on the way
    CHECK(r.result.steps[0].negativePivots == -1);         // not checked
    CHECK(r.x[2] == 0.0);
    CHECK(r.x[5] == 0.0);
  }
  SECTION("the check leaves the saddle for a minimum, along both negative directions at once") {
    const SaddleRun r = solveSaddleWells(true, 3);
    INFO(r.result.message);
    REQUIRE(r.result.completed);
    CHECK(r.result.saddleEscapes == 1);
    CHECK(r.result.unstableSteps == 0);
    CHECK(r.result.steps.back().negativePivots == 0);
    // At the residual tolerance (1e-6 N) a well's gradient ε z (z² − 1) ≈ 2ε (|z| − 1) leaves |z| − 1 within 5e-6.
    CHECK(std::abs(std::abs(r.x[2]) - 1.0) < 1e-5);
    CHECK(std::abs(std::abs(r.x[5]) - 1.0) < 1e-5);
    CHECK(std::abs(r.x[0]) < 1e-6);
    CHECK(r.result.steps.back().summary.finalEnergy < 1e-10);
  }
  SECTION("with no escape allowed, the saddle is kept and reported") {
    const SaddleRun r = solveSaddleWells(true, 0);
    REQUIRE(r.result.completed);
    CHECK(r.result.saddleEscapes == 0);
    CHECK(r.result.unstableSteps == 1);
    CHECK(r.result.steps.back().negativePivots == 2);
    CHECK(r.x[2] == 0.0);
    CHECK(r.result.message.find("unstable equilibrium") != std::string::npos);
  }
}

namespace {

/// testing::compressedPlate, by load control in steps of 0.1.
StaticsResult compressFlatPlate(double total, int escapes, Eigen::VectorXd& x) {
  const ShellProblem p = testing::compressedPlate(total);
  ShellSystem system(p, AnalysisKind::Statics);
  x = system.restPositions();
  LoadSteppingOptions o = {};
  o.newton = staticNewtonOptions();
  o.saddleEscapes = escapes;
  o.initialIncrement = o.maxIncrement = 0.1;
  return solveStatics(system, x, o);
}

}  // namespace

TEST_CASE("statics: a flat plate compressed in its plane is checked at every step no factor vouched for",
          "[statics]") {
  testing::SingleThread single;
  Eigen::VectorXd x;
  SECTION("below its buckling load every equilibrium is stable, including those reached without a factorization") {
    const StaticsResult r = compressFlatPlate(0.4 * 0.090, 3, x);
    REQUIRE(r.completed);
    CHECK(r.unstableSteps == 0);
    int unfactored = 0;
    for (const LoadStepResult& s : r.steps) {
      INFO("step " << s.step << ": " << s.summary.iterations << " Newton iterations");
      CHECK(s.negativePivots <= 0);
      if (s.summary.lastHessianPositiveDefinite) continue;
      CHECK(s.negativePivots == 0);  // checked, and stable
      if (s.summary.iterations == 0) ++unfactored;
    }
    CHECK(unfactored > 0);  // the predictor lands on the flat path: steps that factored nothing
    CHECK(r.stabilityChecks >= unfactored);
  }
  SECTION("past it the flat equilibrium is a saddle and is reported, where no Newton solve would have told") {
    const StaticsResult r = compressFlatPlate(2.0 * 0.090, 0, x);
    INFO(r.message);
    REQUIRE(r.completed);
    CHECK(r.unstableSteps > 0);
    CHECK(r.steps.back().negativePivots == 1);  // the first buckling mode
    CHECK(r.message.find("unstable equilibrium") != std::string::npos);
    for (Eigen::Index i = 2; i < x.size(); i += 3) CHECK(x[i] == 0.0);  // flat to the bit
  }
}
