#include "core/mesh.h"
#include "core/psd_projection.h"

#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>

using namespace jetshell;

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// The reference computations use dynamic sizes: one eigen-solver instantiation for every block size keeps this
// file quick to compile (fixed-size solvers of 9 to 18 rows are among the slowest code to compile).
MatrixXd randomOrthogonal(int n) { return Eigen::HouseholderQR<MatrixXd>(MatrixXd::Random(n, n)).householderQ(); }

VectorXd eigenvaluesOf(const MatrixXd& H) { return Eigen::SelfAdjointEigenSolver<MatrixXd>(H).eigenvalues(); }

/// The whole-block projection, eigenvalue by eigenvalue: clamped at 0, or their absolute values.
MatrixXd wholeBlockProjection(const MatrixXd& H, bool absolute) {
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(H);
  const VectorXd d = absolute ? VectorXd(eig.eigenvalues().cwiseAbs()) : VectorXd(eig.eigenvalues().cwiseMax(0.0));
  return eig.eigenvectors() * d.asDiagonal() * eig.eigenvectors().transpose();
}

Vec6 vec6(double a, double b, double c, double d, double e, double f) {
  Vec6 v;
  v << a, b, c, d, e, f;
  return v;
}

/// Q diag(d) Qᵀ with a fixed orthogonal Q. (Six rows: a size the shipped terms instantiate, core/psd_projection.h.)
Mat6 withEigenvalues(const Vec6& d) {
  const MatrixXd Q = randomOrthogonal(6);
  return Q * d.asDiagonal() * Q.transpose();
}

Vec6 sortedEigenvalues(const Mat6& H) { return eigenvaluesOf(H); }

/// A projection of the symmetric A in both modes (project(P, mode) projects P in place, true when it did)
/// against the eigen-decomposition's: within tolerance × ‖A‖, and exactly symmetric.
template <typename Matrix, typename Project>
void checkAgainstSpectrum(const Matrix& A, double tolerance, Project&& project) {
  for (bool absolute : {false, true}) {
    Matrix P = A;
    REQUIRE(project(P, absolute ? PsdProjection::Abs : PsdProjection::Clamp));
    const MatrixXd expected = wholeBlockProjection(MatrixXd{A}, absolute);
    CHECK((MatrixXd{P} - expected).norm() <= tolerance * std::max(A.norm(), 1e-300));
    CHECK(P == P.transpose());
  }
}

}  // namespace

TEST_CASE("psd projection: none keeps the block, clamp zeroes and abs flips negative eigenvalues") {
  std::srand(3);
  const Mat6 H = withEigenvalues(vec6(-2.0, -0.5, 1.0, 3.0, 4.0, 5.0));
  Mat6 none = H, clamp = H, abs = H;
  CHECK_FALSE(projectPsd<6>(none, PsdProjection::None));
  CHECK(none == H);
  CHECK(projectPsd<6>(clamp, PsdProjection::Clamp));
  CHECK(projectPsd<6>(abs, PsdProjection::Abs));
  CHECK((sortedEigenvalues(clamp) - vec6(0.0, 0.0, 1.0, 3.0, 4.0, 5.0)).norm() <= 1e-13);
  CHECK((sortedEigenvalues(abs) - vec6(0.5, 1.0, 2.0, 3.0, 4.0, 5.0)).norm() <= 1e-13);
  // The eigenvectors are kept: the positive part of H is unchanged by the clamp.
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(MatrixXd{H});
  const Vec6 top = eig.eigenvectors().col(5);
  CHECK((clamp * top - 5.0 * top).norm() <= 1e-13);
  CHECK((clamp - clamp.transpose()).norm() <= 1e-14);
}

TEST_CASE("psd projection: positive definite blocks take an early exit and come back untouched") {
  std::srand(4);
  // Diagonally dominant (Gershgorin proves PSD without factorizing).
  Mat6 dominant = Mat6::Identity();
  dominant.topLeftCorner<4, 4>() << 4, 1, -1, 0.5,  //
      1, 3, 0.5, -1,                                //
      -1, 0.5, 3, 1,                                //
      0.5, -1, 1, 3;
  CHECK(isDiagonallyDominant(dominant));
  Mat6 copy = dominant;
  CHECK_FALSE(projectPsd<6>(copy, PsdProjection::Clamp));
  CHECK(copy == dominant);
  // Positive definite but not diagonally dominant: caught by the Cholesky exit, bits unchanged.
  const Mat6 spd = withEigenvalues(vec6(0.01, 1.0, 2.0, 5.0, 10.0, 50.0));
  CHECK_FALSE(isDiagonallyDominant(spd));
  Mat6 spdCopy = spd;
  CHECK_FALSE(projectPsd<6>(spdCopy, PsdProjection::Abs));
  CHECK(spdCopy == spd);
  // A negative diagonal is never dominant.
  Mat6 negative = Mat6::Identity();
  negative(2, 2) = -1e-3;
  CHECK_FALSE(isDiagonallyDominant(negative));
  CHECK(projectPsd<6>(negative, PsdProjection::Clamp));
  CHECK(negative(2, 2) == Approx(0.0).margin(1e-15));
}

TEST_CASE("psd projection: names parse and print") {
  CHECK(psdProjectionFromString("none") == PsdProjection::None);
  CHECK(psdProjectionFromString("clamp") == PsdProjection::Clamp);
  CHECK(psdProjectionFromString("abs") == PsdProjection::Abs);
  CHECK(std::string(toString(PsdProjection::Clamp)) == "clamp");
  CHECK_THROWS_WITH(psdProjectionFromString("Clamp"), Catch::Contains("'Clamp'"));
  CHECK_THROWS_AS(psdProjectionFromString(""), InputError);
}

TEST_CASE("psd projection: a block with NaN is not diagonally dominant and stays non-finite") {
  Eigen::Matrix3d H = Eigen::Matrix3d::Identity() * 4.0;
  H(0, 1) = H(1, 0) = std::nan("");
  CHECK_FALSE(isDiagonallyDominant(H));
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = std::nan("");
  CHECK_FALSE(isDiagonallyDominant(D));
  for (PsdProjection mode : {PsdProjection::Clamp, PsdProjection::Abs}) {
    Eigen::Matrix3d P = H;
    projectPsd<3>(P, mode);
    CHECK_FALSE(P.allFinite());
  }
}

namespace {

using Mat9 = Eigen::Matrix<double, 9, 9>;

/// L: positions of three vertices -> the edge vectors x1 − x0, x2 − x0.
Eigen::Matrix<double, 6, 9> edgeMap() {
  Eigen::Matrix<double, 6, 9> L = Eigen::Matrix<double, 6, 9>::Zero();
  for (int i = 0; i < 2; ++i) {
    L.block<3, 3>(3 * i, 0) = -Eigen::Matrix3d::Identity();
    L.block<3, 3>(3 * i, 3 + 3 * i) = Eigen::Matrix3d::Identity();
  }
  return L;
}

Mat6 edgeBlock(const Eigen::Matrix<double, 6, 1>& d) {
  const MatrixXd Q = randomOrthogonal(6);
  return Q * d.asDiagonal() * Q.transpose();
}

}  // namespace

TEST_CASE("psd projection: a translation-invariant block is judged by its edge-space block") {
  std::srand(5);
  const Eigen::Matrix<double, 6, 9> L = edgeMap();
  // Positive definite in edge space: the 9×9 block is singular (translations), yet it comes back untouched,
  // with no eigen-decomposition.
  Eigen::Matrix<double, 6, 1> spd;
  spd << 0.02, 0.5, 1.0, 2.0, 7.0, 30.0;
  const Mat9 H = L.transpose() * edgeBlock(spd) * L;
  CHECK(hasTranslationNullSpace(H));
  CHECK(edgeSpaceBlockIsPositiveDefinite(H));
  CHECK_FALSE(isDiagonallyDominant(H));
  Mat9 copy = H;
  CHECK_FALSE(projectPsd<9>(copy, PsdProjection::Clamp));
  CHECK(copy == H);

  // Indefinite in edge space: the same result as the eigen-decomposition of the whole 9×9 block.
  Eigen::Matrix<double, 6, 1> mixed;
  mixed << -3.0, -0.25, 0.5, 1.0, 4.0, 9.0;
  const Mat9 Hm = L.transpose() * edgeBlock(mixed) * L;
  CHECK(hasTranslationNullSpace(Hm));
  CHECK_FALSE(edgeSpaceBlockIsPositiveDefinite(Hm));
  const Mat9 expected = wholeBlockProjection(Hm, false);
  Mat9 projected = Hm;
  CHECK(projectPsd<9>(projected, PsdProjection::Clamp));
  CHECK((projected - expected).norm() <= 1e-12 * expected.norm());
  CHECK(eigenvaluesOf(projected).minCoeff() >= -1e-12 * expected.norm());
  CHECK(hasTranslationNullSpace(projected));
  const Mat9 flipped = wholeBlockProjection(Hm, true);
  Mat9 absProjected = Hm;
  CHECK(projectPsd<9>(absProjected, PsdProjection::Abs));
  CHECK((absProjected - flipped).norm() <= 1e-12 * flipped.norm());

  // A block that is not translation invariant is not judged in edge space.
  Mat9 shifted = H;
  shifted(0, 0) += 1.0;
  CHECK_FALSE(hasTranslationNullSpace(shifted));
}

TEST_CASE("psd projection: a block without a translation null space takes the full eigen-decomposition") {
  std::srand(6);
  const MatrixXd Q = randomOrthogonal(9);
  Eigen::Matrix<double, 9, 1> d;
  d << -2.0, -1.0, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0;
  const Mat9 H = Q * d.asDiagonal() * Q.transpose();
  CHECK_FALSE(hasTranslationNullSpace(H));
  Mat9 projected = H;
  CHECK(projectPsd<9>(projected, PsdProjection::Abs));
  const Eigen::Matrix<double, 9, 1> flipped = eigenvaluesOf(projected);
  Eigen::Matrix<double, 9, 1> want;
  want << 0.5, 1.0, 1.0, 2.0, 2.0, 3.0, 4.0, 5.0, 6.0;
  CHECK((flipped - want).norm() <= 1e-12);
}

TEST_CASE("psd projection: an 18-dof translation-invariant block (a bending stencil's size) matches the whole-block projection") {
  std::srand(8);
  using Mat18 = Eigen::Matrix<double, 18, 18>;
  Eigen::Matrix<double, 15, 18> L = Eigen::Matrix<double, 15, 18>::Zero();
  for (int i = 0; i < 5; ++i) {
    L.block<3, 3>(3 * i, 0) = -Eigen::Matrix3d::Identity();
    L.block<3, 3>(3 * i, 3 + 3 * i) = Eigen::Matrix3d::Identity();
  }
  const MatrixXd Q = randomOrthogonal(15);
  Eigen::Matrix<double, 15, 1> d = Eigen::Matrix<double, 15, 1>::LinSpaced(-4.0, 10.0);
  const Mat18 H = L.transpose() * Q * d.asDiagonal() * Q.transpose() * L;
  REQUIRE(hasTranslationNullSpace(H));
  const Mat18 expected = wholeBlockProjection(H, false);
  Mat18 projected = H;
  CHECK(projectPsd<18>(projected, PsdProjection::Clamp));
  CHECK((projected - expected).norm() <= 1e-12 * expected.norm());
}

TEST_CASE("psd projection: the 2x2 closed form equals the eigen-decomposition's projection") {
  std::srand(11);
  for (int trial = 0; trial < 400; ++trial) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Random();
    A = (A + A.transpose()).eval();
    if (trial % 50 == 0) A(0, 1) = A(1, 0) = 0.0;       // diagonal
    if (trial % 50 == 1) A(1, 1) = A(0, 0);             // equal diagonal
    if (trial % 50 == 2) A *= 1e-300;                   // tiny entries (hypot, not a square root of squares)
    checkAgainstSpectrum(A, 1e-14, [](Eigen::Matrix2d& P, PsdProjection mode) {
      projectSpectrum2(P, mode);
      return true;
    });
  }
}

TEST_CASE("psd projection: one negative eigenvalue from a start near its vector, with the spectrum's result") {
  std::srand(12);
  using Mat4 = Eigen::Matrix4d;
  using Vec4 = Eigen::Vector4d;
  for (int trial = 0; trial < 300; ++trial) {
    const MatrixXd Q = randomOrthogonal(4);
    // One negative eigenvalue, of magnitude from near zero to as large as the positive ones.
    const double negative = -std::pow(10.0, -8.0 + 8.0 * (trial % 10) / 9.0);
    const Vec4 d(negative, 0.5 + trial % 3, 2.0, 40.0);
    const Mat4 A = Q * d.asDiagonal() * Q.transpose();
    // The start: the negative eigenvector turned by up to 0.1 rad. (From farther, the iteration may settle on a
    // positive eigenvalue and return false; the caller then takes the full spectrum.)
    const Vec4 start = Q.col(0) + 0.05 * Vec4::Random();
    checkAgainstSpectrum(A, 1e-13,
                         [&](Mat4& P, PsdProjection mode) { return projectSingleNegative<4>(P, start, mode); });
  }
}

TEST_CASE("psd projection: the one-negative path refuses what it cannot prove and leaves the block unchanged") {
  std::srand(13);
  using Mat4 = Eigen::Matrix4d;
  using Vec4 = Eigen::Vector4d;
  const MatrixXd Q = randomOrthogonal(4);
  // Two negative eigenvalues: the Cholesky proof of the rest fails.
  const Mat4 twoNegative = Q * Vec4(-1.0, -0.5, 2.0, 3.0).asDiagonal() * Q.transpose();
  Mat4 copy = twoNegative;
  CHECK_FALSE(projectSingleNegative<4>(copy, Vec4(Q.col(0)), PsdProjection::Clamp));
  CHECK(copy == twoNegative);
  // A start on a positive eigenvector: the iteration stays there (no negative eigenvalue found).
  const Mat4 oneNegative = Q * Vec4(-1.0, 1.0, 2.0, 3.0).asDiagonal() * Q.transpose();
  copy = oneNegative;
  CHECK_FALSE(projectSingleNegative<4>(copy, Vec4(Q.col(3)), PsdProjection::Clamp));
  CHECK(copy == oneNegative);
  // No start, no projection, a non-finite block, and None.
  CHECK_FALSE(projectSingleNegative<4>(copy, Vec4::Zero(), PsdProjection::Clamp));
  Mat4 bad = oneNegative;
  bad(0, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(projectSingleNegative<4>(bad, Vec4(Q.col(0)), PsdProjection::Clamp));
  CHECK_FALSE(projectSingleNegative<4>(copy, Vec4(Q.col(0)), PsdProjection::None));
  CHECK(copy == oneNegative);
}
