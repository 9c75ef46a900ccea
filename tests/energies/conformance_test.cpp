// The conformance suite: every term in the registry (energies/registry.h) goes through the same checks, so a
// newly registered term is enrolled automatically. Limits are set from measured values (quoted beside each)
// with a margin of 100× or more.
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace jetshell;
using namespace jetshell::test;

namespace {

const std::vector<CheckMesh>& meshes() {
  static const std::vector<CheckMesh> m = makeCheckMeshes();
  return m;
}

std::vector<DerivativePath> pathsOf(EnergyTerm& term) {
  if (term.hasAnalytic()) return {DerivativePath::AutoDiff, DerivativePath::Analytic};
  return {DerivativePath::AutoDiff};
}

const char* pathName(DerivativePath p) { return p == DerivativePath::AutoDiff ? "autodiff" : "analytic"; }

}  // namespace

TEST_CASE("conformance: the registry holds the built-in terms and the example, each name once") {
  std::set<std::string> names;
  for (const RegisteredTerm& t : termRegistry()) {
    INFO(t.name);
    CHECK(names.insert(t.name).second);
    CHECK(t.make);
    CHECK_FALSE(t.summary.empty());
  }
  for (const char* required :
       {"membrane", "bending", "bending_gauss_newton", "bending_clamped", "bending_mirrored_clamp", "bending_nested_jet",
        "gravity", "nodal_forces", "inertia", "mass_damping", "membrane_damping", "bending_damping", "end_moment",
        "seam_spring", "hinge_bending", "membrane_staged", "bending_second_order_free", "bending_symmetry_plane",
        "membrane_staged_damping",
        "contact_penalty", "contact_penalty_sphere_faces", "contact_penalty_moving_capsule", "contact_damping",
        "contact_friction", "pointcloud_penalty", "pointcloud_friction"})
    CHECK(names.count(required) == 1);
  CHECK(findRegisteredTerm("membrane") == &termRegistry().front());
  CHECK(findRegisteredTerm("no_such_term") == nullptr);
}

TEST_CASE("conformance: zero energy and gradient at rest") {
  ScopedThreads serial(1);
  int checked = 0;
  for (const RegisteredTerm& entry : termRegistry()) {
    for (const CheckMesh& m : meshes()) {
      const EnergyTermPtr term = buildTerm(entry, m);
      if (!term->zeroAtRest()) continue;
      const Eigen::VectorXd X = flatten(m.mesh.V);
      const double ell = configurationLengthScale(X);
      for (DerivativePath path : pathsOf(*term)) {
        INFO(entry.name << " on " << m.name << ", " << pathName(path));
        const DenseDerivatives d = evaluateDense(*term, X, optionsFor(entry, path));
        // The term's scale at rest: ‖H‖ℓ² (an energy) and ‖H‖ℓ (a force). Measured over the registry:
        // |E| <= 5e-34 ‖H‖ℓ², ‖g‖ <= 1.3e-17 ‖H‖ℓ (round-off of B − b on the analytic path).
        const double hNorm = d.hessian.norm();
        REQUIRE(hNorm > 0.0);
        CHECK(std::abs(d.energy) <= 1e-14 * hNorm * ell * ell);
        CHECK(d.gradient.norm() <= 1e-14 * hNorm * ell);
        ++checked;
      }
    }
  }
  CHECK(checked >= 10);
}

TEST_CASE("conformance: invariance under rigid motions") {
  ScopedThreads serial(1);
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> normal;
  for (const RegisteredTerm& entry : termRegistry()) {
    for (const CheckMesh& m : meshes()) {
      const EnergyTermPtr term = buildTerm(entry, m);
      const CheckConfiguration c = makeCheckConfiguration(m, ConfigurationKind::Random, 17);
      const Eigen::Matrix3d R =
          Eigen::AngleAxisd(2.5, Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized())
              .toRotationMatrix();
      const Eigen::Vector3d t(0.7, -1.3, 0.4);
      const Eigen::VectorXd y = rigidlyMoved(c.x, R, t);
      for (DerivativePath path : pathsOf(*term)) {
        INFO(entry.name << " on " << m.name << ", " << pathName(path));
        const DenseDerivatives a = evaluateDense(*term, c.x, optionsFor(entry, path));
        const DenseDerivatives b = evaluateDense(*term, y, optionsFor(entry, path));
        const double ell = configurationLengthScale(c.x);
        const double scale = std::max({std::abs(a.energy), a.gradient.norm() * ell, a.hessian.norm() * ell * ell});
        const double eDiff = std::abs(b.energy - a.energy) / scale;
        if (!term->rigidInvariant()) {
          // The flag must be honest: a term that claims no invariance does see this motion.
          CHECK(eDiff > 1e-6);
          continue;
        }
        // Measured over the registry: energy 1.6e-17, gradient 1.3e-16, Hessian 8.5e-16 relative to the
        // term's scale.
        CHECK(eDiff <= 1e-13);
        CHECK((b.gradient - rotateEach(R, a.gradient)).norm() <= 1e-13 * scale / ell);
        CHECK((b.hessian - rotateHessian(R, a.hessian)).norm() <= 1e-13 * scale / (ell * ell));
      }
    }
  }
}

TEST_CASE("conformance: symmetric Hessian, AD equal to analytic, agreement with finite differences") {
  ScopedThreads serial(1);
  // The checker's default limits (AD vs analytic 1e-10, vs FD and asymmetry 1e-8): tools/checks/derivative_check.h
  // quotes what they were measured against.
  const DerivativeTolerances tol;
  for (const RegisteredTerm& entry : termRegistry()) {
    DerivativeCheckOptions options;
    options.evalOptions = entry.options;
    options.hessianIsExact = entry.hessianIsExact;
    int checked = 0;
    for (const CheckMesh& m : meshes()) {
      const EnergyTermPtr term = buildTerm(entry, m);
      for (ConfigurationKind kind : kConfigurationKinds) {
        if (entry.singularAtFold && kind == ConfigurationKind::Fold) continue;
        const CheckConfiguration c = makeCheckConfiguration(m, kind, 1000 + static_cast<int>(kind));
        INFO(entry.name << ": " << c.description);
        const DerivativeCheckResult r = checkDerivatives(*term, c.x, options);
        for (const std::string& failure : checkFailures(r, tol)) FAIL_CHECK(failure);
        CHECK(r.paths.size() == (term->hasAnalytic() ? 2u : 1u));
        CHECK(r.maxHessianAsymmetry() <= tol.asymmetry);
        if (term->hasAnalytic()) {
          REQUIRE(r.maxAdVsAnalytic());
          CHECK(*r.maxAdVsAnalytic() <= tol.adVsAnalytic);
        }
        ++checked;
      }
    }
    CHECK(checked == (entry.singularAtFold ? 8 : 10));
  }
}

TEST_CASE("conformance: a Gauss-Newton Hessian equals the exact one at rest and differs away from it") {
  ScopedThreads serial(1);
  const RegisteredTerm* gn = findRegisteredTerm("bending_gauss_newton");
  REQUIRE(gn);
  for (const CheckMesh& m : meshes()) {
    const EnergyTermPtr term = buildTerm(*gn, m);
    EvalOptions exact = gn->options;
    exact.hessianModel = HessianModel::Exact;
    const Eigen::VectorXd X = flatten(m.mesh.V);
    const Eigen::MatrixXd atRestGn = evaluateDense(*term, X, gn->options).hessian;
    const Eigen::MatrixXd atRestExact = evaluateDense(*term, X, exact).hessian;
    // At rest the bending moments w vanish, and with them the dropped part Σ w_k ∇²b_k. Measured <= 5.6e-17
    // at rest, 0.17–0.23 away from it.
    CHECK((atRestGn - atRestExact).norm() <= 1e-13 * atRestExact.norm());
    const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 3).x;
    const Eigen::MatrixXd gnH = evaluateDense(*term, x, gn->options).hessian;
    const Eigen::MatrixXd exactH = evaluateDense(*term, x, exact).hessian;
    CHECK((gnH - exactH).norm() > 1e-3 * exactH.norm());
  }
}
