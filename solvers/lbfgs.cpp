#include "solvers/lbfgs.h"

#include "solvers/timer.h"

#include <nlopt.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace jetshell {
namespace {

struct Problem {
  Objective* objective;
  EvalOptions eval;
  std::vector<int> free;  // free dof indices
  Eigen::VectorXd x, g;
  Eigen::VectorXd best;
  double bestEnergy = std::numeric_limits<double>::infinity();
  double bestResidual = std::numeric_limits<double>::infinity();
  double threshold = 0.0;
  bool thresholdSet = false;
  double forceScale = 0.0;
  double residualTolerance = 0.0;
  bool converged = false;
  nlopt_opt opt = nullptr;
  SolverSummary* summary = nullptr;
};

double evaluate(unsigned n, const double* xf, double* grad, void* data) {
  Problem& p = *static_cast<Problem*>(data);
  for (unsigned i = 0; i < n; ++i) p.x[p.free[i]] = xf[i];
  const Timer t;
  const double E = p.objective->evaluate(p.x, &p.g, false, p.eval);
  p.summary->assemblySeconds += t.seconds();
  ++p.summary->energyEvaluations;
  ++p.summary->gradientEvaluations;
  const bool finite = std::isfinite(E) && p.g.allFinite();
  const double r = finite ? p.g.lpNorm<Eigen::Infinity>() : std::numeric_limits<double>::infinity();
  if (!p.thresholdSet) {
    p.summary->initialEnergy = E;
    p.summary->initialResidual = r;
    const ForceScale F = p.objective->forceScale(p.x, r);
    p.forceScale = F.value;
    p.summary->forceScale = F.value;
    p.summary->forceScaleSource = F.source;
    p.threshold = p.residualTolerance * F.value;
    p.thresholdSet = true;
  }
  if (!finite) {
    // A huge value makes the line search back off; NaN would end the run.
    if (grad != nullptr)
      for (unsigned i = 0; i < n; ++i) grad[i] = 0.0;
    return std::numeric_limits<double>::max();
  }
  if (grad != nullptr)
    for (unsigned i = 0; i < n; ++i) grad[i] = p.g[p.free[i]];
  if (E < p.bestEnergy || (r <= p.threshold && !p.converged)) {
    p.bestEnergy = E;
    p.bestResidual = r;
    p.best = p.x;
  }
  if (r <= p.threshold && !p.converged) {
    p.converged = true;
    nlopt_force_stop(p.opt);
  }
  return E;
}

}  // namespace

SolverSummary minimizeLbfgs(Objective& objective, Eigen::VectorXd& x, const LbfgsOptions& options) {
  const Timer total;
  SolverSummary s;
  s.minimizer = "lbfgs";
  Problem p;
  p.objective = &objective;
  p.eval.path = options.derivatives;
  p.x = x;
  p.best = x;
  p.residualTolerance = options.residualTolerance;
  p.summary = &s;
  objective.finalize();
  for (int d = 0; d < objective.numDofs(); ++d)
    if (!objective.fixedDof()[static_cast<std::size_t>(d)]) p.free.push_back(d);
  const unsigned n = static_cast<unsigned>(p.free.size());
  std::vector<double> xf(n);
  for (unsigned i = 0; i < n; ++i) xf[i] = x[p.free[i]];

  p.opt = nlopt_create(NLOPT_LD_LBFGS, n);
  nlopt_set_min_objective(p.opt, evaluate, &p);
  nlopt_set_maxeval(p.opt, options.maxEvaluations);
  nlopt_set_vector_storage(p.opt, static_cast<unsigned>(options.memory));
  // Our residual test is the stopping rule; NLopt's own tolerances only catch stagnation.
  nlopt_set_ftol_rel(p.opt, 1e-15);
  nlopt_set_xtol_rel(p.opt, 1e-15);
  double minf = 0.0;
  const nlopt_result code = n > 0 ? nlopt_optimize(p.opt, xf.data(), &minf) : NLOPT_SUCCESS;
  nlopt_destroy(p.opt);

  if (n == 0) {
    s.reason = TerminationReason::Converged;
    s.message = "no free dofs";
  } else if (p.converged) {
    s.reason = TerminationReason::Converged;
  } else if (code == NLOPT_MAXEVAL_REACHED) {
    s.reason = TerminationReason::IterationCap;
  } else if (!std::isfinite(p.bestEnergy)) {
    s.reason = TerminationReason::NonFinite;
  } else {
    s.reason = TerminationReason::LineSearchFailure;  // NLopt stalled above the residual threshold
  }
  std::ostringstream m;
  m << "NLopt result " << static_cast<int>(code) << " after " << s.energyEvaluations << " evaluations";
  if (s.message.empty()) s.message = m.str();
  if (std::isfinite(p.bestEnergy)) x = p.best;
  s.iterations = s.energyEvaluations;
  s.finalEnergy = std::isfinite(p.bestEnergy) ? p.bestEnergy : s.initialEnergy;
  s.finalResidual = std::isfinite(p.bestEnergy) ? p.bestResidual : s.initialResidual;
  s.residualThreshold = p.threshold;
  s.totalSeconds = total.seconds();
  return s;
}

}  // namespace jetshell
