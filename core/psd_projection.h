// Per-element projection of symmetric Hessian blocks onto positive semi-definite matrices.
#pragma once

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

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

/// Completes the block H = Lᵀ H_e L of an energy invariant under a common translation of its K vertices from its
/// edge-space corner H_e (the rows and columns of vertices 1 … K−1, every block set): vertex 0's block in column c
/// is minus column c's sum, and its own block the sum of all (L maps positions to the edge vectors x_k − x_0).
template <int N, typename Corner>
void completeTranslationInvariantRow(const Corner& E, Eigen::Matrix<double, N, N>& H);
template <int N>
void completeTranslationInvariant(Eigen::Matrix<double, N, N>& H) {
  constexpr int R = N - 3;
  completeTranslationInvariantRow(H.template bottomRightCorner<R, R>(), H);
  H.template block<R, 3>(3, 0) = H.template block<3, R>(0, 3).transpose();
}
/// The upper part of completeTranslationInvariant: vertex 0's row of blocks and its own block of H from the
/// edge-space corner E (its top-left (N − 3) × (N − 3) read; E may be H's own corner or a padded copy); the rest
/// of H is not written.
template <int N, typename Corner>
void completeTranslationInvariantRow(const Corner& E, Eigen::Matrix<double, N, N>& H) {
  static_assert(N % 3 == 0 && N >= 6, "blocks of at least two 3-vectors");
  constexpr int R = N - 3;
  Eigen::Matrix<double, 3, R> column = E.template block<3, R>(0, 0);
  for (int r = 1; r < R / 3; ++r) column += E.template block<3, R>(3 * r, 0);
  H.template block<3, R>(0, 3) = -column;
  Eigen::Matrix3d all = column.template leftCols<3>();
  for (int c = 1; c < R / 3; ++c) all += column.template middleCols<3>(3 * c);
  H.template topLeftCorner<3, 3>() = all;
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

/// The matrix type an N×N block's eigen-decomposition works in: the block's own fixed size up to 5 rows, and above
/// that one bounded dynamic-size type of at most 18 rows (no heap allocation). A fixed-size eigen-solver is among
/// the slowest code to compile (15-20 s per size with g++ 12 -O3); the bounded one costs 1.10× the fixed one's
/// time at 6 rows, 1.02× at 9 and within ±6% from 12 to 18 (random symmetric blocks), while at 3 rows the fixed
/// one is 1.45× faster and stays. So the sizes from 6 rows share one instantiation: psd_projection.cpp compiles in
/// 25 s instead of 48 (BENCHMARKS.md "CI time", session 34).
template <int N>
using SpectrumWork = std::conditional_t<(N > 5 && N <= 18),
                                        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 18, 18>,
                                        Eigen::Matrix<double, N, N>>;

/// The 2×2 case of projectSpectrum in closed form: λ = m ∓ r with m the mean of the diagonal and r = hypot(half
/// their difference, the off-diagonal), and the positive eigenvalue's vector from the row without cancellation.
inline void projectSpectrum2(Eigen::Matrix2d& A, PsdProjection mode) {
  const double m = 0.5 * (A(0, 0) + A(1, 1)), d = 0.5 * (A(0, 0) - A(1, 1)), b = 0.5 * (A(0, 1) + A(1, 0));
  const double r = std::hypot(d, b);
  const double low = m - r, high = m + r;
  if (low >= 0.0) return;
  if (high <= 0.0) {  // both eigenvalues negative (or zero)
    if (mode == PsdProjection::Clamp) A.setZero();
    else A = -A;
    return;
  }
  // (A − high I) v = 0 for v = (d + r, b) when d >= 0, else (b, r − d): neither sum cancels.
  Eigen::Vector2d v = d >= 0.0 ? Eigen::Vector2d(d + r, b) : Eigen::Vector2d(b, r - d);
  v.normalize();
  // high v vᵀ, plus |low| u uᵀ with u = v's perpendicular for Abs, written out so A stays exactly symmetric.
  const double keep = mode == PsdProjection::Clamp ? 0.0 : -low;
  A(0, 0) = high * v[0] * v[0] + keep * v[1] * v[1];
  A(1, 1) = high * v[1] * v[1] + keep * v[0] * v[0];
  A(0, 1) = A(1, 0) = (high - keep) * v[0] * v[1];
}

/// A ← V P(Λ) Vᵀ for the symmetric A = V Λ Vᵀ: negative eigenvalues clamped at 0 (Clamp) or replaced by |λ| (Abs).
template <int N>
void projectSpectrum(Eigen::Matrix<double, N, N>& A, PsdProjection mode) {
  if constexpr (N == 2) {
    projectSpectrum2(A, mode);
    return;
  }
  using Work = SpectrumWork<N>;
  const Eigen::SelfAdjointEigenSolver<Work> eig{Work(A)};
  auto d = eig.eigenvalues().eval();
  for (Eigen::Index i = 0; i < d.size(); ++i)
    d[i] = mode == PsdProjection::Clamp ? std::max(d[i], 0.0) : std::abs(d[i]);
  A = eig.eigenvectors() * d.asDiagonal() * eig.eigenvectors().transpose();
}

/// The projection of a symmetric A (neither PSD-proven nor projected) that has exactly one negative eigenvalue ρ,
/// when the caller knows a vector close to its eigenvector (the membrane's in-plane rotation mode, whose stiffness
/// is the stress alone): A ← A − ρ x xᵀ (Clamp) or A − 2ρ x xᵀ (Abs), the same matrix as projectSpectrum's to
/// rounding. ρ and x come from Rayleigh quotient iteration from `start` (cubic: two steps on the T-shirt's blocks),
/// run until ‖A x − ρ x‖ <= 64 ε ‖A‖_F. The other eigenvalues are proven positive by a Cholesky factorization of
/// A + (‖A‖_F − ρ) x xᵀ, whose spectrum is theirs and ‖A‖_F. Returns false and leaves A unchanged when the
/// iteration does not converge to a negative eigenvalue or that factorization fails (a second eigenvalue <= 0):
/// the caller then projects the full spectrum. Measured on 213,089 in-plane blocks of the T-shirt: 244 ns
/// against 834 ns for Eigen's eigen-solver, 0.08% returned false, results within 5e-15 of its relative to ‖A‖.
template <int N>
bool projectSingleNegative(Eigen::Matrix<double, N, N>& A, const Eigen::Matrix<double, N, 1>& start,
                           PsdProjection mode) {
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;
  if (mode == PsdProjection::None) return false;
  const double scale = A.norm();
  const double startNorm = start.norm();
  if (!(scale > 0.0) || !std::isfinite(scale) || !(startNorm > 0.0) || !std::isfinite(startNorm)) return false;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double tolerance = 64.0 * eps * scale;
  Vector x = start / startNorm;
  double rho = x.dot(A * x);
  bool converged = false;
  constexpr int kMaxSteps = 6;
  for (int k = 0;; ++k) {
    const double residual = (A * x - rho * x).norm();
    // A ρ within the tolerance moves A by less than the tolerance whatever x is.
    if (residual <= tolerance || std::abs(rho) <= 0.5 * tolerance) {
      converged = true;
      break;
    }
    if (k == kMaxSteps) break;
    Matrix shifted = A;
    shifted.diagonal().array() -= rho;
    Vector y = shifted.inverse() * x;
    double norm = y.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      // ρ is an eigenvalue to rounding and A − ρI singular: one inverse-iteration step from a shift off it.
      shifted.diagonal().array() += std::max(residual, 4.0 * eps * scale);
      y = shifted.inverse() * x;
      norm = y.norm();
      if (!(norm > 0.0) || !std::isfinite(norm)) return false;
    }
    x = y / norm;
    rho = x.dot(A * x);
  }
  if (!converged || !(rho < 0.0)) return false;
  const Matrix rest = A + (scale - rho) * x * x.transpose();
  if (Eigen::LLT<Matrix>(rest).info() != Eigen::Success) return false;
  const Vector scaled = (mode == PsdProjection::Clamp ? rho : 2.0 * rho) * x;
  for (int j = 0; j < N; ++j)  // A − scaled xᵀ, one triangle mirrored so A stays exactly symmetric
    for (int i = 0; i <= j; ++i) A(j, i) = A(i, j) -= scaled[i] * x[j];
  return true;
}

/// X ← (I + coef · 11ᵀ ⊗ I₃) X: adds coef × the sum of X's 3-row groups to each group.
template <int R>
void addBlockRowSums(Eigen::Matrix<double, R, R>& X, double coef) {
  Eigen::Matrix<double, 3, R> sum = Eigen::Matrix<double, 3, R>::Zero();
  for (int i = 0; i < R / 3; ++i) sum += X.template middleRows<3>(3 * i);
  sum *= coef;
  for (int i = 0; i < R / 3; ++i) X.template middleRows<3>(3 * i) += sum;
}

/// S ← M S M for an edge-space block S (R/3 edge groups), M = (I + 11ᵀ)^{1/2} ⊗ I₃ the metric of
/// projectPsdTranslationInvariant, or M⁻¹ S M⁻¹ (inverse). M^{±1} = I + c 11ᵀ (⊗ I₃) in closed form: 11ᵀ has the
/// one non-zero eigenvalue m = R/3. A rotation of every group by one 3×3 commutes with it.
template <int R>
void applyEdgeMetric(Eigen::Matrix<double, R, R>& S, bool inverse) {
  constexpr double m = R / 3;
  const double root = std::sqrt(1.0 + m);
  const double c = inverse ? (1.0 / root - 1.0) / m : (root - 1.0) / m;
  addBlockRowSums(S, c);
  S.transposeInPlace();
  addBlockRowSums(S, c);
}

/// The projection of a translation-invariant block, computed at (N − 3)³ cost and equal to the projection of
/// the whole block. With H = Lᵀ H_e L and L Lᵀ = (I + 11ᵀ) ⊗ I₃ =: M², the vectors u = Lᵀ M⁻¹ v, v the
/// eigenvectors of S = M H_e M, are orthonormal eigenvectors of H with S's eigenvalues, and the rest of H's
/// spectrum is the translations' zeros. So P(H) = Lᵀ M⁻¹ P(S) M⁻¹ L.
template <int N>
void projectPsdTranslationInvariant(Eigen::Matrix<double, N, N>& H, PsdProjection mode) {
  constexpr int R = N - 3;
  using Reduced = Eigen::Matrix<double, R, R>;
  Reduced S = H.template bottomRightCorner<R, R>();
  applyEdgeMetric(S, false);
  projectSpectrum(S, mode);
  applyEdgeMetric(S, true);
  H.template bottomRightCorner<R, R>() = S;
  completeTranslationInvariant(H);
}

/// Projects the symmetric block H in place. Returns true when the block was changed.
/// Early exits: diagonal dominance, then a Cholesky factorization (positive definite blocks are kept). A block
/// with a translation null space (membrane, bending, contact pairs) is judged by its edge-space block and
/// projected through it, to the same result as a whole-block projection. (Projecting the edge-space block in
/// its own metric, Lᵀ P(H_e) L, is a different PSD approximation: on the T-shirt's landing, under the
/// 4-iteration cap, its directions let the shirt press 4.4 mm below the plane against 1.9 mm.)
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
  if constexpr (N % 3 == 0 && N >= 6) {
    if (judged) {
      projectPsdTranslationInvariant(H, mode);
      return true;
    }
  }
  projectSpectrum(H, mode);
  return true;
}

// The block sizes of the shipped terms (a vertex, a pair, a face, a hinge, five- and six-vertex stencils) are
// instantiated once, in psd_projection.cpp: their fixed-size eigen-solvers are among the slowest code to compile,
// and every element term would otherwise compile its own copy. Other sizes instantiate where they are used.
#define JETSHELL_PSD_PROJECTION_SIZES(X) X(3) X(6) X(9) X(12) X(15) X(18)
#define JETSHELL_DECLARE_PSD_PROJECTION(N) extern template bool projectPsd<N>(Eigen::Matrix<double, N, N>&, PsdProjection);
JETSHELL_PSD_PROJECTION_SIZES(JETSHELL_DECLARE_PSD_PROJECTION)
#undef JETSHELL_DECLARE_PSD_PROJECTION

}  // namespace jetshell
