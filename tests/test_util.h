// Helpers shared by the tests: dense derivatives of a term, terms built from the registry on the check meshes,
// rigid motions, and a scoped OpenMP thread count.
#pragma once

#include "tools/checks/check_configurations.h"
#include "tools/checks/derivative_check.h"
#include "energies/registry.h"

#include <Eigen/Geometry>
#include <omp.h>

namespace jetshell::test {

/// Dense symmetric Hessian of a term at x; also returns its gradient and energy.
inline Eigen::MatrixXd denseHessian(EnergyTerm& term, const Eigen::VectorXd& x, const EvalOptions& options,
                                    Eigen::VectorXd& gradient, double& energy) {
  DenseDerivatives d = evaluateDense(term, x, options);
  gradient = std::move(d.gradient);
  energy = d.energy;
  return std::move(d.hessian);
}

/// The registered term built on a check mesh with the default material.
inline EnergyTermPtr buildTerm(const RegisteredTerm& entry, const CheckMesh& m) {
  static const ShellMaterialParams material;
  return entry.make(TermSetup{m.mesh, m.topology, m.reference, material});
}

/// The entry's evaluation options on the given path.
inline EvalOptions optionsFor(const RegisteredTerm& entry, DerivativePath path) {
  EvalOptions o = entry.options;
  o.path = path;
  return o;
}

/// The block-diagonal I⊗R acting on 3N vectors (gradients rotate like positions).
inline Eigen::VectorXd rotateEach(const Eigen::Matrix3d& R, const Eigen::VectorXd& v) {
  return rigidlyMoved(v, R, Eigen::Vector3d::Zero());
}

/// (I⊗R) H (I⊗R)ᵀ.
inline Eigen::MatrixXd rotateHessian(const Eigen::Matrix3d& R, const Eigen::MatrixXd& H) {
  const Eigen::Index n = H.rows() / 3;
  Eigen::MatrixXd out(H.rows(), H.cols());
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) out.block<3, 3>(3 * i, 3 * j) = R * H.block<3, 3>(3 * i, 3 * j) * R.transpose();
  return out;
}

/// Sets the OpenMP thread count for a scope: the check meshes are tiny, so tests that do not test threading
/// run serially (parallel regions only add overhead there).
class ScopedThreads {
 public:
  explicit ScopedThreads(int n) : previous_(omp_get_max_threads()) { omp_set_num_threads(n); }
  ~ScopedThreads() { omp_set_num_threads(previous_); }
  ScopedThreads(const ScopedThreads&) = delete;
  ScopedThreads& operator=(const ScopedThreads&) = delete;

 private:
  int previous_;
};

}  // namespace jetshell::test
