#include "energies/shell/membrane_projection.h"

#include <Eigen/Cholesky>

#include <cmath>

namespace jetshell {

namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Rows/columns of the rotated edge-space block: edge k's components along t1, t2 (in-plane) and n (normal).
constexpr int kInPlane[4] = {0, 1, 3, 4};
constexpr int kNormal[2] = {2, 5};

// A face without a plane: its block is kept when positive definite, else the caller projects the 9×9 block.
MembraneProjection degenerateUnlessDefinite(const Matrix6d& He) {
  return Eigen::LLT<Matrix6d>(He).info() == Eigen::Success ? MembraneProjection::Kept
                                                             : MembraneProjection::Degenerate;
}

// The split's own PD test: a part that is positive definite is its own projection.
template <int N>
bool positiveDefinite(const Eigen::Matrix<double, N, N>& A) {
  return Eigen::LLT<Eigen::Matrix<double, N, N>>(A).info() == Eigen::Success;
}

}  // namespace

MembraneProjection projectMembraneEdgeBlock(Matrix6d& He, const Eigen::Vector3d& e0, const Eigen::Vector3d& e1,
                                            PsdProjection mode) {
  if (mode == PsdProjection::None || !He.allFinite()) return MembraneProjection::Kept;

  // The face's orthonormal frame (t1 along e0, t2 in the plane, n normal).
  const double l0 = e0.norm();
  if (!(l0 > 0.0)) return degenerateUnlessDefinite(He);
  const Eigen::Vector3d t1 = e0 / l0;
  const Eigen::Vector3d w = e1 - e1.dot(t1) * t1;
  const double lw = w.norm();
  if (!(lw > 1e-12 * (l0 + e1.norm()))) return degenerateUnlessDefinite(He);
  const Eigen::Vector3d t2 = w / lw;
  Eigen::Matrix3d Q;
  Q << t1, t2, t1.cross(t2);

  // S = M (I₂ ⊗ Q)ᵀ He (I₂ ⊗ Q) M with the metric M of projectPsdTranslationInvariant<9>.
  Matrix6d S;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) S.block<3, 3>(3 * i, 3 * j) = Q.transpose() * He.block<3, 3>(3 * i, 3 * j) * Q;
  applyEdgeMetric(S, false);

  Eigen::Matrix4d inPlane;
  Eigen::Matrix2d normal;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) inPlane(i, j) = S(kInPlane[i], kInPlane[j]);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) normal(i, j) = S(kNormal[i], kNormal[j]);
  // He is positive definite exactly when both parts are (the split is a congruence): then it is kept as it is.
  // (This replaces a Cholesky factorization of He itself, which fails on most faces of a draped cloth: any
  // compression makes the normal part, the stress G, indefinite.)
  const bool normalDefinite = positiveDefinite<2>(normal);
  const bool inPlaneDefinite = positiveDefinite<4>(inPlane);
  if (normalDefinite && inPlaneDefinite) return MembraneProjection::Kept;

  if (!normalDefinite) projectSpectrum2(normal, mode);
  if (!inPlaneDefinite) {
    // The in-plane rotation of the face's edges stretches nothing, so the strain part Jaᵀ W'' Ja is blind to it
    // and its stiffness is the stress G alone: it is (nearly always) the eigenvector of the one negative
    // eigenvalue. In S's coordinates it is M⁻¹ r, r = (J p0, J p1) for the in-plane edges p0 = (l0, 0),
    // p1 = (e1·t1, lw) and J the quarter turn.
    const double c = (1.0 / std::sqrt(3.0) - 1.0) / 2.0;  // M⁻¹ = I + c 11ᵀ (⊗ I₂), see applyEdgeMetric
    const Eigen::Vector4d r(0.0, l0, -lw, e1.dot(t1));
    const double sumT1 = r[0] + r[2], sumT2 = r[1] + r[3];
    const Eigen::Vector4d rotation(r[0] + c * sumT1, r[1] + c * sumT2, r[2] + c * sumT1, r[3] + c * sumT2);
    if (!projectSingleNegative<4>(inPlane, rotation, mode)) projectSpectrum<4>(inPlane, mode);
  }
  S.setZero();  // the in-plane/normal coupling is zero (to rounding) and stays zero
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) S(kInPlane[i], kInPlane[j]) = inPlane(i, j);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) S(kNormal[i], kNormal[j]) = normal(i, j);

  applyEdgeMetric(S, true);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) He.block<3, 3>(3 * i, 3 * j) = Q * S.block<3, 3>(3 * i, 3 * j) * Q.transpose();
  return MembraneProjection::Projected;
}

}  // namespace jetshell
