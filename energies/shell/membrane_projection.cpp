#include "energies/shell/membrane_projection.h"

#include <Eigen/Cholesky>

namespace jetshell {

namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Rows/columns of the rotated edge-space block: edge k's components along t1, t2 (in-plane) and n (normal).
constexpr int kInPlane[4] = {0, 1, 3, 4};
constexpr int kNormal[2] = {2, 5};

// The split's own PD test: a part that is positive definite is its own projection.
template <int N>
void projectPart(Eigen::Matrix<double, N, N>& A, PsdProjection mode) {
  if (Eigen::LLT<Eigen::Matrix<double, N, N>>(A).info() == Eigen::Success) return;
  projectSpectrum<N>(A, mode);
}

}  // namespace

MembraneProjection projectMembraneEdgeBlock(Matrix6d& He, const Eigen::Vector3d& e0, const Eigen::Vector3d& e1,
                                            PsdProjection mode) {
  if (mode == PsdProjection::None || !He.allFinite()) return MembraneProjection::Kept;
  if (Eigen::LLT<Matrix6d>(He).info() == Eigen::Success) return MembraneProjection::Kept;

  // The face's orthonormal frame (t1 along e0, t2 in the plane, n normal).
  const double l0 = e0.norm();
  if (!(l0 > 0.0)) return MembraneProjection::Degenerate;
  const Eigen::Vector3d t1 = e0 / l0;
  const Eigen::Vector3d w = e1 - e1.dot(t1) * t1;
  const double lw = w.norm();
  if (!(lw > 1e-12 * (l0 + e1.norm()))) return MembraneProjection::Degenerate;
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
  projectPart<4>(inPlane, mode);
  projectPart<2>(normal, mode);
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
