// Newton with each line search, and L-BFGS, solve the same cantilever: whole solves repeated (0.4 s in CI's
// Release build), which the sanitizer pass leaves out (scripts/test.sh, sanitizeExclude, says why), so a file of
// its own, which that pass does not build (CMakeLists.txt, JETSHELL_LONG_ONLY_TESTS).
// tests/solvers/newton_test.cpp holds the shorter Newton tests that cover the same code.
#include "solvers/lbfgs.h"
#include "solvers/newton.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

using namespace jetshell;

TEST_CASE("newton: every line search and the L-BFGS alternative reach the same equilibrium") {
  ShellSystem system(testing::cantileverPlate(6, 2, 0.01), AnalysisKind::Statics);
  Eigen::VectorXd reference = system.restPositions();
  NewtonSolver plain(system.objective(), NewtonOptions{});
  REQUIRE(plain.minimize(reference).converged());
  const double tip = (reference - system.restPositions()).lpNorm<Eigen::Infinity>();
  for (LineSearchType ls : {LineSearchType::None, LineSearchType::ResidualNorm, LineSearchType::StrongWolfe}) {
    NewtonOptions o;
    o.lineSearch = ls;
    o.maxIterations = 200;
    NewtonSolver newton(system.objective(), o);
    Eigen::VectorXd x = system.restPositions();
    const SolverSummary s = newton.minimize(x);
    INFO(toString(ls) << "\n" << s.fullReport());
    CHECK(s.converged());
    CHECK((x - reference).lpNorm<Eigen::Infinity>() < 1e-4 * tip);
  }
  // L-BFGS stalls on the ill-conditioned shell problem well above Newton's tolerance (measured: ~2e-5 of the
  // force scale on this plate), so it is asked for less.
  LbfgsOptions lo;
  lo.residualTolerance = 1e-4;
  Eigen::VectorXd x = system.restPositions();
  const SolverSummary s = minimizeLbfgs(system.objective(), x, lo);
  INFO(s.briefReport());
  CHECK(s.converged());
  CHECK((x - reference).lpNorm<Eigen::Infinity>() < 1e-2 * tip);
}
