#include "core/parameter_derivatives.h"
#include "energies/element_energy_term.h"
#include "energies/examples/seam_spring.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

using namespace jetshell;
using namespace jetshell::test;

namespace {

/// A functor written before parameters existed: no kParameters.
struct PlainSpring {
  static constexpr int kVertices = 2;
  template <typename T>
  T operator()(const T* x, int) const {
    const T s = norm(load3(x + 3) - load3(x)) - constant<T>(1.0);
    return constant<T>(0.5) * s * s;
  }
};

}  // namespace

TEST_CASE("parameter derivatives: a spring's dE/dk and d2E/dxdk from duals equal E/k and g/k") {
  TriMesh mesh;
  mesh.V.resize(3, 3);
  mesh.V << 0, 0, 0, 2, 0, 0, 0, 1, 0;
  const EnergyTermPtr term = makeSeamSpringTerm(mesh, {{0, 1}, {1, 2}}, 5.0);
  REQUIRE(term->parameterNames() == std::vector<std::string>{"stiffness"});
  REQUIRE(term->parameterValues() == std::vector<double>{5.0});
  Eigen::VectorXd x = flatten(mesh.V);
  x += 0.3 * Eigen::VectorXd::LinSpaced(x.size(), -1.0, 1.0);
  const DenseDerivatives d = evaluateDense(*term, x, EvalOptions{}, false);
  ParameterDerivatives p;
  term->evaluateParameterDerivatives(x, p);
  REQUIRE(p.energy.size() == 1);
  REQUIRE(p.mixed.rows() == x.size());
  REQUIRE(p.mixed.cols() == 1);
  // E is linear in k: ∂E/∂k = E/k, ∂g/∂k = g/k.
  CHECK(p.energy[0] == Approx(d.energy / 5.0).epsilon(1e-14));
  CHECK((p.mixed.col(0) - d.gradient / 5.0).norm() <= 1e-14 * d.gradient.norm());
  // Changing the parameter changes later evaluations.
  term->setParameterValues({10.0});
  CHECK(term->evaluate(x, EvalRequest{}, EvalOptions{}) == Approx(2.0 * d.energy).epsilon(1e-14));
  CHECK_THROWS_AS(term->setParameterValues({1.0, 2.0}), InputError);
  CHECK_THROWS_WITH(term->setParameterValues({std::nan("")}), Catch::Contains("stiffness"));
}

TEST_CASE("parameter derivatives: a functor without parameters keeps working and has none") {
  StencilTable t{2, {0, 1}};
  ElementEnergyTerm<PlainSpring> term("plain", t, 2, PlainSpring{});
  CHECK(term.parameterNames().empty());
  Eigen::VectorXd x(6);
  x << 0, 0, 0, 1.5, 0, 0;
  CHECK(term.evaluate(x, EvalRequest{}, EvalOptions{}) == Approx(0.125));
  ParameterDerivatives p;
  term.evaluateParameterDerivatives(x, p);
  CHECK(p.energy.size() == 0);
  CHECK(p.mixed.rows() == 6);
  CHECK(p.mixed.cols() == 0);
  CHECK_THROWS_AS(term.setParameterValues({1.0}), InputError);
}

TEST_CASE("parameter derivatives: every registered term with parameters agrees with finite differences") {
  ScopedThreads serial(1);
  int terms = 0;
  for (const RegisteredTerm& entry : termRegistry()) {
    for (const CheckMesh& m : makeCheckMeshes()) {
      const EnergyTermPtr term = buildTerm(entry, m);
      if (term->parameterNames().empty()) continue;
      DerivativeCheckOptions o;
      o.evalOptions = entry.options;
      for (ConfigurationKind kind : {ConfigurationKind::Random, ConfigurationKind::Fold}) {
        const CheckConfiguration c = makeCheckConfiguration(m, kind, 77);
        INFO(entry.name << ": " << c.description);
        const ParameterCheckResult r = checkParameterDerivatives(*term, c.x, o);
        for (const std::string& f : checkFailures(r, DerivativeTolerances{})) FAIL_CHECK(f);
        CHECK(r.parameters.size() == term->parameterNames().size());
        // Measured <= 3e-12 over the registry (check-derivatives --parameters); the parameters are restored.
        CHECK(term->parameterValues() == buildTerm(entry, m)->parameterValues());
      }
      ++terms;
    }
  }
  CHECK(terms >= 2 * 13);
}
