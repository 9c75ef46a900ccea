#include "solvers/dynamics.h"
#include "solvers/newton.h"
#include "test_problems.h"
#include "wells_term.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>

using namespace jetshell;

namespace {

/// Solves the cantilever with the default (clamped-projection) Newton and returns the solution.
Eigen::VectorXd solvedCantilever(ShellSystem& system) {
  NewtonSolver newton(system.objective(), NewtonOptions{});
  Eigen::VectorXd x = system.restPositions();
  const SolverSummary s = newton.minimize(x);
  INFO(s.fullReport());
  REQUIRE(s.converged());
  return x;
}

}  // namespace

TEST_CASE("newton: converges quadratically near a solution") {
  ShellSystem system(testing::cantileverPlate(8, 3, 0.02), AnalysisKind::Statics);
  const Eigen::VectorXd solution = solvedCantilever(system);
  const double tip = (solution - system.restPositions()).lpNorm<Eigen::Infinity>();
  // Start from the equilibrium under 99.5% of the load: near the solution, along the physical path.
  Eigen::VectorXd x = system.restPositions();
  system.nodalForces->setLoadFactor(0.995);
  {
    NewtonSolver warm(system.objective(), NewtonOptions{});
    REQUIRE(warm.minimize(x).converged());
  }
  system.nodalForces->setLoadFactor(1.0);
  NewtonOptions o;
  o.projection = PsdProjection::None;  // the exact Hessian: a projection would cost the quadratic rate
  o.residualTolerance = 1e-9;
  o.decrementTolerance = 0.0;
  NewtonSolver newton(system.objective(), o);
  const SolverSummary s = newton.minimize(x);
  INFO(s.fullReport());
  REQUIRE(s.converged());
  CHECK(s.iterations <= 4);
  // The Newton decrement λ = √(gᵀH⁻¹g) is the affine-invariant error measure: each step squares it (up to a
  // constant), so the observed order log(λ_{k+1}/λ_k) / log(λ_k/λ_{k−1}) is about 2 or more. (The residual's
  // ∞-norm is no good measure here: the stiff membrane dofs make it jump.)
  std::vector<double> lambda;
  for (const IterationRecord& it : s.trace) lambda.push_back(std::sqrt(2.0 * it.decrement));
  REQUIRE(lambda.size() >= 3);
  for (std::size_t k = 1; k + 1 < lambda.size(); ++k) {
    const double order = std::log(lambda[k + 1] / lambda[k]) / std::log(lambda[k] / lambda[k - 1]);
    CHECK(order > 1.8);
  }
  CHECK((x - solution).lpNorm<Eigen::Infinity>() < 1e-8 * tip);
}

TEST_CASE("newton: the symbolic analysis runs once per pattern") {
  ShellSystem system(testing::cantileverPlate(6, 2, 0.01), AnalysisKind::Statics);
  NewtonSolver newton(system.objective(), NewtonOptions{});
  Eigen::VectorXd x = system.restPositions();
  const SolverSummary first = newton.minimize(x);
  REQUIRE(first.converged());
  REQUIRE(first.iterations > 1);
  CHECK(first.symbolicAnalyses == 1);
  system.nodalForces->setLoadFactor(1.5);
  const SolverSummary second = newton.minimize(x);
  REQUIRE(second.converged());
  CHECK(second.symbolicAnalyses == 0);
  CHECK(newton.linearSolver().symbolicAnalyses() == 1);
}

TEST_CASE("newton: a non-finite start ends with the non-finite reason and leaves x untouched") {
  ShellSystem system(testing::cantileverPlate(4, 2, 0.01), AnalysisKind::Statics);
  NewtonSolver newton(system.objective(), NewtonOptions{});
  Eigen::VectorXd x = system.restPositions();
  x[5] = std::nan("");
  const Eigen::VectorXd before = x;
  const SolverSummary s = newton.minimize(x);
  CHECK(s.reason == TerminationReason::NonFinite);
  CHECK(s.iterations == 0);
  CHECK(std::isnan(x[5]));
  x[5] = 0.0;
  CHECK((x.head(5) - before.head(5)).norm() == 0.0);
}

TEST_CASE("newton: inexact Newton (Eisenstat-Walker CG tolerances) converges to the same equilibrium with fewer "
          "CG iterations") {
  ShellSystem system(testing::cantileverPlate(6, 2, 0.01), AnalysisKind::Statics);
  const Eigen::VectorXd reference = solvedCantilever(system);
  const double tip = (reference - system.restPositions()).lpNorm<Eigen::Infinity>();
  int cgIterations[2] = {0, 0};
  for (bool adaptive : {false, true}) {
    NewtonOptions o;
    o.maxIterations = 200;
    o.linear.type = LinearSolverType::PCG;
    o.linear.preconditioner = Preconditioner::BlockJacobi;
    o.linear.cgRelativeTolerance = 1e-10;
    o.adaptiveLinearTolerance = adaptive;
    NewtonSolver newton(system.objective(), o);
    Eigen::VectorXd x = system.restPositions();
    const SolverSummary s = newton.minimize(x);
    INFO((adaptive ? "adaptive\n" : "fixed\n") << s.fullReport());
    REQUIRE(s.converged());
    CHECK(s.finalResidual <= s.residualThreshold);  // judged on the true gradient, not on CG's residual
    CHECK((x - reference).lpNorm<Eigen::Infinity>() < 1e-4 * tip);
    CHECK(newton.linearSolver().relativeTolerance() == o.linear.cgRelativeTolerance);  // restored after the solve
    for (const IterationRecord& rec : s.trace) cgIterations[adaptive ? 1 : 0] += rec.cgIterations;
  }
  CHECK(cgIterations[1] < cgIterations[0]);
}

TEST_CASE("newton: exact-Hessian-first time steps leave wide blocks unprojected and reach the same state") {
  testing::SingleThread single;
  // Twenty 60 Hz steps of a hanging cloth falling and swinging, with every block projected and with only the
  // small (membrane, 9-dof) blocks projected first.
  Eigen::VectorXd positions[2];
  int exactSteps[2] = {0, 0}, iterations[2] = {0, 0};
  double sag = 0.0;
  for (int first = 0; first < 2; ++first) {
    ShellSystem system(testing::hangingCloth(0.3, 0.3, 6, 6), AnalysisKind::Dynamics);
    DynamicsOptions o;
    o.timeStep = 1.0 / 60.0;
    o.updateTolerance = 0.0;  // Newton's own residual test, so the two runs solve the same equations tightly
    o.newton.residualTolerance = 1e-8;
    o.newton.exactHessianFirst = first == 1;
    DynamicsSolver solver(system, o);
    for (int s = 0; s < 20; ++s) {
      const StepReport r = solver.step();
      REQUIRE(r.success);
      for (const SolverSummary& solve : r.solves) exactSteps[first] += solve.exactHessianSteps;
      iterations[first] += r.newtonIterations;
    }
    positions[first] = solver.positions();
    if (first == 0) sag = (solver.positions() - system.restPositions()).lpNorm<Eigen::Infinity>();
  }
  INFO("Newton iterations: all projected " << iterations[0] << ", exact first " << iterations[1]
                                           << "; unprojected steps " << exactSteps[1]);
  CHECK(exactSteps[1] >= iterations[1] / 2);  // inertia keeps most of these Hessians positive definite
  REQUIRE(sag > 1e-4);
  // Both solve every step to the same tolerance; the hanging cloth buckles (a bifurcation that amplifies
  // tolerance-level differences), so they agree to 0.1% of the motion, not to the tolerance itself.
  CHECK((positions[1] - positions[0]).lpNorm<Eigen::Infinity>() < 1e-3 * sag);
}

TEST_CASE("newton: exact-Hessian-first falls back to the projected Hessian where the system is indefinite") {
  // Starting inside the wells' concave part the unprojected Hessian is indefinite: those iterations are redone
  // projected, and the solve still reaches a minimum (every coordinate at ±1).
  constexpr int n = 4;
  Objective objective(n);
  // A double well per coordinate, E = Σ (x_i² − 1)² / 4: its Hessian 3x_i² − 1 is negative for |x_i| < 1/√3.
  objective.addTerm(std::make_shared<testing::WellsTerm>(n, std::array<double, 3>{1.0, 1.0, 1.0}));
  PhysicalScales scales;
  scales.force = 1.0;
  objective.setScales(scales);
  NewtonOptions o;
  o.exactHessianFirst = true;
  o.exactFirstProjectedDofs = 0;  // nothing projected first: the whole Hessian as it is
  NewtonSolver newton(objective, o);
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(3 * n, 0.05, 0.4);
  const SolverSummary s = newton.minimize(x);
  INFO(s.fullReport());
  REQUIRE(s.converged());
  CHECK(s.projectionFallbacks > 0);
  CHECK(s.exactHessianSteps > 0);  // once the iterates leave the concave part, the exact Hessian is used
  CHECK((x.cwiseAbs().array() - 1.0).abs().maxCoeff() < 1e-6);
}

TEST_CASE("objective: a projection limited to small blocks projects the membrane's 9-dof blocks and leaves the "
          "bending's 18-dof blocks as they are") {
  ShellSystem system(testing::cantileverPlate(6, 2, 0.01), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  for (int v = 0; v < system.mesh().numVertices(); ++v) {
    x[3 * v] *= 0.9;  // compressed, so membrane blocks are indefinite
    x[3 * v + 2] += 0.05 * std::sin(4.0 * system.mesh().V(v, 0)) * system.mesh().V(v, 1);
  }
  // A fresh objective of the two elastic terms, as a user builds one (no prescribed dofs, no contact).
  Objective obj(system.mesh().numVertices());
  obj.addTerm(system.membrane);
  obj.addTerm(system.bending);
  auto dense = [&](const EvalOptions& o) {
    Eigen::VectorXd g;
    obj.evaluate(x, &g, true, o);
    const Eigen::MatrixXd U(obj.assembler().matrix());
    Eigen::MatrixXd full = U + U.transpose();
    full.diagonal() -= U.diagonal();
    return full;
  };
  EvalOptions none, all, small;
  all.projection = small.projection = PsdProjection::Clamp;
  small.projectionMaxBlockDofs = 12;
  const Eigen::MatrixXd H = dense(none), Hall = dense(all), Hsmall = dense(small);
  // The membrane alone, projected and not: the only difference the limited projection may make.
  auto membraneOnly = [&](const EvalOptions& o) {
    HessianAssembler a;
    const int slot = a.addStencils(system.membrane->stencils());
    a.finalize(system.mesh().numVertices());
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    system.membrane->evaluate(x, {&g, &a, slot}, o);
    const Eigen::MatrixXd U(a.matrix());
    Eigen::MatrixXd full = U + U.transpose();
    full.diagonal() -= U.diagonal();
    return full;
  };
  const Eigen::MatrixXd membraneChange = membraneOnly(all) - membraneOnly(none);
  REQUIRE(membraneChange.norm() > 1e-6 * H.norm());         // the membrane blocks were indefinite
  REQUIRE((Hall - H - membraneChange).norm() > 1e-6 * H.norm());  // and so were some bending blocks
  CHECK((Hsmall - H - membraneChange).norm() <= 1e-10 * H.norm());
}

TEST_CASE("newton: once a time step passed at its start, the next starts are judged on their gradient alone, with "
          "the same trajectory", "[solvers]") {
  testing::SingleThread single;
  const ShellProblem p = testing::freeCloth();
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsOptions o;
  o.timeStep = 0.02;
  o.updateTolerance = 0.1;
  o.extrapolatedStart = true;
  o.newton.gradientFirstStart = true;
  DynamicsOptions off = o;
  off.newton.gradientFirstStart = false;
  DynamicsSolver a(system, o);
  ShellSystem otherSystem(p, AnalysisKind::Dynamics);
  DynamicsSolver b(otherSystem, off);
  // Free fall: from the third step on, the extrapolated start is the exact step (it passes with no iteration).
  int skipped = 0;
  for (int i = 0; i < 6; ++i) {
    const StepReport ra = a.step(), rb = b.step();
    REQUIRE(ra.success);
    REQUIRE(rb.success);
    REQUIRE(ra.solves.size() == 1);
    const SolverSummary& s = ra.solves[0];
    CHECK(s.converged());
    CHECK(rb.solves.at(0).hessianEvaluations >= 1);  // off: the start's Hessian is always assembled
    // Before any step passed at its start, the start's Hessian comes with its gradient: no extra gradient.
    if (i < 3) CHECK(s.gradientEvaluations == rb.solves[0].gradientEvaluations);
    if (s.hessianEvaluations == 0) {
      ++skipped;
      CHECK(s.iterations == 0);
      CHECK(s.finalResidual == rb.solves[0].finalResidual);
    }
    CHECK((a.positions() - b.positions()).lpNorm<Eigen::Infinity>() == 0.0);
  }
  CHECK(skipped >= 3);
  // A start that fails its test (the history is dropped, so Newton starts from the inertial predictor, off by
  // Δt² g): the Hessian is assembled after all, Newton iterates, and both runs take the same step; it cost one
  // gradient more.
  a.setState(a.positions(), a.velocities(), a.time());
  b.setState(b.positions(), b.velocities(), b.time());
  const StepReport ra = a.step(), rb = b.step();
  REQUIRE(ra.success);
  REQUIRE(rb.success);
  const SolverSummary& s = ra.solves.at(0);
  CHECK(s.converged());
  CHECK(s.iterations >= 1);
  CHECK(s.hessianEvaluations >= 1);
  CHECK(s.gradientEvaluations == rb.solves.at(0).gradientEvaluations + 1);  // the start's gradient, evaluated twice
  CHECK((a.positions() - b.positions()).lpNorm<Eigen::Infinity>() == 0.0);
}

TEST_CASE("newton: the iterate test sees each iterate with the fraction of the Newton direction that led to it",
          "[solvers]") {
  ShellSystem system(testing::cantileverPlate(8, 3, 0.02), AnalysisKind::Statics);
  NewtonSolver newton(system.objective(), NewtonOptions{});
  std::vector<int> iterations;
  std::vector<double> fractions;
  newton.setIterateTest([&](const IterateView& it) {
    iterations.push_back(it.iteration);
    fractions.push_back(it.newtonStepFraction);
    return IterateTestResult{};  // never passes: the residual test ends the solve
  });
  Eigen::VectorXd x = system.restPositions();
  const SolverSummary s = newton.minimize(x);
  INFO(s.fullReport());
  REQUIRE(s.converged());
  CHECK(s.convergenceTest == "residual");
  // Asked at the start and after every step but the last (the residual test ends the solve first).
  REQUIRE(static_cast<int>(iterations.size()) == s.iterations);
  REQUIRE(s.trace.size() >= iterations.size());
  CHECK(fractions.at(0) == 0.0);
  for (std::size_t k = 1; k < iterations.size(); ++k) {
    CHECK(iterations[k] == static_cast<int>(k));
    CHECK(fractions[k] == s.trace[k - 1].stepLength);  // no step bound in statics without contact
  }
}

TEST_CASE("newton: each iteration records the largest vertex move of its accepted step") {
  ShellSystem system(testing::cantileverPlate(8, 3, 0.02), AnalysisKind::Statics);
  // The same deterministic solve stopped after one and after two iterations: the second iteration's record is
  // the largest vertex displacement between the two iterates.
  auto solveFor = [&](int iterations, SolverSummary& summary) {
    NewtonOptions o;
    o.maxIterations = iterations;
    NewtonSolver newton(system.objective(), o);
    Eigen::VectorXd x = system.restPositions();
    summary = newton.minimize(x);
    return x;
  };
  SolverSummary one, two;
  const Eigen::VectorXd x1 = solveFor(1, one), x2 = solveFor(2, two);
  REQUIRE(one.trace.size() == 1);
  REQUIRE(two.trace.size() == 2);
  const Eigen::VectorXd x0 = system.restPositions();
  CHECK(one.trace[0].largestMove > 0.0);
  CHECK(one.trace[0].largestMove == Approx(largestVertexNorm(x1 - x0)).epsilon(1e-12));
  CHECK(two.trace[1].largestMove == Approx(largestVertexNorm(x2 - x1)).epsilon(1e-12));
  // Not the largest coordinate: a vertex's whole displacement.
  CHECK(largestVertexNorm(x1 - x0) >= (x1 - x0).lpNorm<Eigen::Infinity>());
  // The JSON trace carries it, per iteration.
  const nlohmann::json j = toJson(two, true);
  REQUIRE(j.at("trace").size() == 2);
  CHECK(j.at("trace")[1].at("largest_move").get<double>() == two.trace[1].largestMove);
  CHECK(two.fullReport().find("move [m]") != std::string::npos);
}

TEST_CASE("newton: a solve says whether its last factor was the true Hessian's and positive definite") {
  testing::SingleThread single;
  auto solve = [](const NewtonOptions& o, Eigen::VectorXd* start = nullptr, bool mustConverge = true) {
    ShellSystem system(testing::cantileverPlate(8, 3, 0.02), AnalysisKind::Statics);
    Eigen::VectorXd x = start != nullptr ? *start : system.restPositions();
    NewtonSolver newton(system.objective(), o);
    const SolverSummary s = newton.minimize(x);
    INFO(s.fullReport());
    if (mustConverge) REQUIRE(s.converged());
    if (start != nullptr) *start = x;
    return s;
  };
  NewtonOptions unprojected;
  unprojected.projection = PsdProjection::None;
  Eigen::VectorXd x;
  {
    ShellSystem system(testing::cantileverPlate(8, 3, 0.02), AnalysisKind::Statics);
    x = system.restPositions();
  }
  CHECK(solve(unprojected, &x).lastHessianPositiveDefinite);  // CHOLMOD factored the exact Hessian unshifted
  CHECK_FALSE(solve(unprojected, &x).lastHessianPositiveDefinite);  // from the equilibrium: nothing factored
  NewtonOptions projected;
  projected.exactHessianNearSolution = false;
  projected.maxIterations = 3;  // projected Newton converges linearly here; its factors are what counts
  CHECK_FALSE(solve(projected, nullptr, false).lastHessianPositiveDefinite);  // clamped: says nothing of the energy
  NewtonOptions iterative = unprojected;
  iterative.linear.type = LinearSolverType::PCG;
  CHECK_FALSE(solve(iterative).lastHessianPositiveDefinite);  // CG proves no definiteness
}
