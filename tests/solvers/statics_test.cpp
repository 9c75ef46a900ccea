#include "solvers/statics.h"
#include "energies/shell/boundary_rules.h"
#include "tests/solvers/test_problems.h"
#include "tests/solvers/wells_term.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

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
  o.saddleStep = 0.1;
  o.branchSwitch.bisections = -1;
  CHECK_THROWS_WITH(solveStatics(system, x, o), Catch::Contains("branchSwitch.bisections"));
  o.branchSwitch.bisections = 10;
  o.branchSwitch.step = 0.0;
  CHECK_THROWS_WITH(solveStatics(system, x, o), Catch::Contains("branchSwitch.step"));
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

/// testing::compressedPlate from rest in steps of 0.1, landing on λ = 0.25, 0.5, 0.75 and 1, by load control unless
/// `adjust` changes the options. `seen` gets every step the callback saw.
StaticsResult solveCompressedPlate(double total, Eigen::VectorXd& x,
                                   const std::function<void(LoadSteppingOptions&)>& adjust,
                                   std::vector<LoadStepResult>* seen = nullptr) {
  ShellSystem system(testing::compressedPlate(total), AnalysisKind::Statics);
  x = system.restPositions();
  LoadSteppingOptions o = {};
  o.newton = staticNewtonOptions();
  o.initialIncrement = o.maxIncrement = 0.1;
  o.levels = {0.25, 0.5, 0.75};
  adjust(o);
  return solveStatics(system, x, o, [&](const LoadStepResult& s) {
    if (seen != nullptr) seen->push_back(s);
    return true;
  });
}

/// The same by load control with `escapes` saddle escapes; `steps` gets the step indices the callback saw.
StaticsResult compressFlatPlate(double total, int escapes, Eigen::VectorXd& x, bool branchSwitching = false,
                                std::vector<int>* steps = nullptr) {
  std::vector<LoadStepResult> seen;
  const StaticsResult r = solveCompressedPlate(total, x, [&](LoadSteppingOptions& o) {
    o.saddleEscapes = escapes;
    o.branchSwitching = branchSwitching;
  }, &seen);
  if (steps != nullptr)
    for (const LoadStepResult& s : seen) steps->push_back(s.step);
  return r;
}

/// The largest out-of-plane displacement of x.
double largestDeflection(const Eigen::VectorXd& x) {
  double z = 0.0;
  for (Eigen::Index i = 2; i < x.size(); i += 3) z = std::max(z, std::abs(x[i]));
  return z;
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

namespace {

/// One vertex on a path with a known answer: x and y on springs to 0, z with the energy f(z, λ) that `energy`
/// gives with its first two derivatives; the load factor reaches it through a hook.
class OneVertexTerm : public EnergyTerm {
 public:
  struct Value {
    double energy, gradient, hessian;
  };
  using Energy = std::function<Value(double z, double lambda)>;
  explicit OneVertexTerm(Energy energy) : energy_(std::move(energy)) {}
  double lambda = 0.0;
  std::string name() const override { return "one_vertex"; }
  StencilTable stencils() const override {
    StencilTable t;
    t.width = 1;
    t.ids.push_back(0);
    return t;
  }
  bool zeroAtRest() const override { return false; }
  bool rigidInvariant() const override { return false; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override {
    const Value z = energy_(x[2], lambda);
    if (request.gradient != nullptr) {
      (*request.gradient)[0] += x[0];
      (*request.gradient)[1] += x[1];
      (*request.gradient)[2] += z.gradient;
    }
    if (request.hessian != nullptr) {
      Eigen::Matrix3d H = Eigen::Vector3d(1.0, 1.0, z.hessian).asDiagonal();
      projectPsd<3>(H, options.projection);
      request.hessian->addElementHessian(request.hessianSlot, 0, H.data());
    }
    return 0.5 * (x[0] * x[0] + x[1] * x[1]) + z.energy;
  }

 private:
  Energy energy_;
};

/// The vertex from `start` by load control in steps of 0.1 to λ = 1 (x: the end state), with o's other options.
StaticsResult solveOneVertex(const OneVertexTerm::Energy& energy, const Eigen::Vector3d& start, LoadSteppingOptions o,
                             Eigen::VectorXd& x) {
  Objective objective(1);
  auto term = std::make_shared<OneVertexTerm>(energy);
  objective.addTerm(term);
  PhysicalScales scales;
  scales.force = scales.length = 1.0;
  objective.setScales(scales);
  LoadFactorHooks loads;
  loads.others.push_back({[term](double l) { term->lambda = l; }, {}});
  x = start;
  o.newton = staticNewtonOptions();
  o.initialIncrement = o.maxIncrement = 0.1;
  return solveStatics(objective, loads, x, o);
}

/// A subcritical pitchfork at λ_c = 0.55: f = ½ (1 − λ/λ_c) z² − ¼ z⁴ + ⅙ z⁶. z = 0 is stable below λ_c and a saddle
/// above. The branch leaving it, λ = λ_c (1 − z² + z⁴), falls and is unstable up to z² = ½
/// (f'' = (1 − λ/λ_c) − 3 z² + 5 z⁴ = 2 z⁴ − 2 z² < 0 on it), then rises and is stable.
constexpr double kCritical = 0.55;
OneVertexTerm::Value subcritical(double z, double lambda) {
  const double a = 1.0 - lambda / kCritical, z2 = z * z;
  return {0.5 * a * z2 - 0.25 * z2 * z2 + z2 * z2 * z2 / 6.0, a * z - z2 * z + z2 * z2 * z,
          a - 3.0 * z2 + 5.0 * z2 * z2};
}

/// The subcritical vertex from (0.5, 0.5, 0), switching with `step`.
StaticsResult solveSubcritical(double step, Eigen::VectorXd& x) {
  LoadSteppingOptions o = {};
  o.branchSwitch.step = step;
  return solveOneVertex(subcritical, Eigen::Vector3d(0.5, 0.5, 0.0), o, x);
}

/// A vertex that snaps through (a shallow two-bar truss reduced to its apex): f = ¼ (z² − 1)² + λ z. From z = 1 at
/// λ = 0 the equilibria z³ − z + λ = 0 reach a limit point at z = 1/√3, λ = 2 / (3√3) = 0.385; past it the only
/// equilibrium is the inverted one, z < −1. Solved from its rest state (0, 0, 1).
StaticsResult solveSnap(bool detect, Eigen::VectorXd& x) {
  LoadSteppingOptions o = {};
  o.detectJumps = detect;
  auto snap = [](double z, double lambda) {
    return OneVertexTerm::Value{0.25 * (z * z - 1.0) * (z * z - 1.0) + lambda * z, z * z * z - z + lambda,
                                3.0 * z * z - 1.0};
  };
  return solveOneVertex(snap, Eigen::Vector3d(0.0, 0.0, 1.0), o, x);
}

}  // namespace

TEST_CASE("statics: load control reports a step whose equilibrium jumps past a limit point", "[statics]") {
  testing::SingleThread single;
  Eigen::VectorXd x;
  const StaticsResult r = solveSnap(true, x);
  INFO(r.message);
  REQUIRE(r.completed);
  CHECK(x[2] == Approx(-1.324718).epsilon(1e-5));  // the inverted root of z³ − z + 1 = 0
  REQUIRE(r.loadJumps.size() == 1);
  const LoadJump& j = r.loadJumps.front();
  const double limit = 2.0 / (3.0 * std::sqrt(3.0));
  CHECK(j.loadFactorBefore < limit);
  CHECK(j.loadFactorAfter > limit);
  CHECK(j.energyReleased > 0.0);
  CHECK(j.ratio > LoadJump::kRatio);
  CHECK(r.steps[static_cast<std::size_t>(j.step)].loadFactor == j.loadFactorAfter);
  CHECK(r.message.find("changed abruptly") != std::string::npos);
  // Off: the same path, nothing reported.
  const StaticsResult quiet = solveSnap(false, x);
  CHECK(quiet.loadJumps.empty());
  CHECK(x[2] == Approx(-1.324718).epsilon(1e-5));
}

TEST_CASE("statics: smooth load paths report no jump", "[statics]") {
  testing::SingleThread single;
  // A cantilever plate bent far (tip force 20 N on a 1 m plate, E h³ small) in ten steps, and in one.
  for (double steps : {0.1, 1.0}) {
    ShellSystem system(testing::cantileverPlate(8, 2, 20.0), AnalysisKind::Statics);
    Eigen::VectorXd x = system.restPositions();
    LoadSteppingOptions o = {};
    o.newton = staticNewtonOptions();
    o.initialIncrement = o.maxIncrement = steps;
    const StaticsResult r = solveStatics(system, x, o);
    INFO("increment " << steps << ": " << r.message);
    REQUIRE(r.completed);
    CHECK(x[3 * 26 + 2] > 0.3);  // the free corner rose far
    CHECK(r.loadJumps.empty());
  }
}

TEST_CASE("statics: a branch switch lands only on a stable branch", "[statics]") {
  Eigen::VectorXd x;
  SECTION("a step that reaches the stable part of the branch switches") {
    // |Δz| = 1 meets the branch at z² = 1, λ = λ_c, stable (E_zz = 2); from there arc length follows it up to λ = 1,
    // where z² = ½ (1 + √(1 − 4 (1 − 1/λ_c))).
    const StaticsResult r = solveSubcritical(1.0, x);
    INFO(r.message);
    REQUIRE(r.completed);
    REQUIRE(r.branchSwitches.size() == 1);
    CHECK(r.branchSwitches[0].stableLoadFactor <= kCritical);
    CHECK(r.branchSwitches[0].unstableLoadFactor >= kCritical);
    CHECK(r.branchSwitches[0].loadFactor == Approx(kCritical).epsilon(1e-3));
    const double z2 = 0.5 * (1.0 + std::sqrt(1.0 - 4.0 * (1.0 - 1.0 / kCritical)));
    CHECK(std::abs(x[2]) == Approx(std::sqrt(z2)).epsilon(1e-6));
    CHECK(r.unstableSteps == 0);
  }
  SECTION("steps that reach only its unstable part are refused, and the saddle escape takes over") {
    // |Δz| ≤ 0.2 meets the branch where it is unstable (z² < ½): each landing is refused, the reason kept.
    const StaticsResult r = solveSubcritical(0.2, x);
    INFO(r.message);
    REQUIRE(r.completed);
    CHECK(r.branchSwitches.empty());
    CHECK(r.branchSwitchFailure.find("negative eigenvalue") != std::string::npos);
    CHECK(r.message.find("no branch switch") != std::string::npos);
    CHECK(r.saddleEscapes >= 1);
    CHECK(r.unstableSteps == 0);
    const double z2 = 0.5 * (1.0 + std::sqrt(1.0 - 4.0 * (1.0 - 1.0 / kCritical)));
    CHECK(std::abs(x[2]) == Approx(std::sqrt(z2)).epsilon(1e-6));
  }
}

TEST_CASE("statics: load control switches at a bifurcation to the stable branch and follows it", "[statics]") {
  // testing::compressedPlate at twice its buckling load (P_cr = 0.090 N for the continuum strip, so λ_c ≈ 0.5).
  testing::SingleThread single;
  Eigen::VectorXd flat, buckled;
  const StaticsResult saddle = compressFlatPlate(2.0 * 0.090, 0, flat);
  std::vector<int> seen;
  const StaticsResult r = compressFlatPlate(2.0 * 0.090, 0, buckled, true, &seen);
  INFO(r.message);
  REQUIRE(r.completed);
  REQUIRE(r.branchSwitches.size() == 1);
  const BranchSwitchPoint& b = r.branchSwitches.front();
  // The bracket on the critical load: ten halvings of one load step of 0.1 (at most), inside the bracket that arc
  // length reports when it passes the same bifurcation on the flat path (its path points are independent of the
  // load steps here).
  CHECK(b.stableLoadFactor < b.unstableLoadFactor);
  CHECK(b.unstableLoadFactor - b.stableLoadFactor < 0.1 / 512);
  CHECK(b.negativeEigenvalues == 1);
  {
    ShellSystem system(testing::compressedPlate(2.0 * 0.090), AnalysisKind::Statics);
    Eigen::VectorXd x = system.restPositions();
    LoadSteppingOptions o = {};
    o.newton = staticNewtonOptions();
    o.path.control = PathControl::ArcLength;
    o.initialIncrement = o.maxIncrement = 0.02;
    o.branchSwitching = false;  // arc length then reports the bifurcation and keeps to the flat path
    const StaticsResult arc = solveStatics(system, x, o);
    REQUIRE(arc.bifurcationPoints.size() == 1);
    CHECK(arc.bifurcationPoints[0].loadFactorBefore <= b.stableLoadFactor);
    CHECK(arc.bifurcationPoints[0].loadFactorAfter >= b.unstableLoadFactor);
  }
  // It landed on the new branch just past the bracket, with no negative eigenvalue.
  CHECK(b.loadFactor >= b.stableLoadFactor);
  CHECK(b.loadFactor < b.unstableLoadFactor + 0.05);
  CHECK(r.steps[static_cast<std::size_t>(b.step)].negativePivots == 0);
  // On to the target by arc length: every level landed on, every equilibrium stable, the steps numbered in order
  // for the callback and in the result alike.
  CHECK(r.unstableSteps == 0);
  CHECK(r.bifurcationPoints.empty());
  std::vector<double> levels;
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    const LoadStepResult& s = r.steps[i];
    CHECK(s.step == static_cast<int>(i));
    CHECK(s.negativePivots <= 0);
    if (s.atLevel) levels.push_back(s.loadFactor);
  }
  REQUIRE(seen.size() == r.steps.size());
  for (std::size_t i = 0; i < seen.size(); ++i) CHECK(seen[i] == static_cast<int>(i));
  REQUIRE(levels.size() == 4);
  CHECK(levels.back() == Approx(1.0).margin(1e-12));
  CHECK(r.steps.back().loadFactor == Approx(1.0).margin(1e-12));
  // The plate buckled, and the buckled state is a lower equilibrium than the flat saddle at the same load.
  CHECK(largestDeflection(flat) == 0.0);
  CHECK(largestDeflection(buckled) > 0.1);
  CHECK(r.steps.back().summary.finalEnergy < saddle.steps.back().summary.finalEnergy);
  // Below the buckling load nothing is switched.
  Eigen::VectorXd below;
  const StaticsResult stable = compressFlatPlate(0.4 * 0.090, 0, below, true);
  CHECK(stable.branchSwitches.empty());
  CHECK(largestDeflection(below) == 0.0);
}

TEST_CASE("statics: arc length switches at a bifurcation to the stable branch, as load control does", "[statics]") {
  testing::SingleThread single;
  Eigen::VectorXd byLoad;
  const StaticsResult load = compressFlatPlate(2.0 * 0.090, 0, byLoad, true);
  REQUIRE(load.branchSwitches.size() == 1);
  Eigen::VectorXd x;
  std::vector<LoadStepResult> seen;
  const StaticsResult r = solveCompressedPlate(
      2.0 * 0.090, x, [](LoadSteppingOptions& o) { o.path.control = PathControl::ArcLength; }, &seen);
  INFO(r.message);
  REQUIRE(r.completed);
  REQUIRE(r.branchSwitches.size() == 1);
  CHECK(r.bifurcationPoints.empty());
  CHECK(r.message.rfind("arcLength control switched at a bifurcation", 0) == 0);
  // The same bracket on the critical load as load control's, to the bisection's resolution.
  const BranchSwitchPoint &a = r.branchSwitches.front(), &b = load.branchSwitches.front();
  CHECK(a.negativeEigenvalues == 1);
  CHECK(a.stableLoadFactor < a.unstableLoadFactor);
  CHECK(std::abs(a.stableLoadFactor - b.stableLoadFactor) < 0.02);
  // Every step stable and in order, the path parameter rising through the switch, every level landed on once.
  std::vector<double> levels;
  REQUIRE(seen.size() == r.steps.size());
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    CHECK(r.steps[i].step == static_cast<int>(i));
    CHECK(seen[i].step == static_cast<int>(i));
    CHECK(r.steps[i].negativePivots <= 0);
    if (i > 0) CHECK(r.steps[i].pathParameter > r.steps[i - 1].pathParameter);
    if (r.steps[i].atLevel) levels.push_back(r.steps[i].loadFactor);
  }
  CHECK(levels == std::vector<double>{0.25, 0.5, 0.75, 1.0});
  // The same buckled equilibrium at λ = 1 (up to the mode's sign): as deflected, and as low in energy.
  CHECK(largestDeflection(x) == Approx(largestDeflection(byLoad)).epsilon(1e-4));
  CHECK(r.steps.back().summary.finalEnergy == Approx(load.steps.back().summary.finalEnergy).epsilon(1e-6));
}

TEST_CASE("statics: a first load step that lands on a saddle switches from the start", "[statics]") {
  // The compressed plate loaded to twice its buckling load in one step: no accepted equilibrium precedes the
  // saddle, so the rest state (stable, unloaded) is the bracket's stable end.
  testing::SingleThread single;
  Eigen::VectorXd stepped;
  const StaticsResult reference = compressFlatPlate(2.0 * 0.090, 0, stepped, true);
  REQUIRE(reference.branchSwitches.size() == 1);
  Eigen::VectorXd x;
  const StaticsResult r = solveCompressedPlate(2.0 * 0.090, x, [](LoadSteppingOptions& o) {
    o.saddleEscapes = 0;
    o.initialIncrement = o.maxIncrement = 1.0;
    o.levels.clear();
  });
  INFO(r.message);
  REQUIRE(r.completed);
  REQUIRE(r.branchSwitches.size() == 1);
  const BranchSwitchPoint& b = r.branchSwitches.front();
  CHECK(b.stableLoadFactor < b.unstableLoadFactor);
  CHECK(b.unstableLoadFactor - b.stableLoadFactor < 1.0 / 512);  // ten halvings of the one step
  CHECK(b.stableLoadFactor < reference.branchSwitches.front().unstableLoadFactor);
  CHECK(b.unstableLoadFactor > reference.branchSwitches.front().stableLoadFactor);
  CHECK(r.unstableSteps == 0);
  CHECK(largestDeflection(x) == Approx(largestDeflection(stepped)).epsilon(1e-4));
  CHECK(r.steps.back().summary.finalEnergy == Approx(reference.steps.back().summary.finalEnergy).epsilon(1e-6));
}

TEST_CASE("statics: a switch that lands far below the critical load is refused", "[statics]") {
  // The rule: within the step, and not more than four bracket widths below the bracket (either direction of λ).
  CHECK(landingOutside(0.62, 0.6, 0.7, 0.6167, 0.6168).empty());
  CHECK(landingOutside(0.6166, 0.6, 0.7, 0.6167, 0.6168).empty());  // 1 width below: a nearly flat branch
  CHECK(landingOutside(1e-10, 0.0, 1.0, 0.0635, 0.0645) == "below the bracket on the critical load");
  CHECK(landingOutside(0.71, 0.6, 0.7, 0.6167, 0.6168) == "outside the step");
  CHECK(landingOutside(0.6, 0.6, 0.7, 0.6167, 0.6168) == "outside the step");
  CHECK(landingOutside(0.45, 0.5, 0.4, 0.47, 0.469).empty());  // λ falling
  CHECK(landingOutside(0.49, 0.5, 0.4, 0.47, 0.469) == "below the bracket on the critical load");
  // Where it mattered: a cloth hanging in its plane from two corners buckles out of it under its weight (λ ≈ 0.064
  // here). When the first load step, to the whole weight, lands on the flat saddle (whether Newton keeps the
  // symmetry depends on round-off, so on the build), the switch's correction finds the cloth turned about its two
  // pins at no load, λ ≈ 1e-10, inside the step; accepted, the path went on from the unloaded cloth and ran out of
  // steps. Refused, the saddle escapes take the cloth off the saddle. Either way the run ends stable.
  testing::SingleThread single;
  ShellSystem system(testing::hangingCloth(0.3, 0.3, 6, 6), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  const StaticsResult r = solveStatics(system, x, LoadSteppingOptions{});
  INFO(r.message);
  REQUIRE(r.completed);
  CHECK(r.branchSwitches.empty());
  CHECK(r.unstableSteps == 0);
  CHECK(r.steps.back().loadFactor == 1.0);
}
