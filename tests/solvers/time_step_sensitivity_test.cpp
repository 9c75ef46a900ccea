#include "solvers/time_step_sensitivity.h"

#include "solvers/dynamics.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

namespace {

/// A cantilever plate (6 × 2 squares, clamped at x = 0) falling under gravity −z with an end load, mass
/// damping α_R = 2/s and stiffness damping β_R = 0.01 s: every transient term of the incremental potential.
ShellProblem dampedCantilever() {
  ShellProblem p = testing::cantileverPlate(6, 2, 0.02);
  p.hasGravity = true;
  p.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  p.material.massDampingCoefficient = 2.0;
  p.material.stiffnessDampingCoefficient = 0.01;
  return p;
}

/// The fitted quantities as scales q (1 = the problem's values) of groups of term parameters:
///   q0 density (inertia, gravity, and the mass-damping term whose masses scale with it), q1 α_R,
///   q2 β_R (both damping terms), q3 the bending moduli (elastic and damping terms), q4 the end load.
struct Group {
  TermParameter parameter;
  std::vector<int> scales;  // the product of these q's multiplies the base value
};

std::vector<Group> groups() {
  return {{{"inertia", "density"}, {0}},
          {{"gravity", "density"}, {0}},
          {{"mass_damping", "alpha_R"}, {0, 1}},
          {{"membrane_damping", "beta_R"}, {2}},
          {{"bending_damping", "beta_R"}, {2}},
          {{"bending", "alpha"}, {3}},
          {{"bending", "beta"}, {3}},
          {{"bending_damping", "alpha"}, {3}},
          {{"bending_damping", "beta"}, {3}},
          {{"nodal_forces", "scale"}, {4}}};
}

/// `steps` time steps with the sensitivities carried along (the solver's observer advances them per solve).
void advance(DynamicsSolver& solver, TimeStepSensitivity& sensitivity, int steps) {
  for (int k = 0; k < steps; ++k) {
    sensitivity.beginStep();
    REQUIRE(solver.step().success);
    sensitivity.endStep();
  }
}

struct SensitivityRun {
  Eigen::VectorXd x;
  Eigen::MatrixXd S;
  int inexact = 0;
};

SensitivityRun run(const Eigen::VectorXd& q, TimeIntegrator integrator, int steps, bool sensitivities) {
  ShellSystem system(dampedCantilever(), AnalysisKind::Dynamics);
  const std::vector<Group> g = groups();
  std::vector<TermParameter> parameters;
  Eigen::MatrixXd dvdq = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(g.size()), q.size());
  for (std::size_t t = 0; t < g.size(); ++t) {
    const double base = termParameterValue(system.objective(), g[t].parameter);
    double value = base;
    for (int k : g[t].scales) value *= q[k];
    for (int k : g[t].scales) dvdq(static_cast<Eigen::Index>(t), k) = value / q[k];
    setTermParameterValue(system.objective(), g[t].parameter, value);
    parameters.push_back(g[t].parameter);
  }
  DynamicsOptions o;
  o.integrator = integrator;
  o.timeStep = 0.01;
  o.updateTolerance = 0.0;  // Newton to its residual tolerance: the trajectory is then a smooth function of q
  o.newton.residualTolerance = 1e-13;
  DynamicsSolver solver(system, o);
  TimeStepSensitivity sensitivity(system);
  sensitivity.reset(parameters, dvdq);
  if (sensitivities)
    solver.setSubstepObserver([&](const SubstepView& v) { REQUIRE(sensitivity.advance(v)); });
  advance(solver, sensitivity, steps);
  return {solver.positions(), sensitivity.positions(), sensitivity.inexactSolves()};
}

void checkAgainstDifferences(TimeIntegrator integrator) {
  testing::SingleThread single;
  const int Q = 5, steps = 6;
  const Eigen::VectorXd q = Eigen::VectorXd::Ones(Q);
  const SensitivityRun base = run(q, integrator, steps, true);
  CHECK(base.inexact == 0);
  const double moved = (base.x - ShellSystem(dampedCantilever(), AnalysisKind::Dynamics).restPositions()).norm();
  REQUIRE(moved > 1e-3);  // the plate has moved: the test is not trivially passed at rest
  for (int k = 0; k < Q; ++k) {
    const double h = 1e-4;
    Eigen::VectorXd qp = q, qm = q;
    qp[k] += h;
    qm[k] -= h;
    const Eigen::VectorXd fd = (run(qp, integrator, steps, false).x - run(qm, integrator, steps, false).x) / (2.0 * h);
    INFO("parameter " << k << ": |dx/dq| = " << fd.norm());
    REQUIRE(fd.norm() > 1e-8);
    CHECK((base.S.col(k) - fd).norm() <= 1e-6 * fd.norm());
  }
}

}  // namespace

TEST_CASE("time-step sensitivities: dx/dq through backward Euler steps matches differences of whole runs",
          "[sensitivity][dynamics]") {
  checkAgainstDifferences(TimeIntegrator::BackwardEuler);
}

TEST_CASE("time-step sensitivities: dx/dq through BDF2 steps (and its backward Euler start) matches differences "
          "of whole runs", "[sensitivity][dynamics]") {
  checkAgainstDifferences(TimeIntegrator::BDF2);
}

TEST_CASE("time-step sensitivities: solves accepted at the iteration cap are counted as inexact",
          "[sensitivity][dynamics]") {
  testing::SingleThread single;
  ShellSystem system(dampedCantilever(), AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.timeStep = 0.01;
  o.updateTolerance = 0.0;
  o.newton.maxIterations = 1;
  o.newton.residualTolerance = 1e-13;
  o.acceptIterationCap = true;
  DynamicsSolver solver(system, o);
  TimeStepSensitivity sensitivity(system);
  sensitivity.reset({{"inertia", "density"}}, Eigen::MatrixXd::Ones(1, 1));
  solver.setSubstepObserver([&](const SubstepView& v) { REQUIRE(sensitivity.advance(v)); });
  advance(solver, sensitivity, 2);
  CHECK(sensitivity.inexactSolves() == 2);
}

TEST_CASE("time-step sensitivities: solves ended by the time-discretization rule are counted as inexact",
          "[sensitivity][dynamics]") {
  testing::SingleThread single;
  ShellSystem system(dampedCantilever(), AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.timeStep = 0.01;
  o.updateTolerance = 0.5;  // a loose rule: Newton stops long before the residual tolerance
  o.newton.residualTolerance = 1e-13;
  DynamicsSolver solver(system, o);
  TimeStepSensitivity sensitivity(system);
  sensitivity.reset({{"inertia", "density"}}, Eigen::MatrixXd::Ones(1, 1));
  int ruleStops = 0;
  solver.setSubstepObserver([&](const SubstepView& v) {
    if (v.solve->convergenceTest == "iterate") ++ruleStops;
    REQUIRE(sensitivity.advance(v));
  });
  advance(solver, sensitivity, 3);
  REQUIRE(ruleStops > 0);
  CHECK(sensitivity.inexactSolves() == ruleStops);
}

TEST_CASE("time-step sensitivities: a static system is refused", "[sensitivity][dynamics]") {
  ShellSystem system(dampedCantilever(), AnalysisKind::Statics);
  CHECK_THROWS_WITH(TimeStepSensitivity(system), Catch::Contains("not built for dynamics"));
}
