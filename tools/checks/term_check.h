// Every derivative check of the conformance suite in one call, for a term outside the registry (in the spirit of
// Ceres' GradientChecker). In a Catch2 test:
//
//   auto term = makeMyTerm(mesh, ...);
//   for (const std::string& failure : termCheckFailures(*term, x)) FAIL_CHECK(failure);
//
// At one configuration x (3N): checkDerivatives (AD vs analytic, gradient and Hessian vs Richardson-extrapolated
// central differences, symmetry, PSD model Hessians) and, when the term has parameters,
// checkParameterDerivatives (∂E/∂p, ∂²E/∂x∂p). With a factory instead of a term, the term is built on each check
// mesh (tools/checks/check_configurations.h) and checked on one configuration of every kind, and also at rest
// (zero energy and gradient when zeroAtRest()) and under a rigid motion (when rigidInvariant()).
// Output: one human-readable line per violated tolerance; empty when every check passes.
#pragma once

#include "energies/registry.h"
#include "tools/checks/derivative_check.h"

#include <string>
#include <vector>

namespace jetshell {

struct TermCheckOptions {
  DerivativeCheckOptions check;  // evalOptions, hessianIsExact (false for model Hessians), FD settings
  DerivativeTolerances tolerances;
  bool parameters = true;  // also check the parameter derivatives
};

/// The checks at one configuration x.
std::vector<std::string> termCheckFailures(EnergyTerm& term, const Eigen::VectorXd& x,
                                           const TermCheckOptions& options = {});

/// The term built by `make` on every check mesh (default material), at one configuration of every kind, at
/// rest and under a rigid motion. Each line names the mesh and configuration.
std::vector<std::string> termCheckFailures(const TermFactory& make, const TermCheckOptions& options = {});

}  // namespace jetshell
