#include "solvers/time_step_policy.h"

#include "core/mesh.h"

namespace jetshell {

TimeStepPolicy timeStepPolicyFromString(const std::string& name) {
  if (name == "page") return TimeStepPolicy::Page;
  if (name == "jetshell") return TimeStepPolicy::Jetshell;
  if (name == "reference") return TimeStepPolicy::Reference;
  throw InputError("time-step policy '" + name + "': expected page, jetshell or reference");
}

const char* toString(TimeStepPolicy p) {
  switch (p) {
    case TimeStepPolicy::Page: return "page";
    case TimeStepPolicy::Jetshell: return "jetshell";
    case TimeStepPolicy::Reference: return "reference";
  }
  return "?";
}

void applyTimeStepLinearAlgebra(NewtonOptions& n) {
  if (n.linear.type == LinearSolverType::Auto) {
    // Inertia dominates a time step's Hessian: CG preconditioned by the one-ring factor (about a tenth of the
    // full factor's flops) needs a handful of iterations (BENCHMARKS.md "Solver"). The one-ring pattern is the
    // mesh's: contact pairs between distant vertices stay out of the factor, so it is analysed once per run.
    n.linear.type = LinearSolverType::PCG;
    n.linear.preconditioner = Preconditioner::OneRingCholesky;
    n.linear.cgRelativeTolerance = 1e-6;
    // A solve the one-ring factor does not capture (a crushed, tangled shirt: 5,895 iterations) is finished
    // with the whole Hessian's factor instead (BENCHMARKS.md "Contact", session 33).
    n.linear.cgDirectAfter = 100;
    n.adaptiveLinearTolerance = true;
  }
  // Project element Hessians only where the whole system needs it (NewtonOptions::exactHessianFirst).
  if (n.projection != PsdProjection::None) n.exactHessianFirst = true;
}

void applyTimeStepPolicy(TimeStepPolicy policy, DynamicsOptions& o) {
  NewtonOptions& n = o.newton;
  switch (policy) {
    case TimeStepPolicy::Page:
      n.maxIterations = 4;
      n.residualTolerance = 0.0;  // only the page's own tests
      n.decrementTolerance = 0.0;
      n.absoluteResidualTolerance = 1e-3;
      n.relativeResidualTolerance = 1e-6;
      n.lineSearch = LineSearchType::ResidualNorm;
      o.acceptIterationCap = true;
      o.extrapolatedStart = false;
      o.updateTolerance = 0.0;
      return;
    case TimeStepPolicy::Jetshell:
      n.maxIterations = 20;
      n.lineSearch = LineSearchType::BacktrackingArmijo;
      applyTimeStepLinearAlgebra(n);
      o.acceptIterationCap = false;
      o.extrapolatedStart = true;
      o.updateTolerance = jetshellUpdateTolerance;
      o.correctionTest = true;
      return;
    case TimeStepPolicy::Reference:
      n.maxIterations = 200;
      n.residualTolerance = 1e-10;
      n.decrementTolerance = 0.0;
      n.lineSearch = LineSearchType::BacktrackingArmijo;
      o.acceptIterationCap = false;
      o.extrapolatedStart = true;
      o.updateTolerance = 0.0;
      return;
  }
}

}  // namespace jetshell
