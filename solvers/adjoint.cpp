#include "solvers/adjoint.h"

namespace jetshell {

Eigen::VectorXd adjointGradient(EquilibriumSensitivity& sensitivity, const Eigen::VectorXd& dfdx,
                                const Eigen::MatrixXd& mixed) {
  const Eigen::VectorXd lambda = sensitivity.solve(dfdx);
  return -(mixed.transpose() * lambda);
}

Eigen::MatrixXd forwardSensitivities(EquilibriumSensitivity& sensitivity, const Eigen::MatrixXd& mixed) {
  Eigen::MatrixXd S(mixed.rows(), mixed.cols());
  for (Eigen::Index c = 0; c < mixed.cols(); ++c) S.col(c) = -sensitivity.solve(mixed.col(c));
  return S;
}

}  // namespace jetshell
