// Per-element projection of symmetric Hessian blocks onto positive semi-definite matrices.
#pragma once

#include <Eigen/Dense>

#include <cmath>
#include <string>

namespace jetshell {

/// None: keep the exact block. Clamp: negative eigenvalues become 0. Abs: eigenvalues become |λ|.
enum class PsdProjection { None, Clamp, Abs };

PsdProjection psdProjectionFromString(const std::string& name);  // "none" | "clamp" | "abs"
const char* toString(PsdProjection p);

/// True when the symmetric block is diagonally dominant with a non-negative diagonal, which proves it PSD
/// (Gershgorin) at O(n²) cost: the cheap early exit before an eigen-decomposition. False for a block with a
/// NaN or infinite entry (NaN comparisons are false, so the test is written to fail on them).
template <typename Matrix>
bool isDiagonallyDominant(const Matrix& H) {
  for (int i = 0; i < H.rows(); ++i) {
    double off = 0.0;
    for (int j = 0; j < H.cols(); ++j) {
      if (j != i) off += std::abs(H(i, j));
    }
    if (!(H(i, i) >= off) || !std::isfinite(off)) return false;
  }
  return true;
}

/// Projects the symmetric block H in place. Returns true when the block was changed.
/// Early exits: diagonal dominance, then a Cholesky factorization (positive definite blocks are kept).
/// A block with a non-finite entry is left as it is (it is not PSD-proven, and no eigen-decomposition can make
/// it finite): the non-finite value reaches the assembled matrix, where the solver reports it.
template <int N>
bool projectPsd(Eigen::Matrix<double, N, N>& H, PsdProjection mode) {
  if (mode == PsdProjection::None) return false;
  if (isDiagonallyDominant(H)) return false;
  if (!H.allFinite()) return false;
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(H);
  if (llt.info() == Eigen::Success) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(H);
  Eigen::Matrix<double, N, 1> d = eig.eigenvalues();
  for (int i = 0; i < N; ++i) d[i] = mode == PsdProjection::Clamp ? std::max(d[i], 0.0) : std::abs(d[i]);
  H = eig.eigenvectors() * d.asDiagonal() * eig.eigenvectors().transpose();
  return true;
}

}  // namespace jetshell
