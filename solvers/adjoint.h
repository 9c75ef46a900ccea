// Gradients of functions of a static equilibrium with respect to term parameters, by the adjoint
// (implicit-function) method, and the forward sensitivities a Gauss–Newton Jacobian needs.
//
// For f(x*(p)) with x*(p) an equilibrium (g(x*, p) = 0) and H = ∂g/∂x symmetric:
//   adjoint:  H λ = ∂f/∂x  (one solve, any number of parameters),  df/dp = −λᵀ ∂g/∂p
//   forward:  H S = −∂g/∂p (one solve per parameter),               dx*/dp = S
// Both use EquilibriumSensitivity's factor of the exact Hessian at x* (solvers/sensitivity.h). An explicit
// ∂f/∂p, when f depends on p directly, is added by the caller.
//
// Inputs: sensitivity (factored at x*), ∂f/∂x (3N), ∂g/∂p (3N × P). Outputs: df/dp (P) or dx*/dp (3N × P).
#pragma once

#include "solvers/sensitivity.h"

#include <Eigen/Core>

namespace jetshell {

/// df/dp = −(H⁻¹ ∂f/∂x)ᵀ ∂g/∂p: one linear solve.
Eigen::VectorXd adjointGradient(EquilibriumSensitivity& sensitivity, const Eigen::VectorXd& dfdx,
                                const Eigen::MatrixXd& mixed);

/// dx*/dp = −H⁻¹ ∂g/∂p: one linear solve per column.
Eigen::MatrixXd forwardSensitivities(EquilibriumSensitivity& sensitivity, const Eigen::MatrixXd& mixed);

}  // namespace jetshell
