// PSD projection of a membrane face's Hessian, split into its in-plane and normal parts.
//
// The membrane energy depends on the positions only through the metric a(e0, e1) = [e0·e0, e0·e1, e1·e1], so its
// edge-space Hessian (6×6 over e0 = x1 − x0, e1 = x2 − x0) is
//   He = Jaᵀ W'' Ja + G ⊗ I₃,   G = [[2 w0, w1], [w1, 2 w2]],  w = ∂W/∂a.
// Every row of Ja is made of e0 and e1, which lie in the face's plane. In a basis (t1, t2, n) of the face, He
// therefore has no entry coupling an in-plane component with a normal one: it is a 4×4 in-plane block plus the
// 2×2 normal block G. The projection's metric, (I + c 11ᵀ) ⊗ I₃ (core/psd_projection.h), acts on the edge index
// only and keeps the split. So the projection of the face's 9×9 block equals projectPsd<9>'s, computed with a
// 4×4 and a 2×2 eigen-decomposition instead of a 6×6 one. The 2×2 is in closed form; the 4×4 has (on 99.9% of
// the T-shirt's compressed faces) one negative eigenvalue, whose eigenvector is close to the in-plane rotation
// of the edges, which stretches nothing: projectSingleNegative finds it from there (core/psd_projection.h), and
// the full eigen-solver takes the rest.
#pragma once

#include "core/psd_projection.h"

#include <Eigen/Core>

namespace jetshell {

enum class MembraneProjection {
  Kept,        ///< He was positive definite (or not finite) and is unchanged, as projectPsd<9> leaves it
  Projected,   ///< He was replaced by its projection
  Degenerate,  ///< the face has no plane (e0 ≈ 0 or e1 ∥ e0): He is unchanged, project the 9×9 block instead
};

/// Projects the edge-space block He of a face with edges e0, e1 in place (see above).
MembraneProjection projectMembraneEdgeBlock(Eigen::Matrix<double, 6, 6>& He, const Eigen::Vector3d& e0,
                                            const Eigen::Vector3d& e1, PsdProjection mode);

}  // namespace jetshell
