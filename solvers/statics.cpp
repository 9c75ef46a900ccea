#include "solvers/statics.h"

#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace jetshell {
namespace {

void check(bool ok, const char* field, double value, const char* rule) {
  if (ok) return;
  std::ostringstream s;
  s << "load stepping: " << field << " = " << value << ": " << rule;
  throw InputError(s.str());
}

}  // namespace

StaticsResult solveStatics(Objective& objective, NodalForceTerm* loads, Eigen::VectorXd& x,
                           const LoadSteppingOptions& o, const LoadStepCallback& callback) {
  check(std::isfinite(o.targetLoadFactor), "targetLoadFactor", o.targetLoadFactor, "must be finite");
  check(o.minIncrement > 0.0, "minIncrement", o.minIncrement, "must be > 0");
  check(o.maxIncrement >= o.minIncrement, "maxIncrement", o.maxIncrement, "must be >= minIncrement");
  check(o.initialIncrement >= o.minIncrement, "initialIncrement", o.initialIncrement, "must be >= minIncrement");
  check(o.growth >= 1.0, "growth", o.growth, "must be >= 1");
  if (x.size() != objective.numDofs()) throw InputError("load stepping: x has the wrong size");

  StaticsResult result;
  result.activeTerms = objective.activeTermNames();
  NewtonSolver newton(objective, o.newton);
  const double target = o.targetLoadFactor;
  const double direction = target >= 0.0 ? 1.0 : -1.0;
  double lambda = 0.0;
  double increment = std::min(o.initialIncrement, o.maxIncrement);
  int cuts = 0;
  Eigen::VectorXd trial;
  // At least one solve, even for a target of 0 (gravity or prescribed positions alone).
  while (result.steps.empty() || direction * (target - lambda) > 1e-12 * std::max(1.0, std::abs(target))) {
    const double next = direction * std::min(direction * (target - lambda), increment) + lambda;
    trial = x;
    objective.applyPrescribed(next, trial);
    if (loads != nullptr) loads->setLoadFactor(next);
    SolverSummary summary = newton.minimize(trial);
    result.newtonIterations += summary.iterations;
    if (!summary.converged()) {
      summary.trace.clear();
      result.failedSolves.push_back(summary);
      ++cuts;
      ++result.totalCuts;
      increment *= 0.5;
      if (increment < o.minIncrement) {
        if (loads != nullptr) loads->setLoadFactor(lambda);
        std::ostringstream s;
        s << "load step to lambda = " << next << " failed (" << toString(summary.reason) << ": " << summary.message
          << ") with the increment cut below " << o.minIncrement << "; stopped at lambda = " << lambda;
        result.message = s.str();
        result.loadFactor = lambda;
        return result;
      }
      continue;
    }
    lambda = next;
    x = trial;
    LoadStepResult step;
    step.step = static_cast<int>(result.steps.size());
    step.loadFactor = lambda;
    step.x = x;
    step.cuts = cuts;
    const bool easy = summary.iterations <= o.easyIterations;
    step.summary = std::move(summary);
    result.steps.push_back(std::move(step));
    cuts = 0;
    if (easy) increment = std::min(o.maxIncrement, increment * o.growth);
    result.loadFactor = lambda;
    if (callback && !callback(result.steps.back())) {
      result.stopped = true;
      result.message = "stopped by the callback at lambda = " + std::to_string(lambda);
      return result;
    }
  }
  result.completed = true;
  result.loadFactor = target;
  std::ostringstream s;
  s << "reached lambda = " << target << " in " << result.steps.size() << " steps (" << result.totalCuts << " cuts, "
    << result.newtonIterations << " Newton iterations)";
  result.message = s.str();
  return result;
}

StaticsResult solveStatics(ShellSystem& system, Eigen::VectorXd& x, const LoadSteppingOptions& options,
                           const LoadStepCallback& callback) {
  if (system.kind() != AnalysisKind::Statics)
    throw InputError(std::string("solveStatics: the system was built for ") + toString(system.kind()));
  return solveStatics(system.objective(), system.nodalForces.get(), x, options, callback);
}

}  // namespace jetshell
