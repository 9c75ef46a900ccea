#include "solvers/linear_solver.h"
#include "solvers/one_ring_pattern.h"
#include "test_problems.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

using namespace jetshell;

namespace {

/// The hanging cloth's first-step Hessian (inertia at Δt = 1/60 plus membrane and two-ring bending), bent.
struct ClothHessian {
  ShellSystem shell{testing::hangingCloth(0.3, 0.3, 5, 5), AnalysisKind::Dynamics};
  ClothHessian() { testing::assembleBentFirstStep(shell); }
  const Eigen::SparseMatrix<double>& H() const { return shell.objective().assembler().matrix(); }
};

/// CG to 1e-12 preconditioned by the one-ring factor of the cloth's mesh.
LinearSolverOptions oneRingCg(const ClothHessian& c) {
  LinearSolverOptions o;
  o.type = LinearSolverType::PCG;
  o.preconditioner = Preconditioner::OneRingCholesky;
  o.cgRelativeTolerance = 1e-12;
  o.oneRing = std::make_shared<OneRingFilter>(c.shell.mesh().F, c.shell.mesh().numVertices());
  return o;
}

}  // namespace

TEST_CASE("one-ring pattern: keeps the one-ring entries, moves the dropped ones' magnitudes to the diagonal", "[solvers]") {
  testing::SingleThread single;
  ClothHessian c;
  const OneRingFilter filter(c.shell.mesh().F, c.shell.mesh().numVertices());
  Eigen::SparseMatrix<double> P;
  filter.apply(c.H(), P);
  REQUIRE(P.rows() == c.H().rows());
  CHECK(P.nonZeros() < c.H().nonZeros());  // bending couples two-rings: some entries go
  const Eigen::MatrixXd H = testing::symmetricFromUpper(c.H()), Pd = testing::symmetricFromUpper(P);
  for (Eigen::Index i = 0; i < H.rows(); ++i) {
    double droppedSum = 0.0;
    for (Eigen::Index j = 0; j < H.cols(); ++j) {
      const bool keep = filter.adjacent(static_cast<int>(i / 3), static_cast<int>(j / 3));
      if (!keep) {
        CHECK(Pd(i, j) == 0.0);
        droppedSum += std::abs(H(i, j));
      } else if (i != j) {
        CHECK(Pd(i, j) == H(i, j));
      }
    }
    CHECK(Pd(i, i) == Approx(H(i, i) + droppedSum).epsilon(1e-14));
  }
  // P − H is positive semi-definite: the preconditioner bounds H from above.
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Pd - H).eigenvalues();
  CHECK(eig.minCoeff() >= -1e-9 * H.diagonal().cwiseAbs().maxCoeff());
}

TEST_CASE("one-ring pattern: CG preconditioned by the one-ring factor solves the full system", "[solvers]") {
  testing::SingleThread single;
  ClothHessian c;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(c.H().rows(), -1.0, 1.0);
  const Eigen::VectorXd reference = testing::symmetricFromUpper(c.H()).ldlt().solve(b);
  LinearSolverOptions o = oneRingCg(c);
  auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
  Eigen::VectorXd x;
  const LinearSolveReport r = solver->solve(c.H(), 1, b, x);
  REQUIRE(r.success);
  CHECK(r.numericFactorizations == 1);
  CHECK(r.cgIterations > 0);
  CHECK((x - reference).norm() <= 1e-8 * reference.norm());
  CHECK(solver->factorStatistics().nnzL > 0.0);

  o.oneRing.reset();  // without the mesh's adjacency the preconditioner cannot be built
  auto missing = makeLinearSolver(o, static_cast<int>(b.size()));
  CHECK_THROWS(missing->solve(c.H(), 1, b, x));
}

TEST_CASE("one-ring pattern: a new Hessian pattern with the same one-ring part keeps the factor's analysis",
          "[solvers]") {
  testing::SingleThread single;
  ClothHessian c;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(c.H().rows(), -1.0, 1.0);
  LinearSolverOptions o = oneRingCg(c);
  auto solver = makeLinearSolver(o, static_cast<int>(b.size()));
  Eigen::VectorXd x;
  REQUIRE(solver->solve(c.H(), 1, b, x).success);
  CHECK(solver->symbolicAnalyses() == 1);

  // A contact pair between two distant vertices: H's pattern grows (a new pattern version), its one-ring part
  // does not.
  const int a = 0, far = c.shell.mesh().numVertices() - 1;
  REQUIRE_FALSE(o.oneRing->adjacent(a, far));
  Eigen::SparseMatrix<double> withPair = c.H();
  for (int k = 0; k < 3; ++k) {
    withPair.coeffRef(3 * a + k, 3 * far + k) += -1.0;
    withPair.coeffRef(3 * a + k, 3 * a + k) += 1.0;
    withPair.coeffRef(3 * far + k, 3 * far + k) += 1.0;
  }
  withPair.makeCompressed();
  const Eigen::VectorXd reference = testing::symmetricFromUpper(withPair).ldlt().solve(b);
  const LinearSolveReport r = solver->solve(withPair, 2, b, x);
  REQUIRE(r.success);
  CHECK_FALSE(r.symbolicAnalysis);
  CHECK(solver->symbolicAnalyses() == 1);
  CHECK((x - reference).norm() <= 1e-8 * reference.norm());

  // A pattern whose one-ring part changes (one vertex fixed: identity rows) is analysed anew.
  Eigen::SparseMatrix<double> fewer = c.H();
  for (int k = 0; k < fewer.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(fewer, k); it; ++it)
      if ((it.row() < 3 || it.col() < 3) && it.row() != it.col()) it.valueRef() = 0.0;
  fewer.prune(0.0);
  fewer.makeCompressed();
  REQUIRE(solver->solve(fewer, 3, b, x).success);
  CHECK(solver->symbolicAnalyses() == 2);
}

TEST_CASE("one-ring pattern: a plan reused over new values gives a fresh filter's matrix, bit for bit",
          "[solvers]") {
  testing::SingleThread single;
  ClothHessian c;
  const OneRingFilter filter(c.shell.mesh().F, c.shell.mesh().numVertices());
  OneRingPlan plan;
  CHECK_FALSE(plan.planned());
  plan.plan(filter, c.H());
  for (double scale : {1.0, -0.5, 3.0}) {
    Eigen::SparseMatrix<double> H = c.H();
    for (Eigen::Index k = 0; k < H.nonZeros(); ++k) H.valuePtr()[k] *= scale * (1.0 + 1e-3 * static_cast<double>(k % 7));
    Eigen::SparseMatrix<double> want;
    filter.apply(H, want);
    const Eigen::SparseMatrix<double>& got = plan.apply(H);
    REQUIRE(got.nonZeros() == want.nonZeros());
    CHECK(std::equal(want.outerIndexPtr(), want.outerIndexPtr() + want.cols() + 1, got.outerIndexPtr()));
    CHECK(std::equal(want.innerIndexPtr(), want.innerIndexPtr() + want.nonZeros(), got.innerIndexPtr()));
    CHECK(std::equal(want.valuePtr(), want.valuePtr() + want.nonZeros(), got.valuePtr()));
  }
  // Another pattern is refused until planned for.
  Eigen::SparseMatrix<double> smaller = c.H();
  smaller.prune([](Eigen::Index r, Eigen::Index col, double) { return r == col || (r + col) % 5 != 0; });
  REQUIRE(smaller.nonZeros() < c.H().nonZeros());
  CHECK_THROWS_AS(plan.apply(smaller), std::invalid_argument);
}

TEST_CASE("one-ring pattern: the plan and its matrix have the same bits on one thread and on three", "[solvers]") {
  ClothHessian c;
  const OneRingFilter filter(c.shell.mesh().F, c.shell.mesh().numVertices(), 2);
  auto planned = [&](int threads) {
    const test::ScopedThreads scope(threads);
    OneRingPlan plan;
    plan.plan(filter, c.H());
    return Eigen::SparseMatrix<double>(plan.apply(c.H()));
  };
  const Eigen::SparseMatrix<double> one = planned(1), three = planned(3);
  REQUIRE(one.nonZeros() == three.nonZeros());
  CHECK(std::equal(one.outerIndexPtr(), one.outerIndexPtr() + one.cols() + 1, three.outerIndexPtr()));
  CHECK(std::equal(one.innerIndexPtr(), one.innerIndexPtr() + one.nonZeros(), three.innerIndexPtr()));
  CHECK(std::equal(one.valuePtr(), one.valuePtr() + one.nonZeros(), three.valuePtr()));
}
