#include "core/mesh.h"
#include "solvers/time_step_policy.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

using namespace jetshell;

namespace {

/// The in-plane hanging cloth (6 × 6 squares) released from rest: it swings down under gravity.
struct Run {
  Eigen::VectorXd x;
  DynamicsResult result;
};

Run run(TimeStepPolicy policy, TimeIntegrator integrator, double dt, int steps,
        const std::function<void(DynamicsOptions&)>& adjust = {}) {
  ShellSystem system(testing::hangingCloth(0.3, 0.3, 6, 6), AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.integrator = integrator;
  o.timeStep = dt;
  applyTimeStepPolicy(policy, o);
  if (adjust) adjust(o);
  DynamicsSolver solver(system, o);
  Run r;
  r.result = simulate(solver, steps * dt);
  r.x = solver.positions();
  return r;
}

}  // namespace

TEST_CASE("time-step policy: names parse, and a bad name is an input error", "[solvers]") {
  for (TimeStepPolicy p : {TimeStepPolicy::Page, TimeStepPolicy::Jetshell, TimeStepPolicy::Reference})
    CHECK(timeStepPolicyFromString(toString(p)) == p);
  CHECK_THROWS_AS(timeStepPolicyFromString("fast"), InputError);
}

TEST_CASE("time-step policy: the page preset moves on at its iteration cap and says so, never 'converged'", "[solvers]") {
  testing::SingleThread single;
  ShellSystem system(testing::hangingCloth(0.3, 0.3, 6, 6), AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.timeStep = 1.0 / 30.0;
  applyTimeStepPolicy(TimeStepPolicy::Page, o);
  CHECK(o.newton.maxIterations == 4);
  CHECK(o.acceptIterationCap);
  o.newton.maxIterations = 1;  // a cap that one iteration cannot meet at this tolerance
  o.newton.absoluteResidualTolerance = 1e-9;
  DynamicsSolver solver(system, o);
  const StepReport r = solver.step();
  REQUIRE(r.success);
  REQUIRE(r.solves.size() == 1);
  CHECK(r.movedOn == 1);
  CHECK(r.solves[0].reason == TerminationReason::IterationCap);
  CHECK_FALSE(r.solves[0].converged());
  CHECK(solver.positions().allFinite());
  const DynamicsResult more = simulate(solver, 2 * o.timeStep);
  CHECK(more.movedOn == 2);
  CHECK_THAT(more.message, Catch::Contains("moved on unconverged"));
}

TEST_CASE("time-step policy: the jetshell rule keeps the Newton error well below the time-discretization error "
          "with fewer iterations than a tight solve", "[solvers]") {
  testing::SingleThread single;
  const double dt = 1.0 / 60.0;
  const int steps = 12;
  for (TimeIntegrator integrator : {TimeIntegrator::BackwardEuler, TimeIntegrator::BDF2}) {
    INFO(toString(integrator));
    const Run tight = run(TimeStepPolicy::Reference, integrator, dt, steps);
    const Run tightHalf = run(TimeStepPolicy::Reference, integrator, dt / 2, 2 * steps);
    const Run fast = run(TimeStepPolicy::Jetshell, integrator, dt, steps);
    REQUIRE(tight.result.completed);
    REQUIRE(tightHalf.result.completed);
    REQUIRE(fast.result.completed);
    CHECK(fast.result.movedOn == 0);
    // The time-discretization error at dt is at least about the change from dt to dt/2.
    const double discretization = (tight.x - tightHalf.x).lpNorm<Eigen::Infinity>();
    const double newtonError = (fast.x - tight.x).lpNorm<Eigen::Infinity>();
    INFO("discretization " << discretization << " m, Newton error " << newtonError << " m");
    CHECK(newtonError <= 0.2 * discretization);
    CHECK(fast.result.newtonIterations < tight.result.newtonIterations);
  }
}

TEST_CASE("time-step policy: from the extrapolated trajectory, a free fall needs no Newton iteration after two steps",
          "[solvers]") {
  testing::SingleThread single;
  ShellSystem system(testing::freeCloth(), AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.timeStep = 0.02;
  applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
  DynamicsSolver solver(system, o);
  REQUIRE(solver.step().success);
  REQUIRE(solver.step().success);
  // Constant acceleration: the extrapolated start is the exact backward-Euler step.
  for (int i = 0; i < 3; ++i) {
    const StepReport r = solver.step();
    REQUIRE(r.success);
    CHECK(r.newtonIterations == 0);
    CHECK(r.solves.at(0).converged());
  }
  // Without the extrapolation the predictor x_n + Δt v_n is off by Δt² g: Newton has to iterate.
  DynamicsOptions plain = o;
  plain.extrapolatedStart = false;
  DynamicsSolver other(system, plain);
  other.step();
  other.step();
  CHECK(other.step().newtonIterations >= 1);
}

TEST_CASE("dynamics: the update tolerance is validated", "[solvers]") {
  ShellSystem system(testing::hangingCloth(0.3, 0.3, 2, 2), AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.updateTolerance = -1.0;
  CHECK_THROWS_AS(DynamicsSolver(system, o), InputError);
  o.updateTolerance = std::nan("");
  CHECK_THROWS_AS(DynamicsSolver(system, o), InputError);
}
