#include "solvers/supernodal_cholesky.h"

#include "solvers/cholmod_factor.h"
#include "solvers/shell_system.h"
#include "test_problems.h"
#include "tests/test_util.h"

#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cholmod.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace jetshell;

namespace {

/// CHOLMOD's analysis of one matrix, factored twice: by CHOLMOD's numeric factorization and by ours.
struct TwoFactors {
  cholmod_common common{};
  cholmod_factor* theirs = nullptr;
  cholmod_factor* ours = nullptr;
  SupernodalCholesky numeric;
  explicit TwoFactors(const Eigen::SparseMatrix<double>& upper) {
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SUPERNODAL;
    common.quick_return_if_not_posdef = 1;
    common.print = 0;
    cholmod_sparse A = view(upper);
    theirs = cholmod_analyze(&A, &common);
    ours = cholmod_copy_factor(theirs, &common);
    std::string message;
    REQUIRE(numeric.prepare(*ours, upper, message));
    REQUIRE(cholmod_change_factor(CHOLMOD_REAL, 1, 1, 1, 1, ours, &common));
  }
  ~TwoFactors() {
    cholmod_free_factor(&theirs, &common);
    cholmod_free_factor(&ours, &common);
    cholmod_finish(&common);
  }
  TwoFactors(const TwoFactors&) = delete;
  TwoFactors& operator=(const TwoFactors&) = delete;

  static cholmod_sparse view(const Eigen::SparseMatrix<double>& m) {
    cholmod_sparse A{};
    A.nrow = A.ncol = static_cast<std::size_t>(m.rows());
    A.nzmax = static_cast<std::size_t>(m.nonZeros());
    A.p = const_cast<int*>(m.outerIndexPtr());
    A.i = const_cast<int*>(m.innerIndexPtr());
    A.x = const_cast<double*>(m.valuePtr());
    A.stype = 1;
    A.itype = CHOLMOD_INT;
    A.xtype = CHOLMOD_REAL;
    A.dtype = CHOLMOD_DOUBLE;
    A.sorted = A.packed = 1;
    return A;
  }
  /// Both factorizations of upper + shift·I; returns their first failing columns (n: none).
  std::pair<std::size_t, std::size_t> factor(const Eigen::SparseMatrix<double>& upper, double shift) {
    cholmod_sparse A = view(upper);
    double beta[2] = {shift, 0.0};
    cholmod_factorize_p(&A, beta, nullptr, 0, theirs, &common);
    return {theirs->minor, numeric.factorize(*ours, upper, shift)};
  }
  /// max |L_ours − L_theirs| / max |L_theirs| over the stored values.
  double difference() const {
    REQUIRE(theirs->xsize == ours->xsize);
    const auto* a = static_cast<const double*>(theirs->x);
    const auto* b = static_cast<const double*>(ours->x);
    double largest = 0.0, diff = 0.0;
    for (std::size_t k = 0; k < theirs->xsize; ++k) {
      largest = std::max(largest, std::abs(a[k]));
      diff = std::max(diff, std::abs(a[k] - b[k]));
    }
    return diff / largest;
  }
};

/// A 625-vertex hanging cloth's first-step Hessian (inertia, membrane, bending), bent: 1,875 dofs.
Eigen::SparseMatrix<double> clothHessian() {
  ShellSystem shell{testing::hangingCloth(0.6, 0.6, 24, 24), AnalysisKind::Dynamics};
  testing::assembleBentFirstStep(shell);
  return shell.objective().assembler().matrix();
}

}  // namespace

TEST_CASE("supernodal cholesky: the factor is CHOLMOD's to round-off, with and without a shift", "[solvers]") {
  const Eigen::SparseMatrix<double> H = clothHessian();
  TwoFactors f(H);
  REQUIRE(f.ours->nsuper > 10);  // many supernodes, and descendants updating them
  for (const double shift : {0.0, 1e3}) {
    const auto [theirs, ours] = f.factor(H, shift);
    CHECK(theirs == f.theirs->n);
    CHECK(ours == f.ours->n);
    CHECK(f.difference() < 1e-13);
  }
}

TEST_CASE("supernodal cholesky: an indefinite matrix fails at CHOLMOD's column, a NaN fails too", "[solvers]") {
  Eigen::SparseMatrix<double> H = clothHessian();
  TwoFactors f(H);
  const double large = 1e3 * H.coeff(0, 0);
  Eigen::SparseMatrix<double> negative = H;
  negative.coeffRef(900, 900) = -large;  // a negative pivot in the middle of the ordering
  const auto [theirs, ours] = f.factor(negative, 0.0);
  CHECK(theirs < f.theirs->n);
  CHECK(ours == theirs);

  Eigen::SparseMatrix<double> notANumber = H;
  notANumber.coeffRef(10, 10) = std::numeric_limits<double>::quiet_NaN();
  CHECK(f.numeric.factorize(*f.ours, notANumber, 0.0) < f.ours->n);
  CHECK(f.factor(H, 0.0).second == f.ours->n);  // and the same object factors a good matrix afterwards
  CHECK(f.difference() < 1e-13);
}

TEST_CASE("supernodal cholesky: the solve is CHOLMOD's to round-off, in place too", "[solvers]") {
  const Eigen::SparseMatrix<double> H = clothHessian();
  TwoFactors f(H);
  const auto [theirs, ours] = f.factor(H, 0.0);
  REQUIRE(theirs == f.theirs->n);
  REQUIRE(ours == f.ours->n);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(H.rows(), -1.0, 2.0).array().sin();
  cholmod_dense B{};
  B.nrow = B.d = B.nzmax = static_cast<std::size_t>(b.size());
  B.ncol = 1;
  B.x = const_cast<double*>(b.data());
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, f.theirs, &B, &f.common);
  REQUIRE(X != nullptr);
  const Eigen::Map<const Eigen::VectorXd> expected(static_cast<const double*>(X->x), b.size());
  Eigen::VectorXd x(b.size());
  f.numeric.solve(*f.ours, b.data(), x.data());
  CHECK((x - expected).norm() < 1e-12 * expected.norm());
  Eigen::VectorXd inPlace = b;
  f.numeric.solve(*f.ours, inPlace.data(), inPlace.data());
  CHECK(inPlace == x);
  cholmod_free_dense(&X, &f.common);
}

TEST_CASE("cholmod factor: solves with the supernodal factorization, refuses a matrix of another pattern",
          "[solvers]") {
  testing::SingleThread single;
  const Eigen::SparseMatrix<double> H = clothHessian();
  CholmodFactor factor;
  REQUIRE(factor.analyze(H) == CholmodFactor::Status::Ok);
  REQUIRE(factor.factorize(H, 0.0) == CholmodFactor::Status::Ok);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(H.rows(), -1.0, 1.0);
  Eigen::VectorXd x;
  REQUIRE(factor.solve(b, x) == CholmodFactor::Status::Ok);
  const Eigen::SparseMatrix<double> full = H.selfadjointView<Eigen::Upper>();
  CHECK((full * x - b).norm() < 1e-10 * b.norm());

  Eigen::SparseMatrix<double> other = H;
  other.coeffRef(0, H.cols() - 1) = 1.0;  // an entry the analysis did not see
  other.makeCompressed();
  CHECK(factor.factorize(other, 0.0) == CholmodFactor::Status::Failed);
  CHECK(factor.message().find("pattern") != std::string::npos);
}

TEST_CASE("cholmod factor: small and degenerate shapes solve like a dense Cholesky", "[solvers]") {
  testing::SingleThread single;
  // A dense matrix (one supernode, no descendants), a diagonal one (supernodes of one column each), an arrow
  // (every column updates the last), and a 1×1.
  const auto dense = [](int n) {
    Eigen::MatrixXd m = Eigen::MatrixXd::Constant(n, n, 0.5) + n * Eigen::MatrixXd::Identity(n, n);
    for (int i = 0; i < n; ++i) m(i, (i + 1) % n) = m((i + 1) % n, i) = 0.25 * (i + 1);
    return m;
  };
  Eigen::MatrixXd arrow = 4.0 * Eigen::MatrixXd::Identity(12, 12);
  for (int i = 0; i < 11; ++i) arrow(i, 11) = arrow(11, i) = 0.3;
  arrow(11, 11) = 12.0;
  const Eigen::MatrixXd diagonal = Eigen::VectorXd::LinSpaced(6, 1.0, 6.0).asDiagonal();
  const Eigen::MatrixXd one = Eigen::MatrixXd::Constant(1, 1, 2.0);
  for (const Eigen::MatrixXd& m : std::vector<Eigen::MatrixXd>{dense(5), dense(40), arrow, diagonal, one}) {
    const Eigen::SparseMatrix<double> upper = m.triangularView<Eigen::Upper>().toDenseMatrix().sparseView();
    CholmodFactor factor;
    REQUIRE(factor.analyze(upper) == CholmodFactor::Status::Ok);
    for (const double shift : {0.0, 0.5}) {
      REQUIRE(factor.factorize(upper, shift) == CholmodFactor::Status::Ok);
      const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(m.rows(), 1.0, 2.0);
      Eigen::VectorXd x;
      REQUIRE(factor.solve(b, x) == CholmodFactor::Status::Ok);
      const Eigen::MatrixXd shifted = m + shift * Eigen::MatrixXd::Identity(m.rows(), m.cols());
      const Eigen::VectorXd expected = shifted.llt().solve(b);
      CHECK((x - expected).norm() <= 1e-12 * expected.norm());
    }
    Eigen::SparseMatrix<double> negative = upper;
    negative.coeffRef(m.rows() - 1, m.cols() - 1) = -1.0;
    CHECK(factor.factorize(negative, 0.0) == CholmodFactor::Status::NotPositiveDefinite);
    CHECK(factor.message().find("not positive definite") != std::string::npos);
  }
}
