#include "solvers/dynamic_relaxation.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

namespace {

/// One relaxation of the loaded cantilever plate: its result, end state, the potential terms' residual evaluated
/// afresh there, and the Hessians and factorizations its steps' solves took.
struct Relaxed {
  RelaxationResult result;
  Eigen::VectorXd x;
  double freshResidual = 0.0;
  int hessians = 0, factorizations = 0;
  double tip = 0.0;  // the largest displacement from rest [m]
};

Relaxed relaxCantilever(bool reuseStepGradient, bool reuseFactor) {
  ShellProblem problem = testing::cantileverPlate(6, 2, 0.01);
  problem.material.density = 1e-3;  // fictitious mass: only the end state matters
  ShellSystem system(problem, AnalysisKind::DynamicRelaxation);
  RelaxationOptions o;
  o.timeStep = 0.05;
  o.massDamping = 20.0;
  o.reuseStepGradient = reuseStepGradient;
  o.reuseFactor = reuseFactor;
  Relaxed out;
  out.x = system.restPositions();
  out.result = relaxToStatic(system, out.x, o, [&out](const StepReport& step, double) {
    for (const SolverSummary& s : step.solves) {
      out.hessians += s.hessianEvaluations;
      out.factorizations += s.numericFactorizations;
    }
    return true;
  });
  Eigen::VectorXd g;
  system.objective().evaluate(out.x, &g, false, EvalOptions{}, TermSelection::PotentialOnly);
  out.freshResidual = g.lpNorm<Eigen::Infinity>();
  out.tip = (out.x - system.restPositions()).lpNorm<Eigen::Infinity>();
  INFO(out.result.message);
  REQUIRE(out.result.converged);
  return out;
}

}  // namespace

TEST_CASE("dynamic relaxation: each step's static residual read from its solve's last gradient is the one "
          "evaluated afresh, and the relaxation ends in the same state",
          "[relaxation]") {
  testing::SingleThread single;
  const Relaxed a = relaxCantilever(true, true), b = relaxCantilever(false, true);
  CHECK(a.result.steps > 10);
  CHECK(a.result.reusedGradients == a.result.steps);  // every step's residual came from its own solve
  CHECK(b.result.reusedGradients == 0);
  CHECK(a.result.steps == b.result.steps);
  CHECK(a.result.newtonIterations == b.result.newtonIterations);
  // The residual that stopped the run is the potential terms' gradient at the final state (to rounding).
  CHECK(std::abs(a.result.staticResidual - a.freshResidual) <= 1e-9 * a.result.residualThreshold);
  CHECK(std::abs(b.result.staticResidual - b.freshResidual) <= 1e-9 * b.result.residualThreshold);
  CHECK((a.x - b.x).lpNorm<Eigen::Infinity>() <= 1e-12 * b.tip);
}

TEST_CASE("dynamic relaxation: reusing an earlier step's factor reaches the state fresh factors reach, with fewer "
          "Hessians and factorizations",
          "[relaxation]") {
  testing::SingleThread single;
  const Relaxed lagged = relaxCantilever(true, true), fresh = relaxCantilever(true, false);
  // Each step is held to the same tests, so both end in equilibrium to the same tolerance.
  CHECK(lagged.freshResidual <= lagged.result.residualThreshold);
  CHECK(fresh.freshResidual <= fresh.result.residualThreshold);
  CHECK((lagged.x - fresh.x).lpNorm<Eigen::Infinity>() <= 1e-5 * fresh.tip);
  CHECK(std::abs(lagged.result.steps - fresh.result.steps) <= fresh.result.steps / 20 + 1);
  INFO("hessians " << lagged.hessians << " vs " << fresh.hessians << ", factorizations " << lagged.factorizations
                   << " vs " << fresh.factorizations);
  CHECK(fresh.factorizations >= fresh.result.newtonIterations);  // plain Newton: one per iteration
  CHECK(lagged.factorizations < fresh.factorizations);
  CHECK(lagged.hessians < fresh.hessians);
}

namespace {

/// testing::compressedPlate at twice its buckling load, relaxed from the flat rest state: the out-of-plane
/// coordinates stay at round-off size (1e-20 m here) unless something breaks the symmetry.
RelaxationResult relaxCompressedPlate(bool check, int escapes, Eigen::VectorXd& x) {
  ShellProblem problem = testing::compressedPlate(2.0 * 0.090);
  problem.material.density = 1e-3;  // fictitious mass: only the end state matters
  ShellSystem system(problem, AnalysisKind::DynamicRelaxation);
  RelaxationOptions o;
  o.timeStep = 0.05;
  o.massDamping = 20.0;
  o.maxSteps = 2000;
  o.checkStability = check;
  o.saddleEscapes = escapes;
  x = system.restPositions();
  return relaxToStatic(system, x, o);
}

double largestOutOfPlane(const Eigen::VectorXd& x) {
  double z = 0.0;
  for (Eigen::Index i = 2; i < x.size(); i += 3) z = std::max(z, std::abs(x[i]));
  return z;
}

}  // namespace

TEST_CASE("dynamic relaxation: a saddle reached from a symmetric start is checked and left downhill") {
  testing::SingleThread single;
  Eigen::VectorXd x;
  SECTION("no check: the plate relaxes to the flat saddle and stays flat") {
    const RelaxationResult r = relaxCompressedPlate(false, 3, x);
    INFO(r.message);
    REQUIRE(r.converged);
    CHECK(r.negativeEigenvalues == -1);
    CHECK(largestOutOfPlane(x) < 1e-12);
  }
  SECTION("the check finds the saddle, and the relaxation goes on from a step downhill to a buckled minimum") {
    const RelaxationResult r = relaxCompressedPlate(true, 3, x);
    INFO(r.message);
    REQUIRE(r.converged);
    CHECK(r.saddleEscapes >= 1);
    CHECK(r.negativeEigenvalues == 0);
    CHECK(largestOutOfPlane(x) > 0.1);  // of a 1 m plate at twice its buckling load
  }
  SECTION("with no escape allowed, the saddle is reported") {
    const RelaxationResult r = relaxCompressedPlate(true, 0, x);
    REQUIRE(r.converged);
    CHECK(r.negativeEigenvalues == 1);
    CHECK(r.message.find("unstable") != std::string::npos);
    CHECK(largestOutOfPlane(x) < 1e-12);
  }
}

TEST_CASE("dynamic relaxation: bad saddle options are refused by name") {
  ShellSystem system(testing::cantileverPlate(2, 1, 0.01), AnalysisKind::DynamicRelaxation);
  Eigen::VectorXd x = system.restPositions();
  RelaxationOptions o;
  o.massDamping = 1.0;
  o.saddleEscapes = -1;
  CHECK_THROWS_WITH(relaxToStatic(system, x, o), Catch::Contains("saddleEscapes"));
  o.saddleEscapes = 3;
  o.saddleStep = 0.0;
  CHECK_THROWS_WITH(relaxToStatic(system, x, o), Catch::Contains("saddleStep"));
}
