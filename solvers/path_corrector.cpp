#include "solvers/path_corrector.h"

#include "solvers/newton.h"
#include "solvers/statics.h"
#include "solvers/timer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace jetshell {

double freeDot(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const std::vector<char>& fixed) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (!fixed[static_cast<std::size_t>(i)]) s += a[i] * b[i];
  return s;
}

Eigen::VectorXd loadVector(Objective& objective, const LoadFactorHooks& hooks, const Eigen::VectorXd& x,
                           double lambda, const Eigen::VectorXd& g, const EvalOptions& evalOptions) {
  const double h = 1e-6 * std::max(1.0, std::abs(lambda));
  Eigen::VectorXd xh = x, gh;
  objective.applyPrescribed(lambda + h, xh);
  hooks.set(lambda + h);
  objective.evaluate(xh, &gh, false, evalOptions);
  hooks.set(lambda);
  Eigen::VectorXd q = -(gh - g) / h;
  objective.zeroFixed(q);
  return q;
}

PathCorrection correctOnPath(Objective& objective, const LoadFactorHooks& hooks, IndefiniteFactor& factor,
                             Eigen::VectorXd& x, double& lambda, const PathConstraint& c, const NewtonOptions& o) {
  PathCorrection out;
  SolverSummary& s = out.summary;
  s.minimizer = "path_newton";
  s.linearSolver = "ldlt_indefinite";
  const EvalOptions evalOptions{o.derivatives, PsdProjection::None, o.bendingHessian};
  const std::vector<char>& fixed = objective.fixedDof();
  Timer total;
  auto finish = [&](TerminationReason reason, const std::string& message) {
    s.reason = reason;
    if (reason == TerminationReason::Converged) s.convergenceTest = "residual";
    s.message = message;
    s.totalSeconds = total.seconds();
    return out;
  };
  Eigen::VectorXd g, a, b, rhs;
  double tolerance = 0.0;
  for (int k = 0;; ++k) {
    Timer timer;
    objective.applyPrescribed(lambda, x);
    hooks.set(lambda);
    const double E = objective.evaluate(x, &g, true, evalOptions);
    ++s.energyEvaluations;
    ++s.gradientEvaluations;
    ++s.hessianEvaluations;
    s.assemblySeconds += timer.seconds();
    const double r = infNorm(g);
    s.finalEnergy = E;
    s.finalResidual = r;
    if (!std::isfinite(E) || !g.allFinite())
      return finish(TerminationReason::NonFinite, "non-finite energy or gradient at iteration " + std::to_string(k));
    if (k == 0) {
      s.initialEnergy = E;
      s.initialResidual = r;
      const ForceScale F = objective.forceScale(x, r);
      s.forceScale = F.value;
      s.forceScaleSource = F.source;
      tolerance = o.residualTolerance * F.value;
      if (o.absoluteResidualTolerance > 0.0) tolerance = std::max(tolerance, o.absoluteResidualTolerance);
      if (o.relativeResidualTolerance > 0.0) tolerance = std::max(tolerance, o.relativeResidualTolerance * r);
      s.residualThreshold = tolerance;
    }
    IterationRecord rec;
    rec.iteration = k;
    rec.energy = E;
    rec.residual = r;
    if (r <= tolerance) {
      if (out.negativePivots < 0 && factor.factorize(objective.assembler().matrix(), objective.assembler().patternVersion()))
        out.negativePivots = factor.negativePivots();
      out.gradient = g;
      std::ostringstream m;
      m << "residual " << r << " N <= " << tolerance << " N (" << o.residualTolerance << " x force scale "
        << s.forceScale << " N from " << s.forceScaleSource << ") at lambda = " << lambda;
      return finish(TerminationReason::Converged, m.str());
    }
    if (k >= o.maxIterations) {
      std::ostringstream m;
      m << "no convergence in " << o.maxIterations << " iterations (residual " << r << " N > " << tolerance << " N)";
      return finish(TerminationReason::IterationCap, m.str());
    }
    if (k >= 3 && r > 1e6 * std::max(s.initialResidual, s.forceScale)) {
      std::ostringstream m;
      m << "diverging at iteration " << k << " (residual " << r << " N from " << s.initialResidual << " N)";
      return finish(TerminationReason::Stalled, m.str());
    }
    timer.reset();
    const bool factored = factor.factorize(objective.assembler().matrix(), objective.assembler().patternVersion());
    s.factorizationSeconds += rec.factorizationSeconds = timer.seconds();
    ++s.numericFactorizations;
    if (!factored) return finish(TerminationReason::LinearSolverFailure, factor.message());
    out.negativePivots = factor.negativePivots();
    timer.reset();
    const Eigen::VectorXd q = loadVector(objective, hooks, x, lambda, g, evalOptions);
    ++s.gradientEvaluations;
    s.assemblySeconds += timer.seconds();
    timer.reset();
    rhs = -g;
    if (!factor.solve(rhs, a) || !factor.solve(q, b))
      return finish(TerminationReason::LinearSolverFailure, "LDLT: non-finite solution");
    s.solveSeconds += rec.solveSeconds = timer.seconds();
    objective.zeroFixed(a);
    objective.zeroFixed(b);
    double dLambda = 0.0;
    switch (c.kind) {
      case PathConstraint::Kind::LoadFactor:
        dLambda = c.loadFactor - lambda;
        break;
      case PathConstraint::Kind::Displacement: {
        const double slope = b[c.dof];
        dLambda = (c.value - x[c.dof] - a[c.dof]) / slope;
        break;
      }
      case PathConstraint::Kind::ArcLength: {
        const Eigen::VectorXd du = x - *c.anchor;
        const double dl = lambda - c.anchorLoadFactor;
        const double value = freeDot(du, du, fixed) + c.loadWeight * dl * dl - c.radius * c.radius;
        const double slope = 2.0 * freeDot(du, b, fixed) + 2.0 * c.loadWeight * dl;
        dLambda = -(value + 2.0 * freeDot(du, a, fixed)) / slope;
        break;
      }
    }
    if (!std::isfinite(dLambda))
      return finish(TerminationReason::LinearSolverFailure,
                    "the constraint does not determine the load factor (its row is orthogonal to the tangent)");
    const Eigen::VectorXd step = a + dLambda * b;
    if (!step.allFinite()) return finish(TerminationReason::NonFinite, "non-finite Newton step");
    x += step;
    lambda += dLambda;
    rec.stepLength = 1.0;
    ++s.iterations;
    s.trace.push_back(rec);
  }
}

}  // namespace jetshell
