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

/// True when every 3-row group of H sums to zero in each column (to roundoff): the block of an energy that is
/// invariant under a common translation of its K vertices. Then H = Lᵀ H_e L, with H_e the block over vertices
/// 1..K−1 and L the map from positions to the edge vectors x_k − x_0, so H is PSD exactly when H_e is.
template <int N>
bool hasTranslationNullSpace(const Eigen::Matrix<double, N, N>& H) {
  static_assert(N % 3 == 0, "blocks of 3-vectors");
  for (int j = 0; j < N; ++j) {
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0, magnitude = 0.0;
      for (int k = c; k < N; k += 3) {
        sum += H(k, j);
        magnitude += std::abs(H(k, j));
      }
      if (!(std::abs(sum) <= 1e-10 * magnitude)) return false;
    }
  }
  return true;
}

/// True when a translation-invariant block is positive semi-definite, judged by a Cholesky factorization of its
/// edge-space block H_e (N − 3 square). The full block is always singular, so its own Cholesky never succeeds and
/// every such block would otherwise go to an eigen-decomposition.
template <int N>
bool edgeSpaceBlockIsPositiveDefinite(const Eigen::Matrix<double, N, N>& H) {
  constexpr int R = N - 3;
  using Reduced = Eigen::Matrix<double, R, R>;
  return Eigen::LLT<Reduced>(Reduced(H.template bottomRightCorner<R, R>())).info() == Eigen::Success;
}

/// Projects the symmetric block H in place. Returns true when the block was changed.
/// Early exits: diagonal dominance, then a Cholesky factorization (positive definite blocks are kept). A block
/// with a translation null space (membrane, bending, contact pairs) is judged by its edge-space block; an
/// indefinite one is projected as a whole, as any other block. (Projecting the edge-space block instead,
/// Lᵀ P(H_e) L, was measured: it costs (N−3)³ instead of N³, but on the T-shirt's landing, under the 4-iteration
/// cap, its directions let the shirt press 4.4 mm below the plane against 1.9 mm.)
/// A block with a non-finite entry is left as it is (it is not PSD-proven, and no eigen-decomposition can make
/// it finite): the non-finite value reaches the assembled matrix, where the solver reports it.
template <int N>
bool projectPsd(Eigen::Matrix<double, N, N>& H, PsdProjection mode) {
  if (mode == PsdProjection::None) return false;
  if (isDiagonallyDominant(H)) return false;
  if (!H.allFinite()) return false;
  bool judged = false, positive = false;
  if constexpr (N % 3 == 0 && N >= 6) {
    judged = hasTranslationNullSpace(H);
    if (judged) positive = edgeSpaceBlockIsPositiveDefinite(H);
  }
  if (!judged) positive = Eigen::LLT<Eigen::Matrix<double, N, N>>(H).info() == Eigen::Success;
  if (positive) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(H);
  Eigen::Matrix<double, N, 1> d = eig.eigenvalues();
  for (int i = 0; i < N; ++i) d[i] = mode == PsdProjection::Clamp ? std::max(d[i], 0.0) : std::abs(d[i]);
  H = eig.eigenvectors() * d.asDiagonal() * eig.eigenvectors().transpose();
  return true;
}

}  // namespace jetshell
