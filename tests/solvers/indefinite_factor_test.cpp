#include "solvers/indefinite_factor.h"

#include "solvers/shell_system.h"
#include "test_problems.h"
#include "tests/test_util.h"

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <vector>

using namespace jetshell;

namespace {

/// A 169-vertex hanging cloth's first-step Hessian (inertia, membrane, bending), bent: 507 dofs, many supernodes.
Eigen::SparseMatrix<double> smallClothHessian() {
  ShellSystem shell{testing::hangingCloth(0.6, 0.6, 12, 12), AnalysisKind::Dynamics};
  testing::assembleBentFirstStep(shell);
  return shell.objective().assembler().matrix();
}

/// upper − σ I, σ halfway between the matrix's k-th and (k+1)-th smallest eigenvalues: exactly k negative ones,
/// none near zero if those two are apart. (The six smallest are the pinned dofs' unit rows, then 2.5, 3.1, 4.5.)
Eigen::SparseMatrix<double> shiftedBelow(const Eigen::SparseMatrix<double>& upper, int k) {
  const Eigen::MatrixXd dense = Eigen::MatrixXd(upper).selfadjointView<Eigen::Upper>();
  const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues();
  const double sigma = 0.5 * (eigenvalues[k - 1] + eigenvalues[k]);
  Eigen::SparseMatrix<double> shifted = upper;
  for (Eigen::Index i = 0; i < shifted.rows(); ++i) shifted.coeffRef(i, i) -= sigma;
  return shifted;
}

double relativeResidual(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  const Eigen::VectorXd r = upper.selfadjointView<Eigen::Upper>() * x - b;
  return r.norm() / b.norm();
}

}  // namespace

TEST_CASE("indefinite factor: a definite matrix has no negative pivot, and its solve is exact to round-off",
          "[solvers]") {
  const Eigen::SparseMatrix<double> H = smallClothHessian();
  IndefiniteFactor factor;
  REQUIRE(factor.factorize(H, 1));
  CHECK(factor.negativePivots() == 0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(H.rows(), -1.0, 2.0);
  Eigen::VectorXd x;
  REQUIRE(factor.solve(b, x));
  CHECK(relativeResidual(H, x, b) < 1e-10);
  Eigen::VectorXd d;
  CHECK_FALSE(factor.negativeCurvatureDirection(d));
}

TEST_CASE("indefinite factor: the negative pivots count the negative eigenvalues, and the solve stays exact",
          "[solvers]") {
  const Eigen::SparseMatrix<double> H = smallClothHessian();
  IndefiniteFactor factor;
  for (const int k : {6, 7, 8}) {
    const Eigen::SparseMatrix<double> A = shiftedBelow(H, k);
    REQUIRE(factor.factorize(A, 1));  // one pattern: analysed once
    CHECK(factor.negativePivots() == k);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), 2.0, -1.0);
    Eigen::VectorXd x;
    REQUIRE(factor.solve(b, x));
    CHECK(relativeResidual(A, x, b) < 1e-8);
    Eigen::VectorXd d;
    REQUIRE(factor.negativeCurvatureDirection(d));
    CHECK(d.dot(A.selfadjointView<Eigen::Upper>() * d) < 0.0);
  }
  CHECK(factor.analyses() == 1);
  REQUIRE(factor.factorize(H, 1));  // and back to the definite matrix
  CHECK(factor.negativePivots() == 0);
}

TEST_CASE("indefinite factor: a zero or NaN pivot is a failure, and the next matrix factors again", "[solvers]") {
  Eigen::SparseMatrix<double> H = smallClothHessian();
  IndefiniteFactor factor;
  Eigen::SparseMatrix<double> zero = H;
  for (Eigen::SparseMatrix<double>::InnerIterator it(zero, 0); it; ++it) it.valueRef() = 0.0;  // column 0
  for (Eigen::Index j = 1; j < zero.cols(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(zero, j); it; ++it)
      if (it.row() == 0) it.valueRef() = 0.0;  // and row 0: a singular matrix with a zero pivot
  CHECK_FALSE(factor.factorize(zero, 1));
  CHECK_FALSE(factor.message().empty());
  Eigen::VectorXd x;
  CHECK_FALSE(factor.solve(Eigen::VectorXd::Ones(H.rows()), x));  // no factor to solve with

  Eigen::SparseMatrix<double> notANumber = H;
  notANumber.coeffRef(10, 10) = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(factor.factorize(notANumber, 1));

  REQUIRE(factor.factorize(H, 1));
  CHECK(factor.negativePivots() == 0);
  REQUIRE(factor.solve(Eigen::VectorXd::Ones(H.rows()), x));
  CHECK(relativeResidual(H, x, Eigen::VectorXd::Ones(H.rows())) < 1e-10);
}

TEST_CASE("indefinite factor: a new pattern version is analysed again", "[solvers]") {
  const Eigen::SparseMatrix<double> H = smallClothHessian();
  IndefiniteFactor factor;
  REQUIRE(factor.factorize(H, 1));
  REQUIRE(factor.factorize(H, 1));
  CHECK(factor.analyses() == 1);
  // A pattern with one more stored entry, announced by its version.
  Eigen::SparseMatrix<double> wider = H;
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index j = 0; j < wider.cols(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(wider, j); it; ++it)
      t.emplace_back(it.row(), it.col(), it.value());
  REQUIRE(wider.coeff(0, wider.cols() - 1) == 0.0);  // the first and last dofs are not coupled
  t.emplace_back(0, static_cast<int>(wider.cols() - 1), 0.0);
  wider.setFromTriplets(t.begin(), t.end());
  wider.makeCompressed();
  REQUIRE(wider.nonZeros() == H.nonZeros() + 1);
  REQUIRE(factor.factorize(wider, 2));
  CHECK(factor.analyses() == 2);
  CHECK(factor.negativePivots() == 0);
}

TEST_CASE("indefinite factor: a 1 x 1 negative matrix has one negative pivot, an empty one none", "[solvers]") {
  IndefiniteFactor factor;
  Eigen::SparseMatrix<double> one(1, 1);
  one.insert(0, 0) = -2.0;
  one.makeCompressed();
  REQUIRE(factor.factorize(one, 1));
  CHECK(factor.negativePivots() == 1);
  Eigen::VectorXd x, d;
  REQUIRE(factor.solve(Eigen::VectorXd::Ones(1), x));
  CHECK(x[0] == -0.5);
  REQUIRE(factor.negativeCurvatureDirection(d));
  CHECK(d.size() == 1);
  CHECK(d[0] != 0.0);

  const Eigen::SparseMatrix<double> empty(0, 0);
  REQUIRE(factor.factorize(empty, 2));
  CHECK(factor.negativePivots() == 0);
  CHECK(factor.solve(Eigen::VectorXd(), x));
  CHECK(x.size() == 0);
  CHECK_FALSE(factor.negativeCurvatureDirection(d));
}
