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

}  // namespace

bool takenInParts(const StepReport& r) { return r.cuts > 0 || r.parts > 1; }

StepErrorCheck checkStepError(const StepReport& taken, DynamicsSolver& run, DynamicsSolver& tight,
                              const DynamicsSolver::Snapshot& before) {
  StepErrorCheck c;
  if (!wholeStep(taken)) return c;  // the passes are of its parts: no one solve to compare
  tight.restore(before);
  tight.startNextSolveFrom(run.positions());
  c.tight = tight.step();
  c.solvedAgain = true;
  // A tight solve accepted at its iteration cap is no reference either.
  if (!wholeStep(c.tight) || !c.tight.solves.front().converged()) return c;
  const Eigen::VectorXd& m = run.system().vertexMass();
  const Eigen::VectorXd predictor = before.x + taken.timeStep * before.v;
  c.error = massWeightedRms(m, run.positions() - tight.positions());
  c.change = massWeightedRms(m, tight.positions() - predictor);
  c.checked = true;
  return c;
}

StepErrorCheck checkPartError(const SubstepView& part, DynamicsSolver& tight) {
  StepErrorCheck c;
  if (part.bdf2) return c;  // not a part: the halves of a step are backward Euler
  const double h = part.timeStep, own = tight.options().timeStep;
  tight.restore({*part.xStart, *part.vStart, Eigen::VectorXd(), Eigen::VectorXd(), part.time, 0.0, 0, false});
  tight.setTimeStep(h);
  tight.startNextSolveFrom(*part.x);
  c.tight = tight.step();
  tight.setTimeStep(own);
  c.solvedAgain = true;
  if (!wholeStep(c.tight) || !c.tight.solves.front().converged()) return c;
  const Eigen::VectorXd& m = tight.system().vertexMass();
  const Eigen::VectorXd predictor = *part.xStart + h * *part.vStart;
  c.error = massWeightedRms(m, *part.x - tight.positions());
  c.change = massWeightedRms(m, tight.positions() - predictor);
  c.checked = true;
  return c;
}

}  // namespace jetshell
