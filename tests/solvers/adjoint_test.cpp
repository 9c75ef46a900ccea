#include "solvers/adjoint.h"

#include "core/mesh_generators.h"
#include "energies/shell/shell_terms.h"
#include "parameterized_springs.h"
#include "solvers/newton.h"

#include <catch2/catch.hpp>

#include <memory>

using namespace jetshell;

namespace {

/// A pretensioned spring net over the unit square (4 × 4 squares), boundary pinned, interior pulled along z.
struct SpringNet {
  TriMesh mesh = makeRectangleGrid(1.0, 1.0, 4, 4);
  std::shared_ptr<testing::ParameterizedSprings> springs;
  std::unique_ptr<Objective> objective;
  std::vector<int> observed{6, 12, 17};  // interior vertices whose z is observed

  explicit SpringNet(double k, double c) {
    springs = std::make_shared<testing::ParameterizedSprings>(mesh, k, c, 0.9);
    objective = std::make_unique<Objective>(mesh.numVertices());
    objective->addTerm(springs);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * mesh.numVertices());
    PrescribedPositions fixed;
    for (int v = 0; v < mesh.numVertices(); ++v) {
      const double x = mesh.V(v, 0), y = mesh.V(v, 1);
      if (x == 0.0 || y == 0.0 || x == 1.0 || y == 1.0) fixed.fixVertex(v, mesh.V.row(v).transpose());
      else f[3 * v + 2] = 0.02 * (1.0 + x + 2.0 * y);  // uneven, so the parameters act differently
    }
    objective->addTerm(makeNodalForceTerm(f));
    objective->setPrescribed(fixed);
  }

  Eigen::VectorXd solve() {
    NewtonOptions o;
    o.residualTolerance = 1e-13;
    o.decrementTolerance = 1e-30;
    o.maxIterations = 100;
    NewtonSolver newton(*objective, o);
    Eigen::VectorXd x = flatten(mesh.V);
    const SolverSummary s = newton.minimize(x);
    INFO(s.message);
    REQUIRE(s.converged());
    return x;
  }

  /// f = ½ Σ (z_v − target_v)²
  double misfit(const Eigen::VectorXd& x, Eigen::VectorXd* dfdx = nullptr) const {
    double f = 0.0;
    if (dfdx) *dfdx = Eigen::VectorXd::Zero(x.size());
    for (std::size_t i = 0; i < observed.size(); ++i) {
      const int v = observed[i];
      const double r = x[3 * v + 2] - 0.05 * static_cast<double>(i + 1);
      f += 0.5 * r * r;
      if (dfdx) (*dfdx)[3 * v + 2] = r;
    }
    return f;
  }
};

const std::vector<TermParameter> kParameters = {{"springs", "k"}, {"springs", "c"}};

}  // namespace

TEST_CASE("adjoint: the test term's mixed derivative matches finite differences of its gradient", "[adjoint]") {
  SpringNet net(1.0, 50.0);
  const Eigen::VectorXd x = net.solve();
  EquilibriumSensitivity sensitivity(*net.objective);
  const Eigen::MatrixXd mixed = sensitivity.mixedDerivatives(x, kParameters);
  for (int j = 0; j < 2; ++j) {
    const double p = termParameterValue(*net.objective, kParameters[j]), h = 1e-6 * p;
    Eigen::VectorXd gp, gm;
    setTermParameterValue(*net.objective, kParameters[j], p + h);
    net.objective->evaluate(x, &gp, false, EvalOptions{});
    setTermParameterValue(*net.objective, kParameters[j], p - h);
    net.objective->evaluate(x, &gm, false, EvalOptions{});
    setTermParameterValue(*net.objective, kParameters[j], p);
    const Eigen::VectorXd fd = (gp - gm) / (2.0 * h);
    CHECK((fd - mixed.col(j)).norm() <= 1e-7 * mixed.col(j).norm());
  }
}

TEST_CASE("adjoint: gradient of a misfit of the equilibrium matches central differences of whole solves",
          "[adjoint]") {
  SpringNet net(1.0, 50.0);
  const Eigen::VectorXd x = net.solve();
  Eigen::VectorXd dfdx;
  net.misfit(x, &dfdx);
  EquilibriumSensitivity sensitivity(*net.objective);
  REQUIRE(sensitivity.factor(x));
  const Eigen::VectorXd grad = adjointGradient(sensitivity, dfdx, sensitivity.mixedDerivatives(x, kParameters));
  CHECK(sensitivity.factorizations() == 1);
  CHECK(sensitivity.solves() == 1);  // one linear solve for both parameters

  for (int j = 0; j < 2; ++j) {
    const double p = termParameterValue(*net.objective, kParameters[j]), h = 1e-4 * p;
    setTermParameterValue(*net.objective, kParameters[j], p + h);
    const double fp = net.misfit(net.solve());
    setTermParameterValue(*net.objective, kParameters[j], p - h);
    const double fm = net.misfit(net.solve());
    setTermParameterValue(*net.objective, kParameters[j], p);
    const double fd = (fp - fm) / (2.0 * h);
    INFO("parameter " << kParameters[j].name << ": adjoint " << grad[j] << ", central difference " << fd);
    CHECK(std::abs(fd - grad[j]) <= 1e-6 * std::abs(fd));
  }
}

TEST_CASE("adjoint: forward sensitivities match central differences of the equilibrium", "[adjoint]") {
  SpringNet net(1.0, 50.0);
  const Eigen::VectorXd x = net.solve();
  EquilibriumSensitivity sensitivity(*net.objective);
  REQUIRE(sensitivity.factor(x));
  const Eigen::MatrixXd S = forwardSensitivities(sensitivity, sensitivity.mixedDerivatives(x, kParameters));
  CHECK(sensitivity.solves() == 2);
  for (int j = 0; j < 2; ++j) {
    const double p = termParameterValue(*net.objective, kParameters[j]), h = 1e-4 * p;
    setTermParameterValue(*net.objective, kParameters[j], p + h);
    const Eigen::VectorXd xp = net.solve();
    setTermParameterValue(*net.objective, kParameters[j], p - h);
    const Eigen::VectorXd xm = net.solve();
    setTermParameterValue(*net.objective, kParameters[j], p);
    const Eigen::VectorXd fd = (xp - xm) / (2.0 * h);
    CHECK((fd - S.col(j)).norm() <= 1e-6 * fd.norm());
  }
}

TEST_CASE("adjoint: unknown terms and parameters are named", "[adjoint]") {
  SpringNet net(1.0, 50.0);
  const Eigen::VectorXd x = flatten(net.mesh.V);
  EquilibriumSensitivity sensitivity(*net.objective);
  CHECK_THROWS_WITH(sensitivity.mixedDerivatives(x, {{"membrane", "lambda"}}), Catch::Contains("no active term named 'membrane'"));
  CHECK_THROWS_WITH(sensitivity.mixedDerivatives(x, {{"springs", "q"}}), Catch::Contains("has no parameter 'q'"));
  CHECK_THROWS_WITH(sensitivity.solve(x), Catch::Contains("no factor"));
}
