#include "solvers/dynamic_relaxation.h"

#include "core/mesh.h"
#include "solvers/stability_check.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace jetshell {

RelaxationResult relaxToStatic(ShellSystem& system, Eigen::VectorXd& x, const RelaxationOptions& o,
                               const RelaxationCallback& callback) {
  if (system.kind() != AnalysisKind::DynamicRelaxation)
    throw InputError(std::string("dynamic relaxation: the system was built for ") + toString(system.kind()));
  const double alpha = o.massDamping > 0.0 ? o.massDamping : system.material().massDampingCoefficient;
  if (!(std::isfinite(alpha) && alpha > 0.0))
    throw InputError("dynamic relaxation: massDamping (or the material's massDampingCoefficient) must be > 0");
  if (o.maxSteps < 1) throw InputError("dynamic relaxation: maxSteps must be >= 1");
  if (o.saddleEscapes < 0 || o.saddleEscapes > 100)
    throw InputError("dynamic relaxation: saddleEscapes = " + std::to_string(o.saddleEscapes) + ": must be in 0..100");
  if (!(std::isfinite(o.saddleStep) && o.saddleStep > 0.0 && o.saddleStep <= 10.0))
    throw InputError("dynamic relaxation: saddleStep = " + std::to_string(o.saddleStep) + ": must be in (0, 10]");

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
  // Its mass is fictitious and its motion overdamped, so its acceleration is smooth however fast the membrane's
  // waves: every step keeps the extrapolated acceleration (the slit ring's relaxation, examples/: 2,062 Newton
  // iterations, against 3,232 from the inertial predictor).
  d.extrapolationWaveLimit = std::numeric_limits<double>::infinity();
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
  IndefiniteFactor factor;  // the stability check's, analysed once per Hessian pattern
  // An equilibrium reached is checked (RelaxationOptions::checkStability); from a saddle the state moves downhill
  // along negative curvature, at rest, and the relaxation goes on, within the same step budget.
  auto unstable = [&](bool mayEscape) {
    if (!o.checkStability) return false;
    const Stability s = assessStability(obj, factor, solver.positions(), o.newton.derivatives, o.saddleStep,
                                        TermSelection::PotentialOnly);
    result.negativeEigenvalues = s.negativeEigenvalues;
    if (s.negativeEigenvalues <= 0 || !mayEscape || result.saddleEscapes == o.saddleEscapes || s.downhill.size() == 0)
      return false;
    ++result.saddleEscapes;
    solver.setState(solver.positions() + s.downhill, Eigen::VectorXd::Zero(x.size()), solver.time());
    x = solver.positions();
    return true;
  };
  if (r0 <= result.residualThreshold && !unstable(true)) {
    result.converged = true;
    result.message = "already in equilibrium";
    if (result.negativeEigenvalues > 0)
      result.message += ", which is unstable (a saddle of the potential energy: " +
                        std::to_string(result.negativeEigenvalues) + " negative eigenvalue(s))";
    return result;
  }
  while (result.steps < o.maxSteps) {
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
    const bool stop = callback && !callback(r, result.staticResidual);
    if (stop && !converged) {
      result.stopped = true;
      result.message = "stopped by the callback";
      return result;
    }
    if (converged && !unstable(!stop)) {  // asked to stop: checked, not left
      result.converged = true;
      break;
    }
  }
  if (result.message.empty()) {
    std::ostringstream s;
    s << (result.converged ? "static residual " : "not converged: static residual ") << result.staticResidual
      << " N (threshold " << result.residualThreshold << " N) after " << result.steps << " steps, "
      << result.newtonIterations << " Newton iterations";
    if (result.saddleEscapes > 0) s << "; left " << result.saddleEscapes << " unstable equilibria downhill";
    if (result.converged && result.negativeEigenvalues > 0)
      s << "; the equilibrium is unstable (a saddle of the potential energy: " << result.negativeEigenvalues
        << " negative eigenvalue(s))";
    result.message = s.str();
  }
  return result;
}

}  // namespace jetshell
