#include "core/term.h"

#include "core/mesh.h"

namespace jetshell {

void EnergyTerm::setParameterValues(const std::vector<double>& values) {
  const std::size_t expected = parameterNames().size();
  if (values.size() != expected)
    throw InputError("term '" + name() + "': " + std::to_string(values.size()) + " parameter values given, " +
                     std::to_string(expected) + " expected");
  if (expected != 0) throw InputError("term '" + name() + "' does not implement setParameterValues");
}

void EnergyTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  if (!parameterNames().empty())
    throw InputError("term '" + name() + "' does not implement evaluateParameterDerivatives");
  out.energy.resize(0);
  out.mixed.resize(x.size(), 0);
}

}  // namespace jetshell
