// One equilibrium on a path whose load factor is an unknown: Newton's method on the bordered system
//   g(x, λ) = 0,  c(x, λ) = 0
// with one LDLᵀ factor of the tangent stiffness K per iteration and two solves, K a = −g and K b = q
// (q = −∂g/∂λ, the load vector, taken as a difference of gradients in λ so that every load hook and prescribed
// motion counts), then δλ from the linearized constraint and δx = a + δλ b.
//
// Inputs: the objective, the load hooks (λ reaches them and the prescribed positions), the start (x, λ) (the
// predictor), the constraint, Newton's tolerances and iteration cap. Outputs: (x, λ) in place, replaced only
// by finite iterates, and a SolverSummary (minimizer "path_newton") whose convergence is the same residual test
// as Newton's (‖g_free‖∞ ≤ residualTolerance × the objective's force scale; solvers/newton.h): a solve that
// stops without passing it says why and is never reported as converged. There is no line search (the bordered
// system is not a minimization); a step that diverges or stalls fails and the path cuts its increment.
// Also out: the negative pivots of the last factor (the count of K's negative eigenvalues near the solution).
#pragma once

#include "solvers/indefinite_factor.h"
#include "solvers/newton.h"
#include "solvers/objective.h"
#include "solvers/solver_summary.h"

#include <Eigen/Core>

#include <functional>
#include <vector>

namespace jetshell {

struct LoadFactorHooks;

/// The extra equation of the bordered system.
struct PathConstraint {
  enum class Kind { LoadFactor, Displacement, ArcLength } kind = Kind::LoadFactor;
  double loadFactor = 0.0;               // LoadFactor: λ is held here
  int dof = -1;                          // Displacement: x[dof] is held at value
  double value = 0.0;
  const Eigen::VectorXd* anchor = nullptr;  // ArcLength: the last equilibrium (x, λ) ...
  double anchorLoadFactor = 0.0;
  double radius = 0.0;                   // ... and the distance to keep from it
  double loadWeight = 0.0;               // ψ² ‖q‖²: the weight of Δλ² in the distance
};

struct PathCorrection {
  SolverSummary summary;
  int negativePivots = -1;  // of the last factor (-1: none made)
  Eigen::VectorXd gradient; // g at the returned (x, λ) when converged (the tangent's load vector starts from it)
};

/// Corrects (x, λ) onto the path. hooks.set(λ) and the prescribed positions at λ are applied at every iterate.
PathCorrection correctOnPath(Objective& objective, const LoadFactorHooks& hooks, IndefiniteFactor& factor,
                             Eigen::VectorXd& x, double& lambda, const PathConstraint& constraint,
                             const NewtonOptions& options);

/// Σ a_i b_i over the free dofs (fixed[i] == 0): the metric of the arc length.
double freeDot(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const std::vector<char>& fixed);

/// The load vector q = −∂g/∂λ at (x, λ) (free dofs; fixed entries zero), from g at λ and at λ + h (h = 1e-6 ×
/// max(1, |λ|)): exact for loads linear in λ. g is the gradient at (x, λ). Leaves the hooks at λ.
Eigen::VectorXd loadVector(Objective& objective, const LoadFactorHooks& hooks, const Eigen::VectorXd& x,
                           double lambda, const Eigen::VectorXd& g, const EvalOptions& evalOptions);

}  // namespace jetshell
