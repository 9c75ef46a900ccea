#include "solvers/linear_solver.h"
#include "solvers/newton.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <omp.h>
#include <sstream>
#include <string>
#include <vector>

using namespace jetshell;

namespace {

/// The cantilever's Hessian (clamped projection) at a bent configuration, and a right-hand side.
struct System {
  ShellSystem shell{testing::cantileverPlate(8, 3, 0.02), AnalysisKind::Statics};
  Eigen::VectorXd g;
  System() { bend(0.05); }
  /// Re-evaluates gradient and Hessian with the plate bent to z = amount·x².
  void bend(double amount) {
    Eigen::VectorXd x = shell.restPositions();
    for (int v = 0; v < shell.mesh().numVertices(); ++v) x[3 * v + 2] += amount * std::pow(shell.mesh().V(v, 0), 2);
    EvalOptions o;
    o.projection = PsdProjection::Clamp;
    shell.objective().evaluate(x, &g, true, o);
  }
  const HessianAssembler& assembler() const { return shell.objective().assembler(); }
};

}  // namespace

TEST_CASE("linear solver: CHOLMOD, Eigen LDLT and PCG agree") {
  testing::SingleThread single;
  System sys;
  const Eigen::VectorXd b = -sys.g;
  const Eigen::MatrixXd H = testing::symmetricFromUpper(sys.assembler().matrix());
  const Eigen::VectorXd reference = H.ldlt().solve(b);
  LinearSolverOptions o;
  o.cgRelativeTolerance = 1e-12;
  struct Case {
    LinearSolverType type;
    Preconditioner preconditioner;
    double tolerance;
  };
  for (const Case& c : {Case{LinearSolverType::Cholmod, Preconditioner::Jacobi, 1e-8},
                        Case{LinearSolverType::EigenLDLT, Preconditioner::Jacobi, 1e-8},
                        Case{LinearSolverType::PCG, Preconditioner::Jacobi, 1e-5},
                        Case{LinearSolverType::PCG, Preconditioner::BlockJacobi, 1e-5},
                        Case{LinearSolverType::PCG, Preconditioner::IncompleteCholesky, 1e-5},
                        Case{LinearSolverType::PCG, Preconditioner::LaggedCholesky, 1e-8}}) {
    o.type = c.type;
    o.preconditioner = c.preconditioner;
    auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
    Eigen::VectorXd x;
    const LinearSolveReport r = solver->solve(sys.assembler(), b, x);
    INFO(solver->name() << ": " << r.message);
    REQUIRE(r.success);
    CHECK(r.regularizations == 0);
    // Only a direct factorization of H itself says H is positive definite.
    CHECK(r.positiveDefinite == (c.type != LinearSolverType::PCG));
    CHECK(r.symbolicAnalysis);
    CHECK((x - reference).norm() <= c.tolerance * reference.norm());
    CHECK((H * x - b).norm() <= c.tolerance * 10.0 * b.norm());
    // Same pattern again: no new analysis.
    const LinearSolveReport again = solver->solve(sys.assembler(), b, x);
    CHECK_FALSE(again.symbolicAnalysis);
    CHECK(solver->symbolicAnalyses() == 1);
  }
}

TEST_CASE("linear solver: the lagged Cholesky preconditioner reuses an old factor until CG needs too many iterations") {
  testing::SingleThread single;
  System sys;
  const Eigen::VectorXd b = -sys.g;
  LinearSolverOptions o;
  o.type = LinearSolverType::PCG;
  o.preconditioner = Preconditioner::LaggedCholesky;
  auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
  Eigen::VectorXd x;
  LinearSolveReport r = solver->solve(sys.assembler(), b, x);
  REQUIRE(r.success);
  CHECK(r.numericFactorizations == 1);
  CHECK(r.cgIterations <= 2);
  // The Hessian at a nearby configuration (same pattern): the old factor still preconditions, no
  // refactorization.
  sys.bend(0.051);
  r = solver->solve(sys.assembler(), b, x);
  REQUIRE(r.success);
  CHECK(r.numericFactorizations == 0);
  CHECK(r.cgIterations > 1);
  CHECK((testing::symmetricFromUpper(sys.assembler().matrix()) * x - b).norm() <= 1e-8 * b.norm());
  // A far one: CG with the old factor gives up after lagRefactorIterations and refactors.
  sys.bend(0.3);
  r = solver->solve(sys.assembler(), b, x);
  REQUIRE(r.success);
  CHECK(r.numericFactorizations == 1);
  CHECK((testing::symmetricFromUpper(sys.assembler().matrix()) * x - b).norm() <= 1e-8 * b.norm());
  CHECK(solver->symbolicAnalyses() == 1);
}

TEST_CASE("linear solver: PCG that spends its iteration budget finishes with the whole matrix's factor") {
  testing::SingleThread single;
  System sys;
  const Eigen::VectorXd b = -sys.g;
  const Eigen::MatrixXd H = testing::symmetricFromUpper(sys.assembler().matrix());
  LinearSolverOptions o;
  o.type = LinearSolverType::PCG;
  o.preconditioner = Preconditioner::Jacobi;
  o.cgRelativeTolerance = 1e-10;
  // Jacobi-preconditioned CG on the bent plate's Hessian needs many iterations.
  Eigen::VectorXd plain;
  const LinearSolveReport slow = makeLinearSolver(o, static_cast<int>(b.size()))->solve(sys.assembler(), b, plain);
  REQUIRE(slow.success);
  REQUIRE(slow.cgIterations > 20);
  CHECK(slow.directFallbacks == 0);
  // With a budget of 10 iterations the whole Hessian is factored and CG ends in an iteration or two more.
  o.cgDirectAfter = 10;
  auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
  Eigen::VectorXd x;
  LinearSolveReport r = solver->solve(sys.assembler(), b, x);
  INFO(r.message);
  REQUIRE(r.success);
  CHECK(r.directFallbacks == 1);
  CHECK(r.numericFactorizations == 1);
  CHECK(r.cgIterations <= 10 + 3);
  CHECK((H * x - b).norm() <= 1e-9 * b.norm());
  // A nearby matrix of the same pattern reuses the analysis; a budget larger than CG needs changes nothing.
  sys.bend(0.051);
  r = solver->solve(sys.assembler(), b, x);
  REQUIRE(r.success);
  CHECK(r.directFallbacks == 1);
  CHECK((testing::symmetricFromUpper(sys.assembler().matrix()) * x - b).norm() <= 1e-9 * b.norm());
  o.cgDirectAfter = 0;
  const LinearSolveReport unbudgeted = makeLinearSolver(o, static_cast<int>(b.size()))->solve(sys.assembler(), b, x);
  REQUIRE(unbudgeted.success);
  o.cgDirectAfter = unbudgeted.cgIterations + 1;
  r = makeLinearSolver(o, static_cast<int>(b.size()))->solve(sys.assembler(), b, x);
  REQUIRE(r.success);
  CHECK(r.directFallbacks == 0);
  CHECK(r.cgIterations == unbudgeted.cgIterations);
}

TEST_CASE("linear solver: an indefinite matrix is shifted, retried and reported") {
  testing::SingleThread single;
  System sys;
  Eigen::SparseMatrix<double> H = sys.assembler().matrix();
  // Lower the free diagonal until the smallest diagonal entry is negative: certainly indefinite.
  const Eigen::VectorXd d = H.diagonal();
  const double shiftDown = d.cwiseAbs().minCoeff() + 1e-3 * d.cwiseAbs().mean();
  for (int j = 0; j < H.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(H, j); it; ++it)
      if (it.row() == j && !sys.assembler().fixedDof()[static_cast<std::size_t>(j)]) it.valueRef() -= shiftDown;
  const Eigen::VectorXd b = -sys.g;
  for (LinearSolverType type : {LinearSolverType::Cholmod, LinearSolverType::EigenLDLT, LinearSolverType::PCG}) {
    LinearSolverOptions o;
    o.type = type;
    auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
    Eigen::VectorXd x;
    const LinearSolveReport r = solver->solve(H, 1, b, x, &sys.assembler().fixedDof());
    INFO(solver->name() << ": " << r.message);
    REQUIRE(r.success);
    CHECK(r.regularizations > 0);
    CHECK(r.shift > 0.0);
    CHECK_FALSE(r.positiveDefinite);  // the shifted matrix was, not H
    CHECK(x.allFinite());
    CHECK(b.dot(x) > 0.0);  // a descent direction for the gradient −b
    // Without retries the same matrix is reported, not solved.
    const LinearSolveReport none = solver->solve(H, 1, b, x, &sys.assembler().fixedDof(), 0);
    CHECK_FALSE(none.success);
    // With too few, each reason is reported once with the shifts it was met at (it was repeated per try).
    const LinearSolveReport few = solver->solve(H, 1, b, x, &sys.assembler().fixedDof(), 2);
    INFO(few.message);
    REQUIRE_FALSE(few.success);
    REQUIRE(few.message.rfind("linear solve failed: ", 0) == 0);
    std::vector<std::string> reasons;
    std::istringstream parts(few.message.substr(21));
    for (std::string part; std::getline(parts, part, ';');) {
      const std::size_t from = part.find_first_not_of(' ');
      const std::string reason = part.substr(from, part.find(" (") - from);
      CHECK(std::find(reasons.begin(), reasons.end(), reason) == reasons.end());
      reasons.push_back(reason);
    }
    if (reasons.size() == 1) CHECK(few.message.find("(3 tries: no shift, then shift ") != std::string::npos);
  }
}

TEST_CASE("linear solver: a Newton solve gives the same iterates with CHOLMOD and Eigen LDLT") {
  testing::SingleThread single;
  ShellSystem system(testing::cantileverPlate(6, 2, 0.01), AnalysisKind::Statics);
  NewtonOptions o;
  o.linear.type = LinearSolverType::Cholmod;
  Eigen::VectorXd xc = system.restPositions();
  const SolverSummary sc = NewtonSolver(system.objective(), o).minimize(xc);
  o.linear.type = LinearSolverType::EigenLDLT;
  Eigen::VectorXd xe = system.restPositions();
  const SolverSummary se = NewtonSolver(system.objective(), o).minimize(xe);
  REQUIRE(sc.converged());
  REQUIRE(se.converged());
  CHECK(sc.linearSolver == "cholmod");
  CHECK(se.linearSolver == "ldlt");
  CHECK(sc.iterations == se.iterations);
  CHECK((xc - xe).lpNorm<Eigen::Infinity>() <= 1e-9);
}

TEST_CASE("linear solver: CHOLMOD runs with its BLAS thread count and leaves OpenMP's settings as they were") {
  System s;
  const int threads = omp_get_max_threads(), levels = omp_get_max_active_levels();
  for (int blasThreads : {1, 2}) {
    LinearSolverOptions o;
    o.type = LinearSolverType::Cholmod;
    o.blasThreads = blasThreads;
    auto solver = makeLinearSolver(o, s.shell.objective().numDofs());
    Eigen::VectorXd x;
    const Eigen::VectorXd b = -s.g;
    REQUIRE(solver->solve(s.assembler(), b, x).success);
    CHECK((testing::symmetricFromUpper(s.assembler().matrix()) * x - b).norm() <= 1e-8 * b.norm());
    CHECK(omp_get_max_threads() == threads);
    CHECK(omp_get_max_active_levels() == levels);
  }
}

TEST_CASE("linear solver: the last system is solved again for a new right-hand side, and not after a shifted "
          "solve or on another pattern") {
  testing::SingleThread single;
  System sys;
  const Eigen::SparseMatrix<double>& H = sys.assembler().matrix();
  const std::uint64_t version = sys.assembler().patternVersion();
  const Eigen::VectorXd b = -sys.g;
  Eigen::VectorXd other = Eigen::VectorXd::LinSpaced(b.size(), -1.0, 1.0);
  for (Eigen::Index i = 0; i < other.size(); ++i)
    if (sys.assembler().fixedDof()[static_cast<std::size_t>(i)]) other[i] = 0.0;
  const Eigen::VectorXd reference = testing::symmetricFromUpper(H).ldlt().solve(other);
  struct Case {
    LinearSolverType type;
    Preconditioner preconditioner;
    double tolerance;  // relative to the reference
  };
  for (const Case& c : {Case{LinearSolverType::Cholmod, Preconditioner::Jacobi, 1e-8},
                        Case{LinearSolverType::PCG, Preconditioner::IncompleteCholesky, 1e-2},
                        Case{LinearSolverType::PCG, Preconditioner::BlockJacobi, 1e-2}}) {
    LinearSolverOptions o;
    o.type = c.type;
    o.preconditioner = c.preconditioner;
    auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
    Eigen::VectorXd x, y;
    LinearSolveReport again;
    INFO(solver->name());
    CHECK_FALSE(solver->solveLastSystem(H, version, other, y, 1e-6, again));  // nothing solved yet
    REQUIRE(solver->solve(sys.assembler(), b, x).success);
    REQUIRE(solver->solveLastSystem(H, version, other, y, 1e-6, again));
    CHECK((y - reference).norm() <= c.tolerance * reference.norm());
    CHECK_FALSE(solver->solveLastSystem(H, version + 1, other, y, 1e-6, again));  // another pattern
    // A shifted solve's system is not H: nothing to solve again.
    Eigen::SparseMatrix<double> indefinite = H;
    const Eigen::VectorXd d = H.diagonal();
    const double shiftDown = d.cwiseAbs().minCoeff() + 1e-3 * d.cwiseAbs().mean();
    for (int j = 0; j < indefinite.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(indefinite, j); it; ++it)
        if (it.row() == j && !sys.assembler().fixedDof()[static_cast<std::size_t>(j)]) it.valueRef() -= shiftDown;
    const LinearSolveReport shifted = solver->solve(indefinite, version, b, x, &sys.assembler().fixedDof());
    INFO(shifted.message);
    REQUIRE(shifted.success);
    REQUIRE(shifted.shift > 0.0);
    CHECK_FALSE(solver->solveLastSystem(indefinite, version, other, y, 1e-6, again));
  }
}
