#include "solvers/dynamic_relaxation.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

using namespace jetshell;

namespace {

RelaxationResult relaxCantilever(bool reuseStepGradient, Eigen::VectorXd& x, double& freshResidual) {
  ShellProblem problem = testing::cantileverPlate(6, 2, 0.01);
  problem.material.density = 1e-3;  // fictitious mass: only the end state matters
  ShellSystem system(problem, AnalysisKind::DynamicRelaxation);
  RelaxationOptions o;
  o.timeStep = 0.05;
  o.massDamping = 20.0;
  o.reuseStepGradient = reuseStepGradient;
  x = system.restPositions();
  const RelaxationResult r = relaxToStatic(system, x, o);
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
