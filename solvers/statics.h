// Static equilibrium: load stepping in the load factor λ, and dynamic relaxation.
//
// Load stepping solves min E(x; λ) for λ rising to the target in increments, each from the previous
// equilibrium: the nodal forces are scaled by λ (NodalForceTerm::setLoadFactor) and prescribed positions are
// evaluated at "time" λ, so a prescribed displacement ramps with the loads. Gravity is not scaled (it has no
// load factor). A step that fails (Newton not converged: iteration cap, line-search or linear-solver failure,
// non-finite values) is cut: x returns to the last equilibrium, the increment halves, and it is retried; after
// a step that converged in few iterations the increment grows. Every accepted step is kept.
// Where the load path has a limit point (snap-through), load control cannot pass it: the increments are cut
// down to minIncrement and the run stops there with the last equilibrium kept; dynamic relaxation (below)
// is the way across.
#pragma once

#include "solvers/newton.h"
#include "solvers/shell_system.h"
#include "solvers/solver_summary.h"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace jetshell {

struct LoadSteppingOptions {
  double targetLoadFactor = 1.0;
  double initialIncrement = 1.0;  // first Δλ (clipped to the target)
  double minIncrement = 1e-4;     // give up below this Δλ
  double maxIncrement = 1.0;
  double growth = 1.5;            // Δλ ×= growth after a step that took <= easyIterations Newton iterations
  int easyIterations = 6;
  NewtonOptions newton;
};

struct LoadStepResult {
  int step = 0;             // accepted-step index, from 0
  double loadFactor = 0.0;  // λ reached
  Eigen::VectorXd x;        // the equilibrium (3N)
  SolverSummary summary;    // the Newton solve that reached it
  int cuts = 0;             // failed attempts before this step was accepted
};

struct StaticsResult {
  bool completed = false;  // the target λ was reached
  bool stopped = false;    // the callback asked to stop
  double loadFactor = 0.0;
  std::vector<LoadStepResult> steps;
  int totalCuts = 0;
  int newtonIterations = 0;
  std::vector<SolverSummary> failedSolves;  // the attempts that were cut (without their traces)
  std::vector<std::string> activeTerms;
  std::string message;
};

/// Called after each accepted load step; return false to stop cleanly (the result keeps the steps so far).
using LoadStepCallback = std::function<bool(const LoadStepResult&)>;

/// Load stepping from x (3N, in/out: on return the last equilibrium; prescribed values are applied at each λ).
/// loads may be null (then λ only drives the prescribed positions). Throws InputError for invalid options.
StaticsResult solveStatics(Objective& objective, NodalForceTerm* loads, Eigen::VectorXd& x,
                           const LoadSteppingOptions& options, const LoadStepCallback& callback = {});
/// The same on a ShellSystem built for AnalysisKind::Statics.
StaticsResult solveStatics(ShellSystem& system, Eigen::VectorXd& x, const LoadSteppingOptions& options,
                           const LoadStepCallback& callback = {});

}  // namespace jetshell
