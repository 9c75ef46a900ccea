// The AD path takes each face's density Hessian once from nested Jets (the membrane and bending densities are
// quadratic forms in their stage inputs) and must renew it when a material parameter changes.
#include "energies/shell/bending_term.h"
#include "energies/shell/membrane_term.h"
#include "tools/checks/check_configurations.h"
#include "tools/checks/derivative_check.h"

#include <catch2/catch.hpp>

using namespace jetshell;

namespace {

/// Largest entry of |a − b| relative to the largest entry of |b|.
double relativeGap(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / b.lpNorm<Eigen::Infinity>();
}

/// Evaluates `term`'s AD Hessian, changes its parameters to `changed`, and compares its AD derivatives with
/// those of a term built with `changed` (both paths).
void checkRenewal(EnergyTerm& term, EnergyTerm& fresh, const std::vector<double>& changed, const Eigen::VectorXd& x) {
  EvalOptions ad, analytic;
  ad.path = DerivativePath::AutoDiff;
  const DenseDerivatives before = evaluateDense(term, x, ad);
  term.setParameterValues(changed);
  const DenseDerivatives after = evaluateDense(term, x, ad), reference = evaluateDense(fresh, x, ad),
                         closedForm = evaluateDense(fresh, x, analytic);
  CHECK(relativeGap(before.hessian, reference.hessian) > 1e-3);  // the change is visible
  CHECK(relativeGap(after.hessian, reference.hessian) <= 1e-12);
  CHECK(relativeGap(after.hessian, closedForm.hessian) <= 1e-10);
  CHECK((after.gradient - closedForm.gradient).lpNorm<Eigen::Infinity>() <=
        1e-10 * closedForm.gradient.lpNorm<Eigen::Infinity>());
}

}  // namespace

TEST_CASE("quadratic densities: the AD path's per-face density Hessians follow a parameter change") {
  const CheckMesh m = makeCheckMeshes().back();
  const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 5).x;
  SECTION("membrane") {
    MembraneTerm term(m.mesh, m.reference, 0.3, 0.7), fresh(m.mesh, m.reference, 0.9, 0.2);
    checkRenewal(term, fresh, {0.9, 0.2}, x);
  }
  SECTION("bending") {
    BendingTerm term(m.mesh, m.topology, m.reference, 0.3, 0.7), fresh(m.mesh, m.topology, m.reference, 0.9, 0.2);
    checkRenewal(term, fresh, {0.9, 0.2}, x);
  }
}
