#include "tools/fit/fit_optimizer.h"
#include "fit_test_util.h"
#include "tools/fit/static_fit_problem.h"

#include "core/mesh_generators.h"
#include "energies/shell/shell_terms.h"
#include "../../solvers/parameterized_springs.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <memory>

using namespace jetshell;

namespace {

/// The fit parameters are the springs' (k, c) themselves.
ParameterMapping springMapping() {
  ParameterMapping mapping;
  mapping.numParameters = 2;
  mapping.termParameters = {{"springs", "k"}, {"springs", "c"}};
  mapping.map = [](const Eigen::VectorXd& q, Eigen::VectorXd& v, Eigen::MatrixXd* J) {
    v = q;
    if (J) *J = Eigen::MatrixXd::Identity(2, 2);
  };
  return mapping;
}

LoadSteppingOptions tightSteps() {
  LoadSteppingOptions o;
  o.newton.residualTolerance = 1e-12;
  o.newton.decrementTolerance = 1e-30;
  return o;
}

/// The spring net of tests/solvers/adjoint_test.cpp as a fit problem: parameters (k, c) of the springs, the
/// z displacement of every interior vertex observed at load factors 0.5 and 1.
struct SpringFit {
  TriMesh mesh = makeRectangleGrid(1.0, 1.0, 4, 4);
  std::shared_ptr<testing::ParameterizedSprings> springs;
  std::shared_ptr<NodalForceTerm> loads;
  std::unique_ptr<Objective> objective;
  std::unique_ptr<StaticFitProblem> problem;
  std::vector<int> interior;

  explicit SpringFit(const Eigen::Vector2d& truth, double weight = 1.0) {
    springs = std::make_shared<testing::ParameterizedSprings>(mesh, 1.0, 1.0, 0.9);
    objective = std::make_unique<Objective>(mesh.numVertices());
    objective->addTerm(springs);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * mesh.numVertices());
    PrescribedPositions fixed;
    for (int v = 0; v < mesh.numVertices(); ++v) {
      const double x = mesh.V(v, 0), y = mesh.V(v, 1);
      if (x == 0.0 || y == 0.0 || x == 1.0 || y == 1.0) {
        fixed.fixVertex(v, mesh.V.row(v).transpose());
      } else {
        f[3 * v + 2] = 0.05 * (1.0 + x + 2.0 * y);
        interior.push_back(v);
      }
    }
    loads = makeNodalForceTerm(f);
    objective->addTerm(loads);
    objective->setPrescribed(fixed);
    // The force the solves' tolerances scale with (objective.h): without it the unloaded level's residual, pure
    // rounding (zero or 1e-18 N, by instruction set), would be its own scale.
    PhysicalScales scales;
    scales.force = f.lpNorm<Eigen::Infinity>();
    objective->setScales(scales);
    const ParameterMapping mapping = springMapping();
    const LoadSteppingOptions o = tightSteps();
    // Synthetic observations: the equilibria with the true parameters.
    std::vector<ObservedCoordinate> observed;
    for (int level = 0; level < 2; ++level)
      for (int v : interior) observed.push_back({level, 3 * v + 2, 0.0, weight, 0});
    problem = std::make_unique<StaticFitProblem>(*objective, LoadFactorHooks{loads.get(), nullptr, {}, {}},
                                                 flatten(mesh.V), mapping, std::vector<double>{0.5, 1.0}, observed,
                                                 o);
    const FitEvaluation e = problem->evaluate(truth, FitDerivatives::None);
    REQUIRE(e.ok);
    for (ObservedCoordinate& c : observed) c.target = e.equilibria[static_cast<std::size_t>(c.level)][c.dof];
    problem = std::make_unique<StaticFitProblem>(*objective, LoadFactorHooks{loads.get(), nullptr, {}, {}},
                                                 flatten(mesh.V), mapping, std::vector<double>{0.5, 1.0}, observed,
                                                 o);
  }
};

std::vector<FitVariable> variables() {
  return {{"k", 0.8, 0.1, 10.0, true}, {"c", 60.0, 1.0, 1000.0, true}};
}

/// Fits (k, c) with algorithm a from (0.8, 60), stopping on the parameter step only; checks that it recovered
/// the truth to 1e-6.
FitResult recover(SpringFit& fit, const Eigen::Vector2d& truth, FitAlgorithm a) {
  FitOptions o;
  o.algorithm = a;
  o.maxEvaluations = 400;
  o.parameterTolerance = 1e-10;
  o.misfitTolerance = 0.0;
  FitResult r = runFit(*fit.problem, variables(), o);
  INFO(toString(a) << ": " << r.termination << " " << r.message << " after " << r.counters.evaluations
                   << " evaluations; q = " << r.q.transpose());
  CHECK(r.success);
  CHECK(std::abs(r.q[0] / truth[0] - 1.0) <= 1e-6);
  CHECK(std::abs(r.q[1] / truth[1] - 1.0) <= 1e-6);
  return r;
}

}  // namespace

TEST_CASE("fit: adjoint gradient equals the forward-sensitivity Jᵀr and central differences", "[fit]") {
  SpringFit fit(Eigen::Vector2d(1.3, 40.0));
  const Eigen::Vector2d q(0.9, 55.0);
  const FitEvaluation g = fit.problem->evaluate(q, FitDerivatives::Gradient);
  const FitEvaluation j = fit.problem->evaluate(q, FitDerivatives::Jacobian);
  REQUIRE(g.ok);
  REQUIRE(j.ok);
  CHECK((g.gradient - j.gradient).norm() <= 1e-9 * g.gradient.norm());
  // Two levels: one factorization and one solve each for the adjoint gradient.
  CHECK(fit.problem->counters().sensitivityFactorizations == 4);
  CHECK(fit.problem->counters().sensitivitySolves == 2 + 4);
  test::checkAgainstCentralDifferences(*fit.problem, q, g.gradient, 1e-4, "adjoint");
}

TEST_CASE("fit: every algorithm recovers known parameters from synthetic observations", "[fit]") {
  const Eigen::Vector2d truth(1.3, 40.0);
  for (FitAlgorithm a : {FitAlgorithm::LevenbergMarquardt, FitAlgorithm::Lbfgs, FitAlgorithm::Mma,
                         FitAlgorithm::Bobyqa, FitAlgorithm::NelderMead}) {
    SpringFit fit(truth);
    const FitResult r = recover(fit, truth, a);
    CHECK(r.history.size() == static_cast<std::size_t>(r.counters.evaluations));
    if (a == FitAlgorithm::Lbfgs || a == FitAlgorithm::Mma) {
      // The adjoint: one extra factorization and one solve per observed level per evaluation.
      CHECK(r.counters.sensitivitySolves == 2 * r.counters.gradientEvaluations);
    }
  }
}

TEST_CASE("fit: the gradient-based NLopt methods do not depend on the misfit's units", "[fit]") {
  // Weights of 1e-12 scale the misfit (and its gradient) by 1e-12 and leave the minimum where it was. NLopt's
  // L-BFGS has an absolute gradient tolerance (1e-8) and MMA an absolute floor on its penalty (1e-5): on the raw
  // misfit L-BFGS stopped at its first point and MMA crept; they now see the misfit relative to the first one.
  const Eigen::Vector2d truth(1.3, 40.0);
  for (FitAlgorithm a : {FitAlgorithm::Lbfgs, FitAlgorithm::Mma}) {
    SpringFit fit(truth, 1e-12);
    const FitResult r = recover(fit, truth, a);
    CHECK(r.counters.evaluations > 3);
  }
}

TEST_CASE("fit: a stop request ends every algorithm before its next evaluation, with the best values so far",
          "[fit]") {
  // Measured before: `jetshell fit` stopped by Ctrl-C died with nothing written, its evaluations lost.
  const Eigen::Vector2d truth(1.3, 40.0);
  for (FitAlgorithm a : {FitAlgorithm::LevenbergMarquardt, FitAlgorithm::Lbfgs, FitAlgorithm::Bobyqa}) {
    SpringFit fit(truth);
    FitOptions o;
    o.algorithm = a;
    o.maxEvaluations = 400;
    o.parameterTolerance = 1e-10;
    int asked = 0;
    o.stopRequested = [&asked] { return ++asked > 4; };
    const FitResult r = runFit(*fit.problem, variables(), o);
    INFO(toString(a) << ": " << r.termination << " " << r.message);
    CHECK(r.interrupted);
    CHECK_FALSE(r.success);
    CHECK(r.termination == "INTERRUPTED");
    CHECK(r.history.size() == 4);  // no evaluation after the request
    CHECK(r.counters.evaluations == 4);
    CHECK_THAT(r.message, Catch::Contains("interrupted after 4 evaluations: the best values so far"));
    // The best of the four, and its misfit.
    double best = std::numeric_limits<double>::infinity();
    for (const FitRecord& rec : r.history) best = std::min(best, rec.misfit);
    CHECK(r.misfit == best);
    CHECK(r.q.size() == 2);
  }
  // Asked before the first evaluation: nothing evaluated, nothing made up.
  SpringFit fit(truth);
  FitOptions o;
  o.stopRequested = [] { return true; };
  const FitResult r = runFit(*fit.problem, variables(), o);
  CHECK(r.interrupted);
  CHECK(r.history.empty());
  CHECK(r.q.size() == 0);
  CHECK_THAT(r.message, Catch::Contains("interrupted after 0 evaluations"));
}

TEST_CASE("fit problem: one load path lands on every observed level, level 0 included", "[fit]") {
  // The springs' equilibria at λ = 0, 0.3, 0.5, 1 from one evaluation equal those of separate paths to each level.
  SpringFit fit(Eigen::Vector2d(1.3, 40.0));
  const Eigen::Vector2d q(0.9, 55.0);
  const int dof = 3 * fit.interior[0] + 2;
  const LoadSteppingOptions o = tightSteps();
  const ParameterMapping mapping = springMapping();
  auto solve = [&](const std::vector<double>& levels) {
    std::vector<ObservedCoordinate> observed;
    for (int k = 0; k < static_cast<int>(levels.size()); ++k) observed.push_back({k, dof, 0.0, 1.0, 0});
    StaticFitProblem p(*fit.objective, LoadFactorHooks{fit.loads.get(), nullptr, {}, {}}, flatten(fit.mesh.V), mapping,
                       levels, observed, o);
    const FitEvaluation e = p.evaluate(q, FitDerivatives::Gradient);
    INFO(e.message);
    REQUIRE(e.ok);
    REQUIRE(e.equilibria.size() == levels.size());
    CHECK(p.counters().fullSolves == (levels[0] == 0.0 && levels.size() > 1 ? 2 : 1));
    return e.equilibria;
  };
  const std::vector<Eigen::VectorXd> all = solve({0.0, 0.3, 0.5, 1.0});
  CHECK(all[0].isApprox(flatten(fit.mesh.V)));  // no load at λ = 0: the rest state
  const double levels[3] = {0.3, 0.5, 1.0};
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXd alone = solve({levels[k]})[0];
    INFO("level " << levels[k]);
    CHECK((all[static_cast<std::size_t>(k + 1)] - alone).norm() <= 1e-8 * alone.norm());
    if (k > 0) CHECK(std::abs(all[static_cast<std::size_t>(k + 1)][dof]) > std::abs(all[static_cast<std::size_t>(k)][dof]));
  }
}

TEST_CASE("fit: uncertainty from the Gauss–Newton approximation", "[fit]") {
  // y = a + b t with known noise: the covariance of linear least squares.
  Eigen::MatrixXd J(4, 2);
  J << 1, 0, 1, 1, 1, 2, 1, 3;
  const Eigen::Vector4d r(0.1, -0.2, 0.2, -0.1);
  const FitUncertainty u = gaussNewtonUncertainty(J, r);
  REQUIRE(u.available);
  const Eigen::Matrix2d C = (J.transpose() * J).inverse() * (r.squaredNorm() / 2.0);
  CHECK(u.standardDeviation[0] == Approx(std::sqrt(C(0, 0))));
  CHECK(u.standardDeviation[1] == Approx(std::sqrt(C(1, 1))));
  CHECK(u.correlation(0, 1) == Approx(C(0, 1) / std::sqrt(C(0, 0) * C(1, 1))));
  Eigen::MatrixXd singular(3, 2);
  singular << 1, 2, 1, 2, 1, 2;
  CHECK_FALSE(gaussNewtonUncertainty(singular, Eigen::Vector3d(0.1, 0.2, 0.3)).available);
}
