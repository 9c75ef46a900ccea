// Exact-first Newton near a solution: the whole Hessian, nothing projected (NewtonOptions::unprojectedNearSolution),
// and the memory that stops trying it where it keeps being indefinite.
#include "solvers/dynamics.h"
#include "solvers/time_step_policy.h"
#include "test_problems.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstring>
#include <sstream>
#include <vector>

using namespace jetshell;

namespace {

struct UnprojectedRun {
  int iterations = 0, unprojectedSteps = 0, unprojectedFallbacks = 0, tries = 0;
  int reportedSteps = 0, reportedFallbacks = 0;  // as each solve's JSON summary gives them
  std::vector<const char*> solves;  // per solve: "-" no try, "held" tries all held, "fell" one fell back
};

UnprojectedRun runSteps(const ShellProblem& p, double eta, int steps, bool unprojected, int fromIteration = 2) {
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsOptions o;
  applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
  o.timeStep = 1.0 / 60.0;
  o.updateTolerance = eta;
  o.newton.unprojectedNearSolution = unprojected;
  o.newton.unprojectedFromIteration = fromIteration;
  DynamicsSolver solver(system, o);
  UnprojectedRun r;
  for (int k = 0; k < steps; ++k) {
    const StepReport s = solver.step();
    INFO("step " << k << ": " << s.message);
    REQUIRE(s.success);
    r.iterations += s.newtonIterations;
    for (const SolverSummary& m : s.solves) {
      r.unprojectedSteps += m.unprojectedSteps;
      r.unprojectedFallbacks += m.unprojectedFallbacks;
      const nlohmann::json j = toJson(m);
      r.reportedSteps += j.at("unprojected_steps").get<int>();
      r.reportedFallbacks += j.at("unprojected_fallbacks").get<int>();
      if (m.unprojectedSteps + m.unprojectedFallbacks > 0) ++r.tries;
      r.solves.push_back(m.unprojectedFallbacks > 0 ? "fell" : m.unprojectedSteps > 0 ? "held" : "-");
    }
  }
  return r;
}

}  // namespace

TEST_CASE("newton: exact-first takes the unprojected Hessian near a solution, so a stiff sheet's tightly solved "
          "steps take fewer iterations than with the small blocks still projected") {
  testing::SingleThread single;
  // A 1 m sheet (E 1e10 Pa, ν 0.25, 1000 kg/m³, 2 mm) on 12 × 12 squares hanging from two corners: its membrane
  // blocks are projected by exact-first, which leaves Newton a linear rate near the solution.
  const ShellProblem p = testing::hangingSheet(12, ShellMaterialParamsFrom3dIsotropic(1e10, 0.25, 1000.0, 0.002));
  const UnprojectedRun on = runSteps(p, 1e-8, 20, true), off = runSteps(p, 1e-8, 20, false);
  INFO("Newton iterations over 20 steps: " << on.iterations << " unprojected near the solution ("
       << on.unprojectedSteps << " steps, " << on.unprojectedFallbacks << " fallbacks), " << off.iterations
       << " with the small blocks projected");
  CHECK(off.unprojectedSteps + off.unprojectedFallbacks == 0);
  CHECK(on.unprojectedSteps > 0);
  CHECK(on.iterations < off.iterations);
  CHECK(on.reportedSteps == on.unprojectedSteps);
  CHECK(on.reportedFallbacks == on.unprojectedFallbacks);
}

TEST_CASE("newton: where the unprojected Hessian keeps being indefinite, exact-first stops trying it for "
          "longer and longer") {
  testing::SingleThread single;
  // A light cloth hanging in its own plane from two corners wrinkles: compressed membrane blocks leave the whole
  // Hessian indefinite near most solutions.
  const ShellProblem p = testing::hangingCloth(1.0, 1.0, 16, 16);
  // Tried from the first iteration on (not the default's third), where this cloth's solves mostly end.
  const UnprojectedRun r = runSteps(p, 0.01, 60, true, 0);
  INFO("60 steps: " << r.tries << " solves tried the unprojected Hessian, " << r.unprojectedFallbacks
       << " fell back, " << r.unprojectedSteps << " unprojected steps held");
  std::ostringstream sequence;
  for (const char* c : r.solves) sequence << c << " ";
  INFO("solves: " << sequence.str());
  CHECK(r.unprojectedFallbacks > 0);  // the case the memory is for
  CHECK(r.reportedFallbacks == r.unprojectedFallbacks);
  // A solve that falls back tries no more, and the next 2^f solves try none (f: the failures remembered, one more
  // with each solve that falls back, one fewer with each whose tries held): two fallbacks with no held solve
  // between are 2, then 4, 8, ... solves apart at least.
  int failures = 0, wait = 0;
  for (std::size_t i = 0; i < r.solves.size(); ++i) {
    const bool tried = std::strcmp(r.solves[i], "-") != 0;
    INFO("solve " << i);
    if (wait > 0) {
      CHECK_FALSE(tried);
      --wait;
      continue;
    }
    if (std::strcmp(r.solves[i], "fell") == 0) {
      failures = std::min(failures + 1, 6);
      wait = 1 << failures;
    } else if (std::strcmp(r.solves[i], "held") == 0 && failures > 0) {
      --failures;
    }
  }
}
