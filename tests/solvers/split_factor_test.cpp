#include "solvers/cholmod_factor.h"
#include "solvers/dynamics.h"
#include "solvers/linear_solver.h"
#include "solvers/one_ring_pattern.h"
#include "solvers/split_factor.h"
#include "solvers/time_step_policy.h"
#include "test_problems.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

using namespace jetshell;

namespace {

/// A 625-vertex hanging cloth's first-step Hessian (inertia at Δt = 1/60, membrane, two-ring bending), bent, and
/// its one-ring part with the mesh cut in two.
struct SplitCloth {
  ShellSystem shell{testing::hangingCloth(0.6, 0.6, 24, 24), AnalysisKind::Dynamics};
  OneRingFilter filter{shell.mesh().F, shell.mesh().numVertices(), 2};
  Eigen::SparseMatrix<double> P;
  SplitCloth() {
    testing::assembleBentFirstStep(shell);
    filter.apply(H(), P);
  }
  const Eigen::SparseMatrix<double>& H() const { return shell.objective().assembler().matrix(); }
  Eigen::VectorXd rhs() const { return Eigen::VectorXd::LinSpaced(H().rows(), -1.0, 1.0).array().sin(); }
};

}  // namespace

TEST_CASE("one-ring pattern: cut in two, the couplings across the cut go to the diagonal like the two-ring ones",
          "[solvers]") {
  testing::SingleThread single;
  SplitCloth c;
  const std::vector<std::int8_t>& part = c.filter.vertexParts();
  REQUIRE(part.size() == static_cast<std::size_t>(c.shell.mesh().numVertices()));
  REQUIRE(std::count(part.begin(), part.end(), std::int8_t{1}) > 0);
  const OneRingFilter whole(c.shell.mesh().F, c.shell.mesh().numVertices());
  Eigen::VectorXd droppedSum = Eigen::VectorXd::Zero(c.H().rows());
  int crossEdges = 0;
  for (Eigen::Index j = 0; j < c.H().outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(c.H(), j); it; ++it) {
      const int a = static_cast<int>(it.row() / 3), b = static_cast<int>(j / 3);
      const bool across = part[static_cast<std::size_t>(a)] != part[static_cast<std::size_t>(b)];
      CHECK(c.filter.adjacent(a, b) == (whole.adjacent(a, b) && !across));
      if (across && whole.adjacent(a, b)) ++crossEdges;
      if (c.filter.adjacent(a, b)) {
        if (it.row() != j) CHECK(c.P.coeff(it.row(), j) == it.value());
      } else {
        CHECK(c.P.coeff(it.row(), j) == 0.0);
        droppedSum[it.row()] += std::abs(it.value());
        droppedSum[j] += std::abs(it.value());
      }
    }
  CHECK(crossEdges > 0);  // the cut dropped one-ring couplings too
  for (Eigen::Index i = 0; i < c.H().rows(); ++i)
    CHECK(c.P.coeff(i, i) == Approx(c.H().coeff(i, i) + droppedSum[i]).epsilon(1e-14));
}

TEST_CASE("split factor: the two halves solved side by side give the whole factor's solution, on any thread count",
          "[solvers]") {
  SplitCloth c;
  const Eigen::VectorXd b = c.rhs();
  CholmodFactor whole;
  REQUIRE(whole.analyze(c.P) == CholmodFactor::Status::Ok);
  REQUIRE(whole.factorize(c.P, 0.5) == CholmodFactor::Status::Ok);
  Eigen::VectorXd reference;
  REQUIRE(whole.solve(b, reference) == CholmodFactor::Status::Ok);

  Eigen::VectorXd first;
  for (int threads : {1, 2}) {
    const test::ScopedThreads scope(threads);
    SplitFactor split(FillOrdering::Auto, 1);
    split.setPartition(c.filter.vertexParts());
    REQUIRE(split.analyze(c.P) == SplitFactor::Status::Ok);
    CHECK(split.parts() == 2);
    CHECK(split.statistics().nnzL > 0.0);
    REQUIRE(split.factorize(c.P, 0.5) == SplitFactor::Status::Ok);
    Eigen::VectorXd x;
    REQUIRE(split.solve(b, x) == SplitFactor::Status::Ok);
    CHECK((x - reference).norm() <= 1e-12 * reference.norm());
    if (threads == 1) first = x;
    else CHECK(x == first);  // each half alone: the same bits whoever runs it
  }
}

TEST_CASE("split factor: one part is the matrix itself, and a matrix that couples the parts is refused", "[solvers]") {
  SplitCloth c;
  const Eigen::VectorXd b = c.rhs();
  SplitFactor one(FillOrdering::Auto, 1);
  REQUIRE(one.analyze(c.H()) == SplitFactor::Status::Ok);  // no partition: the whole two-ring Hessian
  CHECK(one.parts() == 1);
  REQUIRE(one.factorize(c.H(), 0.0) == SplitFactor::Status::Ok);
  Eigen::VectorXd x;
  REQUIRE(one.solve(b, x) == SplitFactor::Status::Ok);
  CholmodFactor whole;
  Eigen::VectorXd reference;
  REQUIRE(whole.analyze(c.H()) == CholmodFactor::Status::Ok);
  REQUIRE(whole.factorize(c.H(), 0.0) == CholmodFactor::Status::Ok);
  REQUIRE(whole.solve(b, reference) == CholmodFactor::Status::Ok);
  CHECK(x == reference);

  SplitFactor split(FillOrdering::Auto, 1);
  split.setPartition(c.filter.vertexParts());
  CHECK(split.analyze(c.H()) == SplitFactor::Status::Failed);  // the cut's couplings are still there
  CHECK_THAT(split.message(), Catch::Contains("couples parts"));
  CHECK_FALSE(split.analyzed());
  CHECK(split.factorize(c.P, 0.0) == SplitFactor::Status::Failed);
  CHECK(split.solve(b, x) == SplitFactor::Status::Failed);
}

TEST_CASE("split factor: a half that is not positive definite is reported, naming the half", "[solvers]") {
  SplitCloth c;
  SplitFactor split(FillOrdering::Auto, 1);
  split.setPartition(c.filter.vertexParts());
  REQUIRE(split.analyze(c.P) == SplitFactor::Status::Ok);
  // A vertex of part 2 with a negative diagonal entry.
  const std::vector<std::int8_t>& part = c.filter.vertexParts();
  const auto v = static_cast<Eigen::Index>(std::find(part.begin(), part.end(), std::int8_t{1}) - part.begin());
  Eigen::SparseMatrix<double> bad = c.P;
  bad.coeffRef(3 * v, 3 * v) = -1.0;
  CHECK(split.factorize(bad, 0.0) == SplitFactor::Status::NotPositiveDefinite);
  CHECK_THAT(split.message(), Catch::Contains("part 2 of 2") && Catch::Contains("not positive definite"));
  CHECK_FALSE(split.factorized());
  REQUIRE(split.factorize(c.P, 0.0) == SplitFactor::Status::Ok);  // and recovers with the next matrix
}

TEST_CASE("split factor: CG preconditioned by the cut one-ring factor solves the full system", "[solvers]") {
  SplitCloth c;
  const Eigen::VectorXd b = c.rhs();
  CholmodFactor whole;
  Eigen::VectorXd reference;
  REQUIRE(whole.analyze(c.H()) == CholmodFactor::Status::Ok);
  REQUIRE(whole.factorize(c.H(), 0.0) == CholmodFactor::Status::Ok);
  REQUIRE(whole.solve(b, reference) == CholmodFactor::Status::Ok);
  for (int parts : {1, 2}) {
    LinearSolverOptions o;
    o.type = LinearSolverType::PCG;
    o.preconditioner = Preconditioner::OneRingCholesky;
    o.cgRelativeTolerance = 1e-12;
    o.oneRing = std::make_shared<OneRingFilter>(c.shell.mesh().F, c.shell.mesh().numVertices(), parts);
    auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
    Eigen::VectorXd x;
    const LinearSolveReport r = solver->solve(c.H(), 1, b, x);
    REQUIRE(r.success);
    CHECK(r.cgIterations > 0);
    CHECK((x - reference).norm() <= 1e-9 * reference.norm());
    CHECK(solver->factorStatistics().nnzL > 0.0);
  }
}

TEST_CASE("split factor: a time step with self-contact cuts the one-ring factor in two, one without keeps it "
          "whole", "[solvers]") {
  for (bool selfContact : {false, true}) {
    ShellProblem p = testing::hangingCloth(0.6, 0.6, 24, 24);
    ShellActorPart cloth;
    cloth.name = "cloth";
    cloth.mesh = p.mesh;
    cloth.material = p.material;
    cloth.clampedVertices = p.clampedVertices;
    cloth.pointCloudCollider.selfContact = selfContact;  // moving contact pairs: the factor cannot overlap assembly
    p.actors = {cloth};
    ShellSystem system(p, AnalysisKind::Dynamics);
    REQUIRE(system.objective().hasMovingStencils() == selfContact);
    DynamicsOptions o;
    o.timeStep = 1.0 / 60.0;
    applyTimeStepLinearAlgebra(o.newton);
    DynamicsSolver solver(system, o);
    REQUIRE(solver.step().success);
    CHECK(solver.newton().linearSolver().factorStatistics().factors == (selfContact ? 2 : 1));
    o.newton.linear.oneRingParts = 3;
    CHECK_THROWS_WITH(DynamicsSolver(system, o), Catch::Contains("oneRingParts must be 0 (auto), 1 or 2, not 3"));
  }
}

TEST_CASE("split factor: a thread's max-active-levels does not reach another thread", "[solvers]") {
  // CholmodFactor's thread scope sets max-active-levels on the overlapped preconditioner's helper thread while
  // the main thread assembles (solvers/objective.cpp); that is harmless only because the value is per thread.
  const int before = omp_get_max_active_levels();
  std::atomic<int> stage{0};
  int helperRegionThreads = 0;
  std::thread helper([&] {
    omp_set_max_active_levels(0);
    stage = 1;
    while (stage != 2) std::this_thread::yield();
#pragma omp parallel num_threads(2)
    {
#pragma omp atomic
      ++helperRegionThreads;
    }
  });
  while (stage != 1) std::this_thread::yield();
  CHECK(omp_get_max_active_levels() == before);
  int mainRegionThreads = 0;
#pragma omp parallel num_threads(2)
  {
#pragma omp atomic
    ++mainRegionThreads;
  }
  stage = 2;
  helper.join();
  CHECK(helperRegionThreads == 1);
  CHECK(mainRegionThreads == (before >= 1 ? 2 : 1));
}

TEST_CASE("split factor: the one-ring parts option is read by name", "[solvers]") {
  CHECK(oneRingPartsFromString("auto") == 0);
  CHECK(oneRingPartsFromString("1") == 1);
  CHECK(oneRingPartsFromString("2") == 2);
  CHECK_THROWS_WITH(oneRingPartsFromString("3"), "one-ring parts '3': expected auto, 1 or 2");
  LinearSolverOptions o;
  CHECK(oneRingPartsFor(o, true) == 2);
  CHECK(oneRingPartsFor(o, false) == 1);
  o.oneRingParts = 1;
  CHECK(oneRingPartsFor(o, true) == 1);
}
