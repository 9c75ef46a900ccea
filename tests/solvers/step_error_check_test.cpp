// The per-step error check (solvers/step_error_check.h): its norm, and that it measures the step taken.
#include "core/mesh_generators.h"
#include "solvers/step_error_check.h"
#include "solvers/time_step_policy.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace jetshell;

TEST_CASE("step error check: the mass-weighted RMS weighs each vertex's length by its mass") {
  Eigen::VectorXd mass(2), u(6);
  mass << 1.0, 3.0;
  u << 3.0, 4.0, 0.0, 0.0, 0.0, 1.0;  // lengths 5 and 1
  CHECK(massWeightedRms(mass, u) == Approx(std::sqrt((25.0 + 3.0) / 4.0)).epsilon(1e-15));
  CHECK(massWeightedRms(Eigen::VectorXd::Zero(2), u) == 0.0);
}

TEST_CASE("step error check: a step solved again with the same settings is at zero distance, a looser one is "
          "not, the distance is the one between the two ends, and a tight solve that did not converge checks "
          "nothing") {
  const ShellProblem p = testing::hangingSheet(6, ShellMaterialParamsFrom3dIsotropic(1e7, 0.3, 1000.0, 0.001));
  ShellSystem runSystem(p, AnalysisKind::Dynamics), sameSystem(p, AnalysisKind::Dynamics),
      tightSystem(p, AnalysisKind::Dynamics);
  DynamicsOptions o;
  applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
  o.timeStep = 1.0 / 60.0;
  o.updateTolerance = 0.1;
  DynamicsSolver run(runSystem, o), same(sameSystem, o);
  o.updateTolerance = 1e-8;
  DynamicsSolver tight(tightSystem, o);
  double largest = 0.0;
  for (int step = 0; step < 5; ++step) {
    const DynamicsSolver::Snapshot start = run.snapshot();
    const StepReport taken = run.step();
    REQUIRE(taken.success);
    const StepErrorCheck a = checkStepError(taken, run, same, start);
    REQUIRE(a.checked);
    REQUIRE(a.solvedAgain);
    INFO("step " << step << ": " << taken.solves.front().iterateEstimate);
    CHECK(a.tight.newtonIterations == 0);  // the same test passes the same iterate at once
    CHECK(a.error == 0.0);
    CHECK(a.change > 0.0);  // the sheet falls
    const StepErrorCheck b = checkStepError(taken, run, tight, start);
    REQUIRE(b.checked);
    CHECK(b.error == Approx(massWeightedRms(runSystem.vertexMass(), run.positions() - tight.positions())));
    largest = std::max(largest, b.error);
  }
  CHECK(largest > 0.0);  // η = 0.1 stops short of the η = 1e-8 solution somewhere
  // A "tight" solve that moves on at its iteration cap is no reference: the step is solved again, not checked.
  ShellSystem cappedSystem(p, AnalysisKind::Dynamics);
  o.newton.maxIterations = 1;
  o.acceptIterationCap = true;
  DynamicsSolver capped(cappedSystem, o);
  const DynamicsSolver::Snapshot start = run.snapshot();
  const StepReport taken = run.step();
  REQUIRE(taken.success);
  const StepErrorCheck d = checkStepError(taken, run, capped, start);
  REQUIRE(d.solvedAgain);
  CHECK(d.tight.movedOn > 0);
  CHECK_FALSE(d.checked);
  StepReport cut;
  cut.success = true;
  cut.cuts = 1;
  cut.substeps = 2;
  const StepErrorCheck c = checkStepError(cut, run, tight, run.snapshot());
  CHECK_FALSE(c.checked);
  CHECK_FALSE(c.solvedAgain);
}

TEST_CASE("step error check: contact steps solved again with the same settings on from their iterate pass it at "
          "once where the residual estimate passed it, and end within the threshold where the correction did") {
  // A 0.3 m cloth (6 × 6 cells, the T-shirt's material) 2 mm above a plane, friction 0.2, gravity tilted by
  // 0.3 rad: the contact is active from the first step and the cloth slides (tan 0.3 > 0.2), so the contact and
  // friction terms of each step depend on the state the step starts from, which restore() must bring back whole.
  ShellProblem p;
  p.mesh = makeRectangleGrid(0.3, 0.3, 6, 6);
  Positions V(p.mesh.V.rows(), 3);
  for (Eigen::Index v = 0; v < V.rows(); ++v) V.row(v) << p.mesh.V(v, 0), 0.002, -p.mesh.V(v, 1);
  p.mesh.V = V;
  p.material = ShellMaterialParamsFrom3dIsotropic(1e5, 0.25, 1000.0, 0.002);
  p.gravity = 9.81 * Eigen::Vector3d(std::sin(0.3), -std::cos(0.3), 0.0);
  RigidPath path;
  path.rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
  ContactParams c;
  c.frictionCoefficient = 0.2;
  p.volumes = {{std::make_shared<VolumeCollider>("incline", makePlaneShape(), path), c}};
  ShellSystem runSystem(p, AnalysisKind::Dynamics), sameSystem(p, AnalysisKind::Dynamics);
  REQUIRE_FALSE(runSystem.contact.termNames().empty());
  DynamicsOptions o;
  applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
  o.timeStep = 1.0 / 60.0;
  DynamicsSolver run(runSystem, o), same(sameSystem, o);
  int checked = 0, residualPasses = 0;
  for (int step = 0; step < 6; ++step) {
    const DynamicsSolver::Snapshot start = run.snapshot();
    const StepReport taken = run.step();
    REQUIRE(taken.success);
    const StepErrorCheck a = checkStepError(taken, run, same, start);
    if (!a.checked) continue;  // a cut step: nothing to compare
    ++checked;
    const SolverSummary& s = taken.solves.front();
    INFO("step " << step << ", " << s.convergenceTest << " " << s.iterateEstimate << ": error " << a.error
                 << " m, threshold " << s.iterateThreshold << " m");
    if (s.iterateEstimate == "residual estimate") {
      // The same test on the same iterate, against the same threshold, passes it at once.
      ++residualPasses;
      CHECK(a.tight.newtonIterations == 0);
      CHECK(a.error == 0.0);
    } else {
      // Passed by the Newton correction: started on the iterate, the same settings have no correction to judge
      // yet, and go on (or pass by a residual estimate no contraction refuses yet) to end within the threshold.
      REQUIRE(s.converged());
      CHECK(a.error <= s.iterateThreshold);
    }
    CHECK(a.change > 0.0);
  }
  CHECK(checked > 0);
  CHECK(residualPasses > 0);  // measured: 2 of 5
}

TEST_CASE("step error check: a part of a cut step is solved again from its own start over its own time step") {
  // A light hanging cloth (E 1e5 Pa, 1 mm, 300 kg/m³) at 0.2 s steps and 3 Newton iterations a solve: 4 of 10
  // steps are cut. Each part the run accepts is solved again by a tight solver from the part's start, over the
  // part's Δt, on from the part's iterate; the first step's whole solve, seen the same way by a solver with the
  // run's settings, ends bit for bit where the run did (neither had any history).
  testing::SingleThread single;
  ShellProblem p = testing::hangingCloth(1.0, 1.0, 8, 8);
  p.material = ShellMaterialParamsFrom3dIsotropic(1e5, 0.3, 300.0, 0.001);
  ShellSystem runSystem(p, AnalysisKind::Dynamics), sameSystem(p, AnalysisKind::Dynamics),
      tightSystem(p, AnalysisKind::Dynamics);
  DynamicsOptions o;
  applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
  o.timeStep = 0.2;
  o.newton.maxIterations = 3;
  DynamicsSolver run(runSystem, o), same(sameSystem, o), tight(tightSystem, tightStepOptions(o));
  int wholeChecked = 0, partsChecked = 0, partPasses = 0, withinThreshold = 0;
  run.setSubstepObserver([&](const SubstepView& part) {
    if (part.timeStep == o.timeStep) {
      if (run.stepCount() > 0) return;
      const StepErrorCheck a = checkPartError(part, same);
      REQUIRE(a.checked);
      CHECK(a.error == 0.0);
      CHECK(a.change > 0.0);
      ++wholeChecked;
      return;
    }
    CHECK(part.time >= run.time());
    const StepErrorCheck t = checkPartError(part, tight);
    CHECK(tight.options().timeStep == o.timeStep);  // set back after the part
    if (!t.checked) return;
    ++partsChecked;
    if (part.solve->converged() && part.solve->convergenceTest == "iterate") {
      ++partPasses;
      if (t.error <= part.solve->iterateThreshold) ++withinThreshold;
    }
  });
  int cutSteps = 0;
  for (int step = 0; step < 10; ++step) {
    run.forgetSolverHistory();
    const StepReport r = run.step();
    REQUIRE(r.success);
    if (takenInParts(r)) ++cutSteps;
  }
  CHECK(wholeChecked == 1);
  CHECK(cutSteps >= 3);
  CHECK(partsChecked >= 10);
  // A part checked from another state, time or Δt would end far beyond its threshold. Measured: 25 of 27 passes
  // within it in a native build, 24 of 28 in the sanitizer build (its rounding takes other iterates); the others
  // are residual-estimate passes of 0.025 s parts, at 1.5 and 2.8 times in the native build (the estimate needs
  // the step's Hessian to be at least its inertia, and the cloth's compression takes some of that away:
  // BENCHMARKS.md, session 68).
  CHECK(partPasses >= 10);
  INFO(withinThreshold << " of " << partPasses << " passes of parts within their threshold");
  CHECK(4 * withinThreshold >= 3 * partPasses);
  // A BDF2 solve is no part of a step (the halves are backward Euler): not solved again.
  SubstepView bdf2;
  bdf2.bdf2 = true;
  const StepErrorCheck none = checkPartError(bdf2, tight);
  CHECK_FALSE(none.solvedAgain);
  CHECK_FALSE(none.checked);
  // What the check sets on the tight solver is checked at that boundary.
  CHECK_THROWS_WITH(tight.setTimeStep(std::nan("")), Catch::Contains("timeStep = nan: must be finite and > 0"));
  CHECK_THROWS_WITH(tight.setTimeStep(0.0), Catch::Contains("must be finite and > 0"));
  CHECK_THROWS_WITH(tight.startNextSolveFrom(Eigen::VectorXd::Zero(3)), Catch::Contains("finite coordinates"));
  Eigen::VectorXd bad = tight.positions();
  bad[0] = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(tight.startNextSolveFrom(bad), Catch::Contains("finite coordinates"));
  CHECK(tight.options().timeStep == o.timeStep);
}
