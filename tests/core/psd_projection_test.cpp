#include "core/mesh.h"
#include "core/psd_projection.h"

#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>

using namespace jetshell;

namespace {

using Mat4 = Eigen::Matrix4d;

/// Q diag(d) Qᵀ with a fixed orthogonal Q.
Mat4 withEigenvalues(const Eigen::Vector4d& d) {
  const Mat4 Q = Eigen::HouseholderQR<Mat4>(Mat4::Random()).householderQ();
  return Q * d.asDiagonal() * Q.transpose();
}

Eigen::Vector4d sortedEigenvalues(const Mat4& H) { return Eigen::SelfAdjointEigenSolver<Mat4>(H).eigenvalues(); }

}  // namespace

TEST_CASE("psd projection: none keeps the block, clamp zeroes and abs flips negative eigenvalues") {
  std::srand(3);
  const Mat4 H = withEigenvalues(Eigen::Vector4d(-2.0, -0.5, 1.0, 3.0));
  Mat4 none = H, clamp = H, abs = H;
  CHECK_FALSE(projectPsd<4>(none, PsdProjection::None));
  CHECK(none == H);
  CHECK(projectPsd<4>(clamp, PsdProjection::Clamp));
  CHECK(projectPsd<4>(abs, PsdProjection::Abs));
  CHECK((sortedEigenvalues(clamp) - Eigen::Vector4d(0.0, 0.0, 1.0, 3.0)).norm() <= 1e-13);
  CHECK((sortedEigenvalues(abs) - Eigen::Vector4d(0.5, 1.0, 2.0, 3.0)).norm() <= 1e-13);
  // The eigenvectors are kept: the positive part of H is unchanged by the clamp.
  const Eigen::SelfAdjointEigenSolver<Mat4> eig(H);
  const Eigen::Vector4d top = eig.eigenvectors().col(3);
  CHECK((clamp * top - 3.0 * top).norm() <= 1e-13);
  CHECK((clamp - clamp.transpose()).norm() <= 1e-14);
}

TEST_CASE("psd projection: positive definite blocks take an early exit and come back untouched") {
  std::srand(4);
  // Diagonally dominant (Gershgorin proves PSD without factorizing).
  Mat4 dominant;
  dominant << 4, 1, -1, 0.5,  //
      1, 3, 0.5, -1,          //
      -1, 0.5, 3, 1,          //
      0.5, -1, 1, 3;
  CHECK(isDiagonallyDominant(dominant));
  Mat4 copy = dominant;
  CHECK_FALSE(projectPsd<4>(copy, PsdProjection::Clamp));
  CHECK(copy == dominant);
  // Positive definite but not diagonally dominant: caught by the Cholesky exit, bits unchanged.
  const Mat4 spd = withEigenvalues(Eigen::Vector4d(0.01, 1.0, 2.0, 50.0));
  CHECK_FALSE(isDiagonallyDominant(spd));
  Mat4 spdCopy = spd;
  CHECK_FALSE(projectPsd<4>(spdCopy, PsdProjection::Abs));
  CHECK(spdCopy == spd);
  // A negative diagonal is never dominant.
  Mat4 negative = Mat4::Identity();
  negative(2, 2) = -1e-3;
  CHECK_FALSE(isDiagonallyDominant(negative));
  CHECK(projectPsd<4>(negative, PsdProjection::Clamp));
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
