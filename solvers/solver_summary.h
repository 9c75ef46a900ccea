// What a minimization did, in the spirit of Ceres' Solver::Summary: why it stopped, the energies and residuals,
// the time per phase, and one record per iteration.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace jetshell {

enum class TerminationReason {
  Converged,            // a convergence test passed
  IterationCap,         // maxIterations reached without convergence
  LineSearchFailure,    // no acceptable step along the search direction
  LinearSolverFailure,  // the Newton system could not be solved, even regularized
  NonFinite,            // a non-finite energy or gradient at the current point, or along every trial step
  Stalled,              // the Newton step no longer changes anything, but the residual is above its tolerance
};
const char* toString(TerminationReason r);

/// One Newton (or L-BFGS) iteration: values at the start of the iteration, then what the step did.
struct IterationRecord {
  int iteration = 0;
  double energy = 0.0;
  double residual = 0.0;   // ‖g_free‖∞ [N]
  double decrement = 0.0;  // ½ gᵀH⁻¹g [J] (Newton) or 0
  double stepLength = 0.0;  // the accepted α
  /// The largest vertex displacement of the accepted step, max_v ‖α d_v‖ [m] (0 when no step was taken): how far
  /// Newton still moved some vertex, the iterate's error scale while Newton contracts.
  double largestMove = 0.0;
  int lineSearchEvaluations = 0;
  int regularizations = 0;  // linear-solver retries with a diagonal shift
  double shift = 0.0;
  int cgIterations = 0;
  int numericFactorizations = 0;
  bool exactHessian = false;  // the step's direction came from the unprojected ("exact") Hessian
  /// With exact-first (NewtonOptions::exactHessianFirst): and not even its small blocks were projected
  /// (NewtonOptions::unprojectedNearSolution).
  bool unprojected = false;
  /// The exact Hessian was tried and found indefinite (or its direction did not descend), so the direction came
  /// from the projected one; cgIterations counts both solves.
  bool projectionFallback = false;
  int directFallbacks = 0;  // PCG solves finished with the whole Hessian's factor (LinearSolverOptions::cgDirectAfter)
  double assemblySeconds = 0.0;
  double factorizationSeconds = 0.0;
  /// The preconditioner's factorization run during the assembly (NewtonOptions::overlapPreconditioner): its
  /// own time, inside assemblySeconds' wall time and not in factorizationSeconds.
  double overlappedFactorizationSeconds = 0.0;
  double solveSeconds = 0.0;
  double lineSearchSeconds = 0.0;
};

struct SolverSummary {
  std::string minimizer;     // "newton" or "lbfgs"
  std::string linearSolver;  // Newton only
  TerminationReason reason = TerminationReason::IterationCap;
  std::string message;        // how it converged, or why not
  int iterations = 0;         // steps taken
  double initialEnergy = 0.0, finalEnergy = 0.0;
  double initialResidual = 0.0, finalResidual = 0.0;  // ‖g_free‖∞ [N]
  double finalDecrement = 0.0;                          // [J]
  double residualThreshold = 0.0;   // the residual test in N: max(tolerance × force scale, round-off floor)
  double decrementThreshold = 0.0;  // the stall test in J (tolerance × force scale × length scale)
  double forceScale = 0.0;          // N: the force the residual is judged against (Objective::forceScale)
  std::string forceScaleSource;     // where forceScale came from
  double roundOffFloor = 0.0;       // N: the residual round-off alone can leave (0 while below the tolerance)
  std::string convergenceTest;      // when converged: "residual", "round_off" (solvers/newton.h), or "iterate"
                                    // (a time step's update test, in m)
  std::string iterateEstimate;      // with "iterate": the estimate that passed (solvers/dynamics.h: "residual
                                    // estimate" or "Newton correction")
  double iterateThreshold = 0.0;    // with "iterate": the threshold [m] that estimate passed
  bool discarded = false;           // its result was not kept: it ended above the time step's previous
                                    // positions, and the step was solved again from them (solvers/dynamics.h)

  double assemblySeconds = 0.0;       // energy + gradient + Hessian at the iterates
  double factorizationSeconds = 0.0;  // symbolic + numeric factorization or preconditioner
  double solveSeconds = 0.0;          // triangular solves or CG
  double lineSearchSeconds = 0.0;     // trial evaluations
  double totalSeconds = 0.0;
  int symbolicAnalyses = 0;  // done during this minimization
  int numericFactorizations = 0;  // Cholesky factorizations (fewer than iterations with a lagged factor)
  int regularizations = 0;   // diagonal-shift retries during this minimization
  int exactHessianSteps = 0;     // Newton steps taken with the unprojected Hessian
  int projectionFallbacks = 0;   // unprojected Hessians found indefinite and reassembled projected
  /// Of exactHessianSteps and projectionFallbacks: those of Hessians with nothing projected, tried by exact-first
  /// near a solution (NewtonOptions::unprojectedNearSolution).
  int unprojectedSteps = 0, unprojectedFallbacks = 0;
  /// The last Hessian this solve factored was the true one (unprojected, exact model) and a direct solver factored
  /// it unshifted (LinearSolveReport::positiveDefinite): the equilibrium reached next to it is a minimum of the
  /// energy, not a saddle. False when the solve factored nothing (it converged at its start, or only reused an
  /// earlier factor), or shifted, projected or solved iteratively (solvers/statics.h: checkStability).
  bool lastHessianPositiveDefinite = false;
  int directFallbacks = 0;       // PCG solves that spent LinearSolverOptions::cgDirectAfter and factored H whole
  int nonFiniteTrials = 0;       // line-search trial points rejected for a non-finite energy or gradient
  int energyEvaluations = 0, gradientEvaluations = 0, hessianEvaluations = 0;
  std::vector<IterationRecord> trace;

  bool converged() const { return reason == TerminationReason::Converged; }
  /// One line: reason, iterations, residual, energy, time.
  std::string briefReport() const;
  /// A table of the iterations and the phase times. Its H column names each step's Hessian: u nothing projected
  /// (NewtonOptions::unprojectedNearSolution), e exact (exact-first keeps blocks of up to
  /// NewtonOptions::exactFirstProjectedDofs projected), f projected after an exact one was found indefinite,
  /// p projected.
  std::string fullReport() const;
};

/// The summary as JSON (trace included when withTrace).
nlohmann::json toJson(const SolverSummary& summary, bool withTrace = false);

}  // namespace jetshell
