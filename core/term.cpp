#include "core/term.h"

#include "core/mesh.h"
#include "core/parameter_derivatives.h"

namespace jetshell {

HessianModel hessianModelFromString(const std::string& name) {
  if (name == "exact") return HessianModel::Exact;
  if (name == "gaussNewton") return HessianModel::GaussNewton;
  throw InputError("Hessian model: '" + name + "' is not one of exact, gaussNewton");
}

void EnergyTerm::setParameterValues(const std::vector<double>& values) {
  validateParameterValues(name(), parameterNames(), values);
  if (!values.empty()) throw InputError("term '" + name() + "' does not implement setParameterValues");
}

void EnergyTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  if (!parameterNames().empty())
    throw InputError("term '" + name() + "' does not implement evaluateParameterDerivatives");
  out.energy.resize(0);
  out.mixed.resize(x.size(), 0);
}

}  // namespace jetshell
