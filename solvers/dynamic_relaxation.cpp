#include "solvers/dynamic_relaxation.h"

#include "core/mesh.h"

#include <cmath>
#include <sstream>

namespace jetshell {

RelaxationResult relaxToStatic(ShellSystem& system, Eigen::VectorXd& x, const RelaxationOptions& o,
                               const RelaxationCallback& callback) {
  if (system.kind() != AnalysisKind::DynamicRelaxation)
    throw InputError(std::string("dynamic relaxation: the system was built for ") + toString(system.kind()));
  const double alpha = o.massDamping > 0.0 ? o.massDamping : system.material().massDampingCoefficient;
  if (!(std::isfinite(alpha) && alpha > 0.0))
    throw InputError("dynamic relaxation: massDamping (or the material's massDampingCoefficient) must be > 0");
  if (o.maxSteps < 1) throw InputError("dynamic relaxation: maxSteps must be >= 1");

  DynamicsOptions d;
  d.integrator = TimeIntegrator::BackwardEuler;
  d.timeStep = o.timeStep;
  d.newton = o.newton;
  // Only CHOLMOD keeps a factor to reuse (LinearSolver::solveWithLastFactor); other solvers stay plain Newton.
  const LinearSolverType type = o.newton.linear.type;
  const bool cholmod = type == LinearSolverType::Cholmod ||
                       (type == LinearSolverType::Auto && x.size() <= o.newton.linear.autoDirectMaxDofs);
  if (o.reuseFactor && cholmod) d.newton.reuseFactor = true;
  d.massDampingOverride = alpha;
  DynamicsSolver solver(system, d);
  solver.setState(x, Eigen::VectorXd::Zero(x.size()), 0.0);
  if (system.nodalForces) system.nodalForces->setLoadFactor(o.loadFactor);
  if (system.gravity) system.gravity->setLoadFactor(o.loadFactor);

  RelaxationResult result;
  result.activeTerms = system.objective().activeTermNames();
  Objective& obj = system.objective();
  Eigen::VectorXd g;
  const EvalOptions evalOptions{o.newton.derivatives};
  // After a step, nothing changed the terms since its Newton solve took its last gradient at the accepted
  // positions: that gradient's potential part is the static residual.
  auto staticResidual = [&](bool afterStep) {
    const Eigen::VectorXd* last =
        afterStep && o.reuseStepGradient ? obj.lastPotentialGradient(solver.positions(), evalOptions.path) : nullptr;
    if (last != nullptr) {
      ++result.reusedGradients;
      return last->lpNorm<Eigen::Infinity>();
    }
    obj.evaluate(solver.positions(), &g, false, evalOptions, TermSelection::PotentialOnly);
    return g.lpNorm<Eigen::Infinity>();
  };
  const double r0 = staticResidual(false);
  const ForceScale F = obj.forceScale(solver.positions(), r0);
  result.forceScale = F.value;
  result.forceScaleSource = F.source;
  result.residualThreshold = o.residualTolerance * F.value;
  result.staticResidual = r0;
  if (r0 <= result.residualThreshold) {
    result.converged = true;
    result.message = "already in equilibrium";
    return result;
  }
  for (int i = 0; i < o.maxSteps; ++i) {
    const StepReport r = solver.step();
    result.newtonIterations += r.newtonIterations;
    result.cuts += r.cuts;
    if (!r.success) {
      result.message = r.message;
      break;
    }
    ++result.steps;
    result.pseudoTime = solver.time();
    x = solver.positions();
    result.staticResidual = staticResidual(true);
    result.residualHistory.push_back(result.staticResidual);
    const bool converged = result.staticResidual <= result.residualThreshold;
    if (callback && !callback(r, result.staticResidual) && !converged) {
      result.stopped = true;
      result.message = "stopped by the callback";
      return result;
    }
    if (converged) {
      result.converged = true;
      break;
    }
  }
  if (result.message.empty()) {
    std::ostringstream s;
    s << (result.converged ? "static residual " : "not converged: static residual ") << result.staticResidual
      << " N (threshold " << result.residualThreshold << " N) after " << result.steps << " steps, "
      << result.newtonIterations << " Newton iterations";
    result.message = s.str();
  }
  return result;
}

}  // namespace jetshell
