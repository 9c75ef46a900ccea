#include "tools/fit/fit_problem.h"

#include "core/mesh.h"

#include <cmath>

namespace jetshell {

void FitProblem::checkObserved(const std::vector<ObservedCoordinate>& observed, int numLevels, int numDofs) {
  if (observed.empty()) throw InputError("fit: no observation");
  for (const ObservedCoordinate& o : observed) {
    if (o.level < 0 || o.level >= numLevels) throw InputError("fit: observation level out of range");
    if (o.dof < 0 || o.dof >= numDofs) throw InputError("fit: observed dof out of range");
    if (!(o.weight >= 0.0) || !std::isfinite(o.weight) || !std::isfinite(o.target))
      throw InputError("fit: observation weights must be finite and >= 0, targets finite");
  }
}

bool FitProblem::applyParameters(Objective& objective, const ParameterMapping& mapping, const Eigen::VectorXd& q,
                                 FitDerivatives derivatives, FitEvaluation& out, Eigen::MatrixXd& dvdq) {
  if (q.size() != mapping.numParameters || !q.allFinite()) {
    out.message = "parameters not finite or of the wrong count";
    return false;
  }
  ++counters_.evaluations;
  if (derivatives == FitDerivatives::Gradient) ++counters_.gradientEvaluations;
  if (derivatives == FitDerivatives::Jacobian) ++counters_.jacobianEvaluations;
  Eigen::VectorXd values;
  mapping.map(q, values, derivatives == FitDerivatives::None ? nullptr : &dvdq);
  for (std::size_t t = 0; t < mapping.termParameters.size(); ++t)
    setTermParameterValue(objective, mapping.termParameters[t], values[static_cast<Eigen::Index>(t)]);
  return true;
}

bool FitProblem::computeResiduals(FitEvaluation& out) const {
  const std::vector<ObservedCoordinate>& obs = observed();
  out.residuals.resize(static_cast<Eigen::Index>(obs.size()));
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const ObservedCoordinate& o = obs[i];
    out.residuals[static_cast<Eigen::Index>(i)] =
        std::sqrt(o.weight) * (out.equilibria[static_cast<std::size_t>(o.level)][o.dof] - o.target);
  }
  out.misfit = 0.5 * out.residuals.squaredNorm();
  if (!std::isfinite(out.misfit)) {
    out.message = "non-finite misfit";
    return false;
  }
  return true;
}

}  // namespace jetshell
