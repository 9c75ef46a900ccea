#include "solvers/stability_check.h"

#include "solvers/newton.h"

#include <cmath>

namespace jetshell {

Stability assessStability(Objective& objective, IndefiniteFactor& factor, const Eigen::VectorXd& x,
                          DerivativePath path, double step, TermSelection selection) {
  EvalOptions exact;
  exact.path = path;
  exact.projection = PsdProjection::None;
  exact.hessianModel = HessianModel::Exact;
  Stability s;
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(x.size());
  s.energy = objective.evaluate(x, &gradient, true, exact, selection);
  if (!factor.factorize(objective.assembler().matrix(), objective.assembler().patternVersion())) return s;
  s.negativeEigenvalues = factor.negativePivots();
  Eigen::VectorXd d;
  if (s.negativeEigenvalues == 0 || !factor.negativeCurvatureDirection(d)) return s;
  objective.zeroFixed(d);
  const double largest = largestVertexNorm(d);
  if (!(largest > 0.0) || !std::isfinite(largest)) return s;
  d *= step * objective.scales().length / largest;
  if (gradient.dot(d) > 0.0) d = -d;
  s.downhill = std::move(d);
  return s;
}

}  // namespace jetshell
