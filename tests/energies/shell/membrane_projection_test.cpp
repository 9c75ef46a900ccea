#include "energies/shell/membrane_projection.h"

#include "core/mesh.h"
#include "core/psd_projection.h"
#include "energies/shell/membrane_term.h"
#include "energies/shell/reference_state.h"
#include "core/topology.h"
#include "tools/checks/derivative_check.h"

#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>

#include <random>

using namespace jetshell;

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

/// A membrane-shaped edge-space block: Jaᵀ W'' Ja + G ⊗ I₃ for a random PSD W'' and a random stress w.
Mat6 membraneBlock(const Eigen::Vector3d& e0, const Eigen::Vector3d& e1, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3d B;
  for (int i = 0; i < 9; ++i) B.data()[i] = u(rng);
  const Eigen::Matrix3d W = B * B.transpose();
  const Eigen::Vector3d w(u(rng), u(rng), u(rng));
  Eigen::Matrix<double, 3, 6> Ja;
  Ja << 2.0 * e0.transpose(), Eigen::RowVector3d::Zero(), e1.transpose(), e0.transpose(), Eigen::RowVector3d::Zero(),
      2.0 * e1.transpose();
  Mat6 He = Ja.transpose() * W * Ja;
  He.topLeftCorner<3, 3>().diagonal().array() += 2.0 * w[0];
  He.bottomRightCorner<3, 3>().diagonal().array() += 2.0 * w[2];
  He.topRightCorner<3, 3>().diagonal().array() += w[1];
  He.bottomLeftCorner<3, 3>().diagonal().array() += w[1];
  return He;
}

/// The face's 9×9 block Lᵀ He L (e0 = x1 − x0, e1 = x2 − x0).
Mat9 wholeBlock(const Mat6& He) {
  Eigen::Matrix<double, 6, 9> L = Eigen::Matrix<double, 6, 9>::Zero();
  for (int k = 0; k < 2; ++k) {
    L.block<3, 3>(3 * k, 0) = -Eigen::Matrix3d::Identity();
    L.block<3, 3>(3 * k, 3 + 3 * k) = Eigen::Matrix3d::Identity();
  }
  return L.transpose() * He * L;
}

}  // namespace

TEST_CASE("membrane projection: the split in-plane/normal projection equals the whole block's", "[membrane][psd]") {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  int projected = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d e0(n(rng), n(rng), n(rng)), e1(n(rng), n(rng), n(rng));
    const Mat6 He = membraneBlock(e0, e1, rng);
    for (PsdProjection mode : {PsdProjection::Clamp, PsdProjection::Abs}) {
      Mat9 expected = wholeBlock(He);
      const bool changed = projectPsd<9>(expected, mode);
      Mat6 split = He;
      const MembraneProjection r = projectMembraneEdgeBlock(split, e0, e1, mode);
      REQUIRE(r != MembraneProjection::Degenerate);
      CHECK((r == MembraneProjection::Projected) == changed);
      projected += r == MembraneProjection::Projected;
      const double scale = std::max(1.0, expected.cwiseAbs().maxCoeff());
      CHECK((wholeBlock(split) - expected).cwiseAbs().maxCoeff() <= 1e-12 * scale);
      CHECK(Eigen::SelfAdjointEigenSolver<Mat6>(split).eigenvalues().minCoeff() >= -1e-12 * scale);
    }
  }
  CHECK(projected > 100);  // most random stresses are indefinite: the split path is the one tested
}

TEST_CASE("membrane projection: positive definite blocks and degenerate faces are left to the caller",
          "[membrane][psd]") {
  const Eigen::Vector3d e0(1.0, 0.0, 0.0), e1(0.0, 1.0, 0.0);
  Mat6 stiff = Mat6::Identity();
  CHECK(projectMembraneEdgeBlock(stiff, e0, e1, PsdProjection::Clamp) == MembraneProjection::Kept);
  CHECK(stiff == Mat6::Identity());
  Mat6 indefinite = -Mat6::Identity();
  CHECK(projectMembraneEdgeBlock(indefinite, e0, e1, PsdProjection::None) == MembraneProjection::Kept);
  CHECK(projectMembraneEdgeBlock(indefinite, e0, 2.0 * e0, PsdProjection::Clamp) == MembraneProjection::Degenerate);
  CHECK(projectMembraneEdgeBlock(indefinite, Eigen::Vector3d::Zero(), e1, PsdProjection::Clamp) ==
        MembraneProjection::Degenerate);
  CHECK(indefinite == -Mat6::Identity());
}

TEST_CASE("membrane projection: the term's projected Hessian is the projection of each face's exact block",
          "[membrane][psd]") {
  // A compressed and sheared 2×2-cell patch: its faces carry compressive stress, so their blocks are indefinite.
  TriMesh mesh;
  mesh.V.resize(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) mesh.V.row(3 * j + i) << 0.5 * i, 0.5 * j, 0.0;
  mesh.F.resize(8, 3);
  int f = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      mesh.F.row(f++) << a, a + 1, a + 4;
      mesh.F.row(f++) << a, a + 4, a + 3;
    }
  const ShellReference ref = computeReference(mesh, buildTopology(mesh));
  MembraneTerm term(mesh, ref, 2.0, 1.5);
  Eigen::VectorXd x(27);
  for (int v = 0; v < 9; ++v) {
    const Eigen::Vector3d p = mesh.V.row(v).transpose();
    x.segment<3>(3 * v) << 0.8 * p[0] + 0.1 * p[1], 0.85 * p[1], 0.05 * std::sin(3.0 * p[0] + p[1]);
  }
  for (DerivativePath path : {DerivativePath::Analytic, DerivativePath::AutoDiff}) {
    // Per face: the exact block, projected as a whole, summed.
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(27, 27);
    for (int face = 0; face < 8; ++face) {
      TriMesh one;
      one.V = mesh.V;
      one.F = mesh.F.row(face);
      MembraneTerm single(one, computeReference(one, buildTopology(one)), 2.0, 1.5);
      const Eigen::MatrixXd full = evaluateDense(single, x, EvalOptions{path, PsdProjection::None}).hessian;
      const int* ids = one.F.data();
      Mat9 block;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) block.block<3, 3>(3 * i, 3 * j) = full.block<3, 3>(3 * ids[i], 3 * ids[j]);
      projectPsd<9>(block, PsdProjection::Clamp);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) expected.block<3, 3>(3 * ids[i], 3 * ids[j]) += block.block<3, 3>(3 * i, 3 * j);
    }
    const Eigen::MatrixXd exact = evaluateDense(term, x, EvalOptions{path, PsdProjection::None}).hessian;
    const Eigen::MatrixXd projected = evaluateDense(term, x, EvalOptions{path, PsdProjection::Clamp}).hessian;
    CHECK((exact - projected).norm() > 1e-3 * exact.norm());  // the patch's blocks are indefinite
    CHECK((projected - expected).cwiseAbs().maxCoeff() <= 1e-11 * exact.cwiseAbs().maxCoeff());
  }
}
