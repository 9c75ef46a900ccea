// The one-ring preconditioner factored during the assembly (Objective::evaluate's narrow hook,
// LinearSolver::preparePreconditioner, NewtonOptions::overlapPreconditioner).
#include "solvers/dynamics.h"
#include "solvers/linear_solver.h"
#include "solvers/one_ring_pattern.h"
#include "solvers/time_step_policy.h"
#include "test_problems.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <atomic>
#include <stdexcept>

using namespace jetshell;

namespace {

/// The hanging cloth bent out of its plane, with inertia centred on its rest shape at Δt = 1/60 s.
struct BentCloth {
  ShellSystem shell{testing::hangingCloth(0.3, 0.3, 6, 6), AnalysisKind::Dynamics};
  Eigen::VectorXd x;
  BentCloth() {
    x = shell.restPositions();
    for (int v = 0; v < shell.mesh().numVertices(); ++v) x[3 * v + 2] += 0.05 * std::pow(shell.mesh().V(v, 0), 2);
    shell.inertia->setCentre(shell.restPositions(), 3600.0);
  }
  static EvalOptions clamp() {
    EvalOptions o;
    o.projection = PsdProjection::Clamp;
    return o;
  }
};

LinearSolverOptions oneRingCg(const ShellSystem& shell) {
  LinearSolverOptions o;
  o.type = LinearSolverType::PCG;
  o.preconditioner = Preconditioner::OneRingCholesky;
  o.cgRelativeTolerance = 1e-12;
  o.oneRing = std::make_shared<OneRingFilter>(shell.mesh().F, shell.mesh().numVertices());
  return o;
}

}  // namespace

TEST_CASE("objective: the narrow hook sees the Hessian without the wide terms, and the sums do not change",
          "[solvers]") {
  for (int threads : {1, 2}) {
    test::ScopedThreads scoped(threads);
    BentCloth c;
    Objective& obj = c.shell.objective();
    Eigen::VectorXd g0, g1;
    const double E0 = obj.evaluate(c.x, &g0, true, BentCloth::clamp());
    const Eigen::MatrixXd H0 = Eigen::MatrixXd(obj.assembler().matrix());

    Eigen::MatrixXd narrow;
    std::atomic<bool> ran{false};
    const double E1 = obj.evaluate(c.x, &g1, true, BentCloth::clamp(), TermSelection::All,
                                   [&](const HessianAssembler& a) {
                                     narrow = Eigen::MatrixXd(a.matrix());
                                     return std::function<void()>([&] { ran = true; });
                                   });
    const Eigen::MatrixXd H1 = Eigen::MatrixXd(obj.assembler().matrix());
    CHECK(ran);
    CHECK(E1 == Approx(E0).epsilon(1e-13));
    CHECK((g1 - g0).norm() <= 1e-12 * g0.norm());
    CHECK((H1 - H0).norm() <= 1e-12 * H0.norm());

    // Bending couples two-rings: at hook time those entries are still zero, and the one-ring part lacks the
    // bending contribution; membrane, inertia and gravity are in.
    const OneRingFilter filter(c.shell.mesh().F, c.shell.mesh().numVertices());
    int twoRing = 0;
    for (Eigen::Index j = 0; j < H0.cols(); ++j)
      for (Eigen::Index i = 0; i <= j; ++i)
        if (!filter.adjacent(static_cast<int>(i / 3), static_cast<int>(j / 3)) && H0(i, j) != 0.0) {
          ++twoRing;
          CHECK(narrow(i, j) == 0.0);
        }
    CHECK(twoRing > 0);
    CHECK((H0 - narrow).norm() > 1e-6 * H0.norm());
    CHECK(narrow.diagonal().minCoeff() > 0.0);  // inertia and membrane already there
  }
}

TEST_CASE("objective: an exception of the overlapped task reaches the caller, and the thread count is restored",
          "[solvers]") {
  test::ScopedThreads scoped(2);
  BentCloth c;
  Eigen::VectorXd g;
  CHECK_THROWS_AS(c.shell.objective().evaluate(c.x, &g, true, BentCloth::clamp(), TermSelection::All,
                                               [](const HessianAssembler&) {
                                                 return std::function<void()>(
                                                     [] { throw std::runtime_error("task failed"); });
                                               }),
                  std::runtime_error);
  CHECK(omp_get_max_threads() == 2);
}

TEST_CASE("pcg: the one-ring factor prepared during assembly, with the wide part lagged, solves H d = b as well",
          "[solvers]") {
  test::ScopedThreads scoped(2);
  BentCloth c;
  Objective& obj = c.shell.objective();
  const std::unique_ptr<LinearSolver> prepared = makeLinearSolver(oneRingCg(c.shell), obj.numDofs());
  const std::unique_ptr<LinearSolver> plain = makeLinearSolver(oneRingCg(c.shell), obj.numDofs());
  const Objective::NarrowAssembledHook prepare = [&](const HessianAssembler& a) {
    return prepared->preparePreconditioner(a.matrix(), a.patternVersion(), true);
  };
  Eigen::VectorXd g;
  for (int k = 0; k < 4; ++k) {
    // Iterates of a bending deformation: the wide part of the preconditioner comes from the one before.
    Eigen::VectorXd x = c.x;
    for (int v = 0; v < c.shell.mesh().numVertices(); ++v) x[3 * v + 1] += 0.02 * k * std::pow(c.shell.mesh().V(v, 0), 3);
    obj.evaluate(x, &g, true, BentCloth::clamp(), TermSelection::All, prepare);
    const Eigen::VectorXd b = -g;
    Eigen::VectorXd d1, d0;
    const LinearSolveReport r1 = prepared->solve(obj.assembler(), b, d1);
    const LinearSolveReport r0 = plain->solve(obj.assembler(), b, d0);
    REQUIRE(r1.success);
    REQUIRE(r0.success);
    // Prepared only on a pattern the solver has planned for, so from the second assembly on.
    CHECK(r1.preparedPreconditioner == (k > 0));
    CHECK_FALSE(r0.preparedPreconditioner);
    CHECK(r1.numericFactorizations == 1);
    CHECK((d1 - d0).norm() <= 1e-9 * d0.norm());
    // The lagged preconditioner is a good one: at most a few CG iterations more than the current one's.
    CHECK(r1.cgIterations <= r0.cgIterations + 3);
  }
  // A solve without a preparation in between sets its own preconditioner up.
  Eigen::VectorXd d;
  const LinearSolveReport again = prepared->solve(obj.assembler(), -g, d);
  CHECK(again.success);
  CHECK_FALSE(again.preparedPreconditioner);
}

TEST_CASE("newton: time steps with the overlapped preconditioner reach the same states", "[solvers][dynamics]") {
  test::ScopedThreads scoped(2);
  Eigen::VectorXd xs[2];
  int prepared[2] = {0, 0};
  for (int overlap : {0, 1}) {
    ShellSystem shell(testing::hangingCloth(0.3, 0.3, 8, 8), AnalysisKind::Dynamics);
    DynamicsOptions o;
    applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
    o.newton.linear.type = LinearSolverType::PCG;
    o.newton.linear.preconditioner = Preconditioner::OneRingCholesky;
    o.newton.overlapPreconditioner = overlap == 1;
    o.updateTolerance = 0.0;  // Newton's own residual test: both runs solve every step to the same tolerance
    DynamicsSolver solver(shell, o);
    for (int step = 0; step < 10; ++step) {
      const StepReport r = solver.step();
      REQUIRE(r.success);
      for (const SolverSummary& s : r.solves)
        for (const IterationRecord& it : s.trace) prepared[overlap] += it.overlappedFactorizationSeconds > 0.0;
    }
    xs[overlap] = solver.positions();
  }
  CHECK(prepared[0] == 0);
  CHECK(prepared[1] > 0);
  // Both converge each step to the residual tolerance (1e-6 of the weight); the states agree far closer than
  // the cloth's motion (centimetres).
  CHECK((xs[1] - xs[0]).lpNorm<Eigen::Infinity>() <= 1e-6);
}

TEST_CASE("dynamics: with the overlapped preconditioner, a run restored from a snapshot repeats the uninterrupted "
          "one bit for bit once that one forgot its solver history there",
          "[solvers][dynamics]") {
  test::ScopedThreads scoped(2);
  DynamicsOptions o;
  applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
  o.integrator = TimeIntegrator::BDF2;
  o.newton.linear.type = LinearSolverType::PCG;
  o.newton.linear.preconditioner = Preconditioner::OneRingCholesky;
  ShellSystem a(testing::hangingCloth(0.3, 0.3, 8, 8), AnalysisKind::Dynamics);
  DynamicsSolver whole(a, o);
  int prepared = 0;
  DynamicsSolver::Snapshot middle;
  for (int step = 0; step < 8; ++step) {
    const StepReport r = whole.step();
    REQUIRE(r.success);
    for (const SolverSummary& s : r.solves)
      for (const IterationRecord& it : s.trace) prepared += it.overlappedFactorizationSeconds > 0.0;
    if (step == 3) {
      middle = whole.snapshot();
      whole.forgetSolverHistory();
    }
  }
  CHECK(prepared > 0);
  ShellSystem b(testing::hangingCloth(0.3, 0.3, 8, 8), AnalysisKind::Dynamics);
  DynamicsSolver resumed(b, o);
  resumed.restore(middle);
  for (int step = 4; step < 8; ++step) REQUIRE(resumed.step().success);
  CHECK(resumed.positions() == whole.positions());
  CHECK(resumed.velocities() == whole.velocities());
}
