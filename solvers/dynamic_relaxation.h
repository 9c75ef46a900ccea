// Dynamic relaxation: pseudo-time stepping with mass damping toward a static equilibrium, the way the engine
// the spec comes from solves its slit annular plate (backward Euler, Δt = 1/30 s, α_R = 0.3 1/s). Each step
// is a damped implicit dynamic step; the run ends when the static residual (the gradient of the potential
// terms alone: elastic energy, gravity, loads) is below residualTolerance × the force scale. Unlike load
// stepping it passes limit points (snap-through) and needs no load increments, at the price of many steps.
#pragma once

#include "solvers/dynamics.h"
#include "solvers/shell_system.h"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace jetshell {

struct RelaxationOptions {
  double timeStep = 1.0 / 30.0;  // pseudo-time step [s]
  double massDamping = 0.0;      // α [1/s]; 0 takes the material's α_R (one of the two must be > 0)
  int maxSteps = 10000;
  double residualTolerance = 1e-6;  // static residual ‖g‖∞ ≤ tolerance × force scale [N]
  double loadFactor = 1.0;          // λ for the nodal forces and the weight
  /// Take each step's static residual from the gradient the step's Newton solve already evaluated at its last
  /// iterate (Objective::lastPotentialGradient) instead of evaluating the potential terms again; false: always
  /// evaluate them (the same residual, one more gradient per step).
  bool reuseStepGradient = true;
  /// Modified Newton in every step (NewtonOptions::reuseFactor, set here over newton's): a relaxation's Hessian
  /// changes slowly, so a step's Newton iterations start from the factor an earlier step left and assemble and
  /// factor anew only when it stops contracting. Each step still meets the same Newton tests. With CHOLMOD only
  /// (newton.linear Cholmod, or Auto resolving to it): other solvers keep no factor. false: newton's own setting
  /// (a fresh Hessian and factor at every iteration by default).
  bool reuseFactor = true;
  /// An equilibrium reached is checked as load control checks one (solvers/stability_check.h): the potential
  /// terms' exact Hessian is factored (LDLᵀ) and its negative eigenvalues counted. From a saddle (a sheet or a
  /// column in compression that a symmetric start keeps flat or straight to round-off: relaxation from rest does
  /// not break the symmetry) the state moves by saddleStep × the mean edge length along negative curvature, at rest,
  /// and relaxes on, up to saddleEscapes times, within maxSteps. A saddle kept is reported
  /// (RelaxationResult::negativeEigenvalues > 0).
  bool checkStability = true;
  int saddleEscapes = 3;
  double saddleStep = 0.1;
  NewtonOptions newton;
};

struct RelaxationResult {
  bool converged = false;
  bool stopped = false;
  int steps = 0;
  double pseudoTime = 0.0;
  double staticResidual = 0.0;     // ‖g_potential‖∞ at the end [N]
  double residualThreshold = 0.0;  // [N]: residualTolerance × forceScale
  double forceScale = 0.0;         // [N] (Objective::forceScale)
  std::string forceScaleSource;
  std::vector<double> residualHistory;  // after each step
  int newtonIterations = 0;
  int cuts = 0;
  int reusedGradients = 0;  // static residuals read from the step's own last gradient (reuseStepGradient)
  int negativeEigenvalues = -1;  // of the potential's Hessian at the last equilibrium checked (-1: none checked)
  int saddleEscapes = 0;         // saddles left downhill (checkStability)
  std::vector<std::string> activeTerms;
  std::string message;
};

/// Called after each step with the static residual; return false to stop cleanly.
using RelaxationCallback = std::function<bool(const StepReport&, double staticResidual)>;

/// Relaxes from x (3N, in/out, starting at rest) on a system built for AnalysisKind::DynamicRelaxation.
/// Throws InputError for invalid options or a system of another kind.
RelaxationResult relaxToStatic(ShellSystem& system, Eigen::VectorXd& x, const RelaxationOptions& options,
                               const RelaxationCallback& callback = {});

}  // namespace jetshell
