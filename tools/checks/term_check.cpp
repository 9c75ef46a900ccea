#include "tools/checks/term_check.h"

#include "tools/checks/check_configurations.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace jetshell {

std::vector<std::string> termCheckFailures(EnergyTerm& term, const Eigen::VectorXd& x,
                                           const TermCheckOptions& options) {
  std::vector<std::string> out = checkFailures(checkDerivatives(term, x, options.check), options.tolerances);
  if (options.parameters && !term.parameterNames().empty()) {
    for (const std::string& f :
         checkFailures(checkParameterDerivatives(term, x, options.check), options.tolerances))
      out.push_back(f);
  }
  return out;
}

std::vector<std::string> termCheckFailures(const TermFactory& make, const TermCheckOptions& options) {
  std::vector<std::string> out;
  const ShellMaterialParams material;
  for (const CheckMesh& m : makeCheckMeshes()) {
    const EnergyTermPtr term = make(TermSetup{m.mesh, m.topology, m.reference, material});
    const Eigen::VectorXd X = flatten(m.mesh.V);
    const double ell = configurationLengthScale(X);
    EvalOptions eval = options.check.evalOptions;
    eval.path = term->hasAnalytic() ? DerivativePath::Analytic : DerivativePath::AutoDiff;
    if (term->zeroAtRest()) {
      const DenseDerivatives d = evaluateDense(*term, X, eval);
      const double scale = d.hessian.norm();
      if (!(std::abs(d.energy) <= 1e-14 * scale * ell * ell && d.gradient.norm() <= 1e-14 * scale * ell))
        out.push_back(m.name + " at rest: energy " + std::to_string(d.energy) + ", |gradient| " +
                      std::to_string(d.gradient.norm()) + " are not zero (zeroAtRest() is true)");
    }
    if (term->rigidInvariant()) {
      const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 17).x;
      const Eigen::Matrix3d R = Eigen::AngleAxisd(2.5, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
      const double a = term->evaluate(x, EvalRequest{}, eval);
      const double b = term->evaluate(rigidlyMoved(x, R, Eigen::Vector3d(0.7, -1.3, 0.4)), EvalRequest{}, eval);
      if (!(std::abs(a - b) <= 1e-12 * std::max(std::abs(a), 1e-300)))
        out.push_back(m.name + ": the energy changes under a rigid motion (rigidInvariant() is true)");
    }
    for (ConfigurationKind kind : kConfigurationKinds) {
      const CheckConfiguration c = makeCheckConfiguration(m, kind, 1000 + static_cast<int>(kind));
      for (const std::string& f : termCheckFailures(*term, c.x, options))
        out.push_back(m.name + ", " + c.description + ": " + f);
    }
  }
  return out;
}

}  // namespace jetshell
