#include "solvers/step_error_check.h"

#include <algorithm>
#include <cmath>

namespace jetshell {

DynamicsOptions tightStepOptions(const DynamicsOptions& run) {
  DynamicsOptions t = run;
  t.updateTolerance = kTightUpdateTolerance;
  t.contactCorrectionFraction = 0.0;
  t.newton.maxIterations = std::max(run.newton.maxIterations, 50);
  t.acceptIterationCap = false;
  t.maxCuts = 0;
  t.newton.linear.type = LinearSolverType::Cholmod;
  t.newton.adaptiveLinearTolerance = false;
  t.newton.exactFirstProjectedDofs = 0;
  return t;
}

double massWeightedRms(const Eigen::VectorXd& mass, const Eigen::VectorXd& u) {
  double sq = 0.0;
  for (Eigen::Index v = 0; v < mass.size(); ++v) sq += mass[v] * u.segment<3>(3 * v).squaredNorm();
  const double total = mass.sum();
  return total > 0.0 ? std::sqrt(sq / total) : 0.0;
}

namespace {

/// One Newton solve over the whole Δt: no cut, no part, nothing solved again from x_n.
bool wholeStep(const StepReport& r) {
  return r.success && r.cuts == 0 && r.substeps == 1 && r.parts == 1 && r.solves.size() == 1;
}

/// `tight`, already set to the step's (or part's) start and Δt = h, solves on from the run's accepted iterate x to
/// its tight tolerance; the distance between x and that solution, and the solution's change against the
/// predictor x_n + h v_n. A tight solve that is not one converged Newton solve (cut, moved on at its cap, or done
/// again from x_n) is no reference: nothing is checked.
StepErrorCheck solveOnFrom(DynamicsSolver& tight, const Eigen::VectorXd& x, const Eigen::VectorXd& xStart,
                           const Eigen::VectorXd& vStart, double h) {
  StepErrorCheck c;
  tight.startNextSolveFrom(x);
  c.tight = tight.step();
  c.solvedAgain = true;
  if (!wholeStep(c.tight) || !c.tight.solves.front().converged()) return c;
  const Eigen::VectorXd& m = tight.system().vertexMass();
  c.error = massWeightedRms(m, x - tight.positions());
  c.change = massWeightedRms(m, tight.positions() - (xStart + h * vStart));
  c.checked = true;
  return c;
}

}  // namespace

bool takenInParts(const StepReport& r) { return r.cuts > 0 || r.parts > 1; }

StepErrorCheck checkStepError(const StepReport& taken, DynamicsSolver& run, DynamicsSolver& tight,
                              const DynamicsSolver::Snapshot& before) {
  if (!wholeStep(taken)) return {};  // the passes are of its parts: no one solve to compare
  tight.restore(before);
  return solveOnFrom(tight, run.positions(), before.x, before.v, taken.timeStep);
}

StepErrorCheck checkPartError(const SubstepView& part, DynamicsSolver& tight) {
  if (part.bdf2) return {};  // not a part: the halves of a step are backward Euler
  const double own = tight.options().timeStep;
  tight.restore({*part.xStart, *part.vStart, Eigen::VectorXd(), Eigen::VectorXd(), part.time, 0.0, 0, false});
  tight.setTimeStep(part.timeStep);
  const StepErrorCheck c = solveOnFrom(tight, *part.x, *part.xStart, *part.vStart, part.timeStep);
  tight.setTimeStep(own);
  return c;
}

}  // namespace jetshell
