#include "solvers/branch_switching.h"

#include "solvers/path_corrector.h"
#include "solvers/stability_check.h"
#include "solvers/statics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace jetshell {
namespace {

/// Inverse iteration steps that turn the direction of negative curvature into the softest eigenvector.
constexpr int kInverseIterations = 4;
/// Halvings of the switch's step after both signs of the mode failed.
constexpr int kStepHalvings = 4;
/// A landing may lie below the bracket's stable end by this many bracket widths (the Euler column's lands 0.55 of a
/// width below it: its discrete branch leaves the critical load nearly flat).
constexpr double kBelowBracket = 4.0;

void checkOption(bool ok, const char* field, double value, const char* rule) {
  if (ok) return;
  std::ostringstream s;
  s << "branch switching: " << field << " = " << value << ": " << rule;
  throw InputError(s.str());
}

}  // namespace

void checkBranchSwitchOptions(const BranchSwitchOptions& o) {
  checkOption(o.bisections >= 0 && o.bisections <= 60, "branchSwitch.bisections", o.bisections, "must be in 0..60");
  checkOption(std::isfinite(o.step) && o.step > 0.0 && o.step <= 100.0, "branchSwitch.step", o.step,
              "must be in (0, 100]");
}

std::string switchFailure(const BranchSwitchResult& r) {
  std::ostringstream why;
  why << "between lambda = " << r.stableLoadFactor << " and " << r.unstableLoadFactor << ": " << r.message;
  return why.str();
}

std::string landingOutside(double lambda, double lambdaA, double lambdaB, double stable, double unstable) {
  const double towards = lambdaB >= lambdaA ? 1.0 : -1.0;  // arc length may meet a bifurcation with λ falling
  if (!(towards * (lambda - lambdaA) > 0.0 && towards * (lambda - lambdaB) <= 0.0)) return "outside the step";
  // A branch that leaves the bifurcation starts at the critical load: a landing far below the bracket is another
  // equilibrium on the cylinder (a cloth pinned at two corners, turned about them at no load).
  if (towards * (lambda - stable) < -kBelowBracket * std::abs(unstable - stable))
    return "below the bracket on the critical load";
  return "";
}

BranchSwitchResult switchBranch(NewtonSolver& newton, const LoadFactorHooks& loads, IndefiniteFactor& factor,
                                const BranchSwitchOptions& o, double lambdaA, const Eigen::VectorXd& xa,
                                double lambdaB, const Eigen::VectorXd& xb) {
  checkBranchSwitchOptions(o);
  Objective& objective = newton.objective();
  const NewtonOptions& newtonOptions = newton.options();
  BranchSwitchResult r;
  double ls = lambdaA, lu = lambdaB;
  Eigen::VectorXd xs = xa, xu = xb;
  auto fail = [&](const std::string& why) {
    r.message = why;
    loads.set(lambdaB);
    return r;
  };

  // 1. The critical load, bracketed on the fundamental branch.
  for (int k = 0; k < o.bisections; ++k) {
    const double lm = 0.5 * (ls + lu);
    Eigen::VectorXd x = 0.5 * (xs + xu);
    objective.applyPrescribed(lm, x);
    loads.set(lm);
    const SolverSummary s = newton.minimize(x);
    r.newtonIterations += s.iterations;
    if (!s.converged()) break;  // keep the bracket found so far
    const Stability st = assessStability(objective, factor, x, newtonOptions.derivatives, 1.0);
    ++r.factorizations;
    if (st.negativeEigenvalues < 0) break;
    if (st.negativeEigenvalues == 0) {
      ls = lm;
      xs = std::move(x);
    } else {
      lu = lm;
      xu = std::move(x);
    }
  }
  r.stableLoadFactor = ls;
  r.unstableLoadFactor = lu;

  // 2. The critical mode, by inverse iteration with the factor at the unstable end.
  objective.applyPrescribed(lu, xu);
  loads.set(lu);
  const Stability at = assessStability(objective, factor, xu, newtonOptions.derivatives, 1.0);
  ++r.factorizations;
  r.negativeEigenvalues = at.negativeEigenvalues;
  if (at.negativeEigenvalues <= 0 || at.downhill.size() == 0)
    return fail("no direction of negative curvature at the bracket's unstable end");
  Eigen::VectorXd mode = at.downhill / at.downhill.norm();
  for (int k = 0; k < kInverseIterations; ++k) {
    Eigen::VectorXd w;
    if (!factor.solve(mode, w)) break;
    objective.zeroFixed(w);
    const double n = w.norm();
    if (!(n > 0.0) || !std::isfinite(n)) break;
    mode = w / n;
  }
  if (mode.dot(at.downhill) < 0.0) mode = -mode;
  const double largest = largestVertexNorm(mode);
  if (!(largest > 0.0) || !std::isfinite(largest)) return fail("the critical mode is not finite");
  mode /= largest;  // its largest vertex move is 1

  // 3–4. The switch: a step along the mode, corrected on the cylinder around the unstable end.
  const std::vector<char>& fixed = objective.fixedDof();
  std::ostringstream tried;
  double step = o.step * objective.scales().length;
  for (int h = 0; h <= kStepHalvings; ++h, step *= 0.5) {
    for (double sign : {1.0, -1.0}) {
      Eigen::VectorXd x = xu + sign * step * mode;
      double lambda = lu;
      PathConstraint c;
      c.kind = PathConstraint::Kind::ArcLength;
      c.anchor = &xu;
      c.anchorLoadFactor = lu;
      const Eigen::VectorXd d = x - xu;
      c.radius = std::sqrt(freeDot(d, d, fixed));
      c.loadWeight = 0.0;
      PathCorrection pc = correctOnPath(objective, loads, factor, x, lambda, c, newtonOptions);
      r.newtonIterations += pc.summary.iterations;
      tried << (tried.tellp() > 0 ? "; " : "") << "step " << sign * step << " m: ";
      if (!pc.summary.converged()) {
        tried << "no correction (" << pc.summary.message << ")";
        continue;
      }
      const std::string outside = landingOutside(lambda, lambdaA, lambdaB, r.stableLoadFactor, r.unstableLoadFactor);
      if (!outside.empty()) {
        tried << "landed at lambda = " << lambda << ", " << outside;
        continue;
      }
      const Stability landed = assessStability(objective, factor, x, newtonOptions.derivatives, 1.0);
      ++r.factorizations;
      if (landed.negativeEigenvalues != 0) {
        tried << "landed at lambda = " << lambda << " on an equilibrium with " << landed.negativeEigenvalues
              << " negative eigenvalue(s)";
        continue;
      }
      loads.set(lambda);
      r.switched = true;
      r.loadFactor = lambda;
      r.x = std::move(x);
      r.summary = std::move(pc.summary);
      return r;
    }
  }
  return fail("no stable branch reached from the bracket's unstable end: " + tried.str());
}

}  // namespace jetshell
