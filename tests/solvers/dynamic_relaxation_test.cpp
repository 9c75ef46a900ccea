#include "solvers/dynamic_relaxation.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

using namespace jetshell;

namespace {

struct Counts {
  int hessians = 0, factorizations = 0;
};

RelaxationResult relaxCantilever(bool reuseStepGradient, Eigen::VectorXd& x, double& freshResidual,
                                 bool reuseFactor = true, Counts* counts = nullptr) {
  ShellProblem problem = testing::cantileverPlate(6, 2, 0.01);
  problem.material.density = 1e-3;  // fictitious mass: only the end state matters
  ShellSystem system(problem, AnalysisKind::DynamicRelaxation);
  RelaxationOptions o;
  o.timeStep = 0.05;
  o.massDamping = 20.0;
  o.reuseStepGradient = reuseStepGradient;
  o.reuseFactor = reuseFactor;
  x = system.restPositions();
  const RelaxationResult r = relaxToStatic(system, x, o, [counts](const StepReport& step, double) {
    for (const SolverSummary& s : step.solves)
      if (counts != nullptr) {
        counts->hessians += s.hessianEvaluations;
        counts->factorizations += s.numericFactorizations;
      }
    return true;
  });
  Eigen::VectorXd g;
  system.objective().evaluate(x, &g, false, EvalOptions{}, TermSelection::PotentialOnly);
  freshResidual = g.lpNorm<Eigen::Infinity>();
  return r;
}

}  // namespace

TEST_CASE("dynamic relaxation: each step's static residual read from its solve's last gradient is the one "
          "evaluated afresh, and the relaxation ends in the same state",
          "[relaxation]") {
  testing::SingleThread single;
  Eigen::VectorXd reused, evaluated;
  double reusedFresh = 0.0, evaluatedFresh = 0.0;
  const RelaxationResult a = relaxCantilever(true, reused, reusedFresh);
  const RelaxationResult b = relaxCantilever(false, evaluated, evaluatedFresh);
  INFO(a.message << " | " << b.message);
  REQUIRE(a.converged);
  REQUIRE(b.converged);
  CHECK(a.steps > 10);
  CHECK(a.reusedGradients == a.steps);  // every step's residual came from its own solve
  CHECK(b.reusedGradients == 0);
  CHECK(a.steps == b.steps);
  CHECK(a.newtonIterations == b.newtonIterations);
  // The residual that stopped the run is the potential terms' gradient at the final state (to rounding).
  CHECK(std::abs(a.staticResidual - reusedFresh) <= 1e-9 * a.residualThreshold);
  CHECK(std::abs(b.staticResidual - evaluatedFresh) <= 1e-9 * b.residualThreshold);
  const double tip = (evaluated - ShellSystem(testing::cantileverPlate(6, 2, 0.01), AnalysisKind::Statics)
                                      .restPositions())
                         .lpNorm<Eigen::Infinity>();
  CHECK((reused - evaluated).lpNorm<Eigen::Infinity>() <= 1e-12 * tip);
}

TEST_CASE("dynamic relaxation: reusing an earlier step's factor reaches the state fresh factors reach, with fewer "
          "Hessians and factorizations",
          "[relaxation]") {
  testing::SingleThread single;
  Eigen::VectorXd lagged, fresh;
  double laggedResidual = 0.0, freshResidual = 0.0;
  Counts l, f;
  const RelaxationResult a = relaxCantilever(true, lagged, laggedResidual, true, &l);
  const RelaxationResult b = relaxCantilever(true, fresh, freshResidual, false, &f);
  INFO(a.message << " | " << b.message);
  REQUIRE(a.converged);
  REQUIRE(b.converged);
  // Each step is held to the same tests, so both end in equilibrium to the same tolerance.
  CHECK(laggedResidual <= a.residualThreshold);
  CHECK(freshResidual <= b.residualThreshold);
  const double tip = (fresh - ShellSystem(testing::cantileverPlate(6, 2, 0.01), AnalysisKind::Statics)
                                  .restPositions())
                         .lpNorm<Eigen::Infinity>();
  CHECK((lagged - fresh).lpNorm<Eigen::Infinity>() <= 1e-5 * tip);
  CHECK(std::abs(a.steps - b.steps) <= b.steps / 20 + 1);
  INFO("hessians " << l.hessians << " vs " << f.hessians << ", factorizations " << l.factorizations << " vs "
                   << f.factorizations);
  CHECK(f.factorizations >= b.newtonIterations);  // plain Newton: one per iteration
  CHECK(l.factorizations < f.factorizations);
  CHECK(l.hessians < f.hessians);
}
