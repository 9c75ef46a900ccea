#include "tools/fit/fit_optimizer.h"

#include "core/mesh.h"
#include "solvers/timer.h"

#include <Eigen/Dense>
#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace jetshell {
namespace {

const char* nloptResultName(nlopt_result r) {
  switch (r) {
    case NLOPT_FAILURE: return "NLOPT_FAILURE";
    case NLOPT_INVALID_ARGS: return "NLOPT_INVALID_ARGS";
    case NLOPT_OUT_OF_MEMORY: return "NLOPT_OUT_OF_MEMORY";
    case NLOPT_ROUNDOFF_LIMITED: return "NLOPT_ROUNDOFF_LIMITED";
    case NLOPT_FORCED_STOP: return "NLOPT_FORCED_STOP";
    case NLOPT_SUCCESS: return "NLOPT_SUCCESS";
    case NLOPT_STOPVAL_REACHED: return "NLOPT_STOPVAL_REACHED";
    case NLOPT_FTOL_REACHED: return "NLOPT_FTOL_REACHED";
    case NLOPT_XTOL_REACHED: return "NLOPT_XTOL_REACHED";
    case NLOPT_MAXEVAL_REACHED: return "NLOPT_MAXEVAL_REACHED";
    case NLOPT_MAXTIME_REACHED: return "NLOPT_MAXTIME_REACHED";
    default: return "NLOPT_UNKNOWN";
  }
}

/// The scaled variables z and their map to q.
struct Scaling {
  std::vector<FitVariable> vars;
  Eigen::VectorXd scale;  // linear variables: q = scale · z

  double toZ(int i, double q) const { return vars[i].logScale ? std::log(q) : q / scale[i]; }
  double toQ(int i, double z) const { return vars[i].logScale ? std::exp(z) : scale[i] * z; }
  double dqdz(int i, double q) const { return vars[i].logScale ? q : scale[i]; }
  Eigen::VectorXd q(const Eigen::VectorXd& z) const {
    Eigen::VectorXd out(z.size());
    for (int i = 0; i < z.size(); ++i) out[i] = toQ(i, z[i]);
    return out;
  }
};

Scaling makeScaling(const std::vector<FitVariable>& vars) {
  Scaling s;
  s.vars = vars;
  s.scale.resize(static_cast<Eigen::Index>(vars.size()));
  for (std::size_t i = 0; i < vars.size(); ++i) {
    const FitVariable& v = vars[i];
    const std::string w = "fit parameter '" + v.label + "'";
    if (!std::isfinite(v.lower) || !std::isfinite(v.upper) || !(v.lower < v.upper))
      throw InputError(w + ": bounds must be finite with lower < upper");
    if (!std::isfinite(v.initial) || v.initial < v.lower || v.initial > v.upper)
      throw InputError(w + ": initial value must lie within the bounds");
    if (v.logScale && !(v.lower > 0.0)) throw InputError(w + ": a log-scale parameter needs lower > 0");
    s.scale[static_cast<Eigen::Index>(i)] = v.initial != 0.0 ? std::abs(v.initial) : v.upper - v.lower;
  }
  return s;
}

/// Shared state of one run: evaluation with history and best-so-far bookkeeping.
struct Run {
  FitProblem* problem = nullptr;
  Scaling scaling;
  FitOptions options;
  FitResult* result = nullptr;
  FitEvaluation best;
  Eigen::VectorXd bestQ;
  bool haveBest = false;
  std::string failure;  // the first failed evaluation's message
  nlopt_opt opt = nullptr;
  /// NLopt sees f / misfitScale, the misfit relative to the first evaluation's (0: not set yet). Both NLopt
  /// methods with gradients carry absolute constants tuned for f = O(1): Luksan's L-BFGS stops with "success"
  /// once every gradient component is below 1e-8, and MMA keeps its penalty ρ ≥ 1e-5, so on a raw misfit of
  /// 1e-9 (displacements in metres) L-BFGS stopped at its first point and MMA crept in steps of ~1e-4.
  double misfitScale = 0.0;

  /// Whether the fit is to stop before its next evaluation (FitOptions::stopRequested); remembered.
  bool stopping() {
    if (!result->interrupted && options.stopRequested && options.stopRequested()) result->interrupted = true;
    return result->interrupted;
  }

  /// Evaluates at z; returns the evaluation (misfit +inf when it failed).
  FitEvaluation at(const Eigen::VectorXd& z, FitDerivatives d) {
    const Eigen::VectorXd q = scaling.q(z);
    FitEvaluation e = problem->evaluate(q, d);
    FitRecord rec;
    rec.evaluation = static_cast<int>(result->history.size()) + 1;
    rec.q = q;
    rec.ok = e.ok;
    rec.misfit = e.ok ? e.misfit : std::numeric_limits<double>::infinity();
    if (e.ok && d != FitDerivatives::None) rec.gradientNorm = e.gradient.norm();
    if (e.ok && d != FitDerivatives::None && !e.derivativesExact) {
      rec.exactGradient = false;
      ++result->inexactDerivativeEvaluations;
    }
    if (e.ok && (!haveBest || e.misfit < best.misfit)) {
      best = e;
      bestQ = q;
      haveBest = true;
      rec.best = true;
    }
    if (!e.ok && failure.empty()) failure = e.message;
    result->history.push_back(rec);
    return e;
  }
  /// ∂f/∂z from ∂f/∂q.
  Eigen::VectorXd gradientZ(const Eigen::VectorXd& gq, const Eigen::VectorXd& q) const {
    Eigen::VectorXd g(gq.size());
    for (int i = 0; i < g.size(); ++i) g[i] = gq[i] * scaling.dqdz(i, q[i]);
    return g;
  }
};

double nloptObjective(unsigned n, const double* zp, double* grad, void* data) {
  Run& run = *static_cast<Run*>(data);
  if (run.stopping()) {  // no made-up value reaches the optimizer: it stops here
    nlopt_force_stop(run.opt);
    if (grad) std::fill(grad, grad + n, 0.0);
    return std::numeric_limits<double>::max();
  }
  const Eigen::VectorXd z = Eigen::Map<const Eigen::VectorXd>(zp, n);
  const FitEvaluation e = run.at(z, grad ? FitDerivatives::Gradient : FitDerivatives::None);
  if (!e.ok) {
    // A failed solve has no misfit: stop rather than feed the optimizer a made-up value.
    nlopt_force_stop(run.opt);
    if (grad) std::fill(grad, grad + n, 0.0);
    return std::numeric_limits<double>::max();
  }
  if (run.misfitScale == 0.0) run.misfitScale = e.misfit > 0.0 ? e.misfit : 1.0;
  if (grad) {
    const Eigen::VectorXd g = run.gradientZ(e.gradient, run.scaling.q(z)) / run.misfitScale;
    std::copy(g.data(), g.data() + n, grad);
  }
  return e.misfit / run.misfitScale;
}

void runNlopt(Run& run, const Eigen::VectorXd& z0, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  FitResult& r = *run.result;
  const unsigned n = static_cast<unsigned>(z0.size());
  nlopt_algorithm a = NLOPT_LN_BOBYQA;
  switch (run.options.algorithm) {
    case FitAlgorithm::Bobyqa: a = NLOPT_LN_BOBYQA; break;
    case FitAlgorithm::NelderMead: a = NLOPT_LN_NELDERMEAD; break;
    case FitAlgorithm::Lbfgs: a = NLOPT_LD_LBFGS; break;
    case FitAlgorithm::Mma: a = NLOPT_LD_MMA; break;
    case FitAlgorithm::LevenbergMarquardt: break;
  }
  run.opt = nlopt_create(a, n);
  nlopt_set_min_objective(run.opt, nloptObjective, &run);
  nlopt_set_lower_bounds(run.opt, lower.data());
  nlopt_set_upper_bounds(run.opt, upper.data());
  nlopt_set_maxeval(run.opt, run.options.maxEvaluations);
  nlopt_set_xtol_abs1(run.opt, run.options.parameterTolerance);
  nlopt_set_ftol_rel(run.opt, run.options.misfitTolerance);
  // Derivative-free methods start from a simplex or trust region of this size in z (10% in each parameter):
  // NLopt's default, a fraction of the bound width, makes first trial points decades away on log scales,
  // where the static solves are needlessly hard.
  if (!usesDerivatives(run.options.algorithm)) nlopt_set_initial_step1(run.opt, 0.1);
  std::vector<double> z(z0.data(), z0.data() + n);
  double minf = 0.0;
  const nlopt_result code = nlopt_optimize(run.opt, z.data(), &minf);
  nlopt_destroy(run.opt);
  run.opt = nullptr;
  r.termination = nloptResultName(code);
  r.iterations = static_cast<int>(r.history.size());
  r.success = code == NLOPT_SUCCESS || code == NLOPT_STOPVAL_REACHED || code == NLOPT_FTOL_REACHED ||
              code == NLOPT_XTOL_REACHED;
  if (code == NLOPT_ROUNDOFF_LIMITED) {
    r.message = "NLopt stopped: round-off limited (the misfit cannot be lowered further in floating point)";
    r.success = run.haveBest;
  }
  if (!run.failure.empty()) r.message = "a forward evaluation failed: " + run.failure;
  if (r.interrupted) r.success = false;
}

void runLevenbergMarquardt(Run& run, const Eigen::VectorXd& z0, const Eigen::VectorXd& lower,
                           const Eigen::VectorXd& upper) {
  FitResult& r = *run.result;
  const int Q = static_cast<int>(z0.size());
  Eigen::VectorXd z = z0;
  if (run.stopping()) return;
  FitEvaluation e = run.at(z, FitDerivatives::Jacobian);
  if (!e.ok) {
    r.termination = "FORWARD_FAILURE";
    r.message = "the first evaluation failed: " + e.message;
    return;
  }
  double mu = 1e-3;
  while (true) {
    const Eigen::VectorXd q = run.scaling.q(z);
    Eigen::MatrixXd J = e.jacobian;
    for (int i = 0; i < Q; ++i) J.col(i) *= run.scaling.dqdz(i, q[i]);
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * e.residuals;
    if (g.lpNorm<Eigen::Infinity>() == 0.0) {
      r.termination = "GRADIENT_ZERO";
      r.success = true;
      return;
    }
    ++r.iterations;
    bool accepted = false;
    while (!accepted) {
      if (run.stopping()) return;
      if (static_cast<int>(r.history.size()) >= run.options.maxEvaluations) {
        r.termination = "MAXEVAL_REACHED";
        return;
      }
      Eigen::MatrixXd B = A;
      const double floor = 1e-12 * std::max(A.diagonal().maxCoeff(), 1e-300);
      for (int i = 0; i < Q; ++i) B(i, i) += mu * std::max(A(i, i), floor);
      const Eigen::VectorXd step = B.ldlt().solve(-g);
      Eigen::VectorXd zt = (z + step).cwiseMax(lower).cwiseMin(upper);
      const double change = (zt - z).lpNorm<Eigen::Infinity>();
      if (!step.allFinite() || change <= run.options.parameterTolerance) {
        r.termination = step.allFinite() ? "XTOL_REACHED" : "SINGULAR_SYSTEM";
        r.success = step.allFinite();
        return;
      }
      FitEvaluation t = run.at(zt, FitDerivatives::Jacobian);
      if (t.ok && t.misfit < e.misfit) {
        const double decrease = e.misfit - t.misfit;
        const double previous = e.misfit;
        z = zt;
        e = std::move(t);
        mu = std::max(mu / 3.0, 1e-12);
        accepted = true;
        if (decrease <= run.options.misfitTolerance * previous) {
          r.termination = "FTOL_REACHED";
          r.success = true;
          return;
        }
      } else {
        mu *= 4.0;
        if (mu > 1e12) {
          r.termination = "STALLED";
          r.message = t.ok ? "no step lowers the misfit (damping exceeded 1e12)" : "evaluations failed: " + t.message;
          r.success = t.ok;  // a local minimum to working precision
          return;
        }
      }
    }
  }
}

}  // namespace

FitUncertainty gaussNewtonUncertainty(const Eigen::MatrixXd& J, const Eigen::VectorXd& r) {
  FitUncertainty u;
  const int M = static_cast<int>(J.rows()), Q = static_cast<int>(J.cols());
  if (M <= Q) {
    u.message = "as many parameters as residuals: no residual variance to scale the covariance with";
    return u;
  }
  // Columns scaled to unit norm first: parameters in physical units differ by many decades (λ ~ 1e2, α ~ 1e-5),
  // which would make JᵀJ look singular when only its scaling is bad.
  Eigen::VectorXd norms(Q);
  for (int i = 0; i < Q; ++i) {
    norms[i] = J.col(i).norm();
    if (!(norms[i] > 0.0)) {
      u.message = "a parameter does not change any residual: the observations do not determine it";
      return u;
    }
  }
  const Eigen::MatrixXd Js = J * norms.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Js.transpose() * Js);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 1e-13 * eig.eigenvalues().maxCoeff())) {
    u.message = "JᵀJ is singular: the observations do not determine every parameter";
    return u;
  }
  const Eigen::MatrixXd Cs = eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() *
                             eig.eigenvectors().transpose();
  const Eigen::MatrixXd C = norms.cwiseInverse().asDiagonal() * Cs * norms.cwiseInverse().asDiagonal();
  u.residualVariance = r.squaredNorm() / static_cast<double>(M - Q);
  u.standardDeviation = (u.residualVariance * C.diagonal()).cwiseSqrt();
  u.correlation.resize(Q, Q);
  for (int i = 0; i < Q; ++i)
    for (int j = 0; j < Q; ++j) u.correlation(i, j) = C(i, j) / std::sqrt(C(i, i) * C(j, j));
  u.available = true;
  u.message = "Gauss–Newton covariance s²(JᵀJ)⁻¹ with s² = Σr²/(M − Q), M = " + std::to_string(M) +
              " residuals, Q = " + std::to_string(Q) + " parameters";
  return u;
}

FitResult runFit(FitProblem& problem, const std::vector<FitVariable>& variables, const FitOptions& options) {
  const Timer timer;
  if (static_cast<int>(variables.size()) != problem.numParameters())
    throw InputError("fit: " + std::to_string(variables.size()) + " variables for " +
                     std::to_string(problem.numParameters()) + " parameters");
  if (options.maxEvaluations < 1 || options.maxEvaluations > 100000)
    throw InputError("fit: maxEvaluations must lie in [1, 100000]");
  if (!(options.parameterTolerance > 0.0) || !(options.misfitTolerance >= 0.0))
    throw InputError("fit: tolerances must be > 0 (parameter) and >= 0 (misfit)");
  FitResult r;
  r.algorithm = options.algorithm;
  r.variables = variables;
  Run run;
  run.problem = &problem;
  run.scaling = makeScaling(variables);
  run.options = options;
  run.result = &r;
  const int Q = problem.numParameters();
  Eigen::VectorXd z0(Q), lower(Q), upper(Q);
  for (int i = 0; i < Q; ++i) {
    z0[i] = run.scaling.toZ(i, variables[static_cast<std::size_t>(i)].initial);
    lower[i] = run.scaling.toZ(i, variables[static_cast<std::size_t>(i)].lower);
    upper[i] = run.scaling.toZ(i, variables[static_cast<std::size_t>(i)].upper);
  }
  const FitCounters before = problem.counters();
  if (options.algorithm == FitAlgorithm::LevenbergMarquardt) runLevenbergMarquardt(run, z0, lower, upper);
  else runNlopt(run, z0, lower, upper);
  r.counters = problem.counters();
  r.counters.evaluations -= before.evaluations;
  r.counters.fullSolves -= before.fullSolves;
  r.counters.newtonIterations -= before.newtonIterations;
  r.counters.newtonFactorizations -= before.newtonFactorizations;
  r.counters.sensitivityFactorizations -= before.sensitivityFactorizations;
  r.counters.sensitivitySolves -= before.sensitivitySolves;
  r.counters.gradientEvaluations -= before.gradientEvaluations;
  r.counters.jacobianEvaluations -= before.jacobianEvaluations;
  r.counters.timeSteps -= before.timeSteps;
  r.counters.inexactDerivativeSolves -= before.inexactDerivativeSolves;
  if (r.interrupted) {
    r.termination = "INTERRUPTED";
    r.success = false;
    std::ostringstream m;
    m << "interrupted after " << r.history.size() << " evaluations" << (run.haveBest ? ": the best values so far" : "");
    r.message = m.str();
  }
  if (!run.haveBest) {
    r.success = false;
    if (r.message.empty()) r.message = "no evaluation succeeded: " + run.failure;
    r.wallSeconds = timer.seconds();
    return r;
  }
  r.q = run.bestQ;
  r.misfit = run.best.misfit;
  r.residuals = run.best.residuals;
  r.equilibria = run.best.equilibria;
  // The uncertainty needs J at the best point: reuse it when the best evaluation has one.
  if (run.best.jacobian.size() > 0) {
    r.jacobian = run.best.jacobian;
  } else if (!r.interrupted) {  // one more solve, which an interrupted fit does not wait for
    const FitEvaluation e = problem.evaluate(r.q, FitDerivatives::Jacobian);
    if (e.ok) r.jacobian = e.jacobian;
    if (e.ok && !e.derivativesExact) ++r.inexactDerivativeEvaluations;
  }
  if (r.jacobian.size() > 0) r.uncertainty = gaussNewtonUncertainty(r.jacobian, r.residuals);
  else if (r.interrupted) r.uncertainty.message = "not computed: the fit was interrupted";
  else r.uncertainty.message = "the Jacobian at the fitted values could not be computed";
  if (r.message.empty()) r.message = r.success ? "converged" : "stopped before the tolerances were met";
  r.wallSeconds = timer.seconds();
  return r;
}

}  // namespace jetshell
