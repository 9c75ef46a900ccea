#include "core/mesh.h"
#include "solvers/dynamics.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

using namespace jetshell;

TEST_CASE("dynamics: a step count beyond the limit is refused before the first step", "[dynamics][hostile]") {
  // duration / timeStep = 1e300 used to be cast to an int (0 steps, "completed").
  ShellProblem problem = testing::hangingCloth(0.3, 0.3, 2, 2);
  ShellSystem system(problem, AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.timeStep = 1e-300;
  DynamicsSolver solver(system, o);
  CHECK_THROWS_WITH(simulate(solver, 1.0),
                    "dynamics: duration / timeStep gives 1e+300 steps, too many (at most 10000000)");
  CHECK(solver.time() == 0.0);
}
