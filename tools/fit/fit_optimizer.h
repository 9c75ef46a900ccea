// Minimizes a static fit's misfit: NLopt's BOBYQA and Nelder–Mead (derivative-free), L-BFGS and MMA (adjoint
// gradients), or a Levenberg–Marquardt outer loop on the least-squares residuals (forward-sensitivity
// Jacobians); then the Gauss–Newton uncertainty of the fitted values.
//
// The optimizers work on scaled variables z: z = ln q for a log-scale parameter, z = q / s otherwise (s = |initial
// value|, or the bound width when it is 0), so every z is O(1) and one tolerance serves all: the parameter
// tolerance is an absolute step in z (for log-scale parameters, a relative change of q).
//
// Inputs: a FitProblem (static or dynamic), the parameters' initial values, bounds and scales, FitOptions.
// Outputs: FitResult (best values, history of every evaluation, NLopt's or the loop's termination reason,
// cost counters, uncertainty).
#pragma once

#include "tools/fit/fit_options.h"
#include "tools/fit/fit_problem.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace jetshell {

/// One forward evaluation.
struct FitRecord {
  int evaluation = 0;          // 1-based
  Eigen::VectorXd q;           // parameter values
  double misfit = 0.0;
  double gradientNorm = -1.0;  // ‖df/dq‖ (physical units), -1 when not computed
  bool ok = true;              // the solve succeeded
  bool exactGradient = true;   // false: derivatives computed through unconverged solves (FitEvaluation)
  bool best = false;           // the best so far when it was made
};

struct FitUncertainty {
  bool available = false;
  std::string message;             // why not, or what the variance is based on
  double residualVariance = 0.0;   // s² = 2f / (M − Q)
  Eigen::VectorXd standardDeviation;
  Eigen::MatrixXd correlation;
};

struct FitResult {
  FitAlgorithm algorithm = FitAlgorithm::LevenbergMarquardt;
  bool success = false;        // the optimizer stopped on a tolerance (not on a failure or the evaluation cap)
  bool interrupted = false;    // FitOptions::stopRequested stopped it (termination "INTERRUPTED")
  std::string termination;     // NLopt's result name (NLOPT_XTOL_REACHED, ...) or the loop's reason
  std::string message;
  int iterations = 0;          // Levenberg–Marquardt iterations, or NLopt evaluations
  std::vector<FitVariable> variables;
  Eigen::VectorXd q;           // best values
  double misfit = 0.0;         // at q
  Eigen::VectorXd residuals;   // at q
  Eigen::MatrixXd jacobian;    // at q (for the uncertainty), M × Q
  std::vector<Eigen::VectorXd> equilibria;  // at q, per level
  std::vector<FitRecord> history;
  FitCounters counters;        // of the optimization (the final Jacobian for the uncertainty is not included)
  FitUncertainty uncertainty;
  /// Evaluations whose derivatives went through solves accepted short of convergence (dynamic steps at the
  /// iteration cap): their gradients and Jacobians are approximate. 0: every derivative was exact.
  int inexactDerivativeEvaluations = 0;
  double wallSeconds = 0.0;
};

/// Runs the fit. Throws InputError for invalid variables (bounds not finite or not ordered, initial value out
/// of bounds, a log-scale bound <= 0) or options.
FitResult runFit(FitProblem& problem, const std::vector<FitVariable>& variables, const FitOptions& options);

/// The Gauss–Newton covariance s²(JᵀJ)⁻¹ as standard deviations and correlations (J: M × Q, r: M).
FitUncertainty gaussNewtonUncertainty(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residuals);

}  // namespace jetshell
