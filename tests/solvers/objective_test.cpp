#include "solvers/objective.h"
#include "solvers/shell_system.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

using namespace jetshell;

TEST_CASE("objective: the potential terms' part of the last gradient is kept for the positions it was taken at",
          "[objective]") {
  ShellProblem problem = testing::cantileverPlate(4, 2, 0.01);
  ShellSystem system(problem, AnalysisKind::DynamicRelaxation);  // potentials, then inertia and mass damping
  REQUIRE(system.inertia);
  REQUIRE(system.massDamping);
  Objective& obj = system.objective();
  const Eigen::VectorXd X = system.restPositions();
  Eigen::VectorXd x = X, y = X;
  for (Eigen::Index i = 0; i < x.size(); i += 3) x[i + 2] += 1e-3 * std::sin(0.7 * static_cast<double>(i));
  y[y.size() - 1] += 1e-3;
  system.inertia->setCentre(X, 100.0);
  system.massDamping->setCentre(X, 10.0);

  Eigen::VectorXd all, potential;
  obj.evaluate(x, &potential, false, EvalOptions{}, TermSelection::PotentialOnly);
  CHECK(obj.lastPotentialGradient(x, DerivativePath::Analytic) != nullptr);
  obj.evaluate(x, &all, true, EvalOptions{});
  REQUIRE(obj.lastPotentialGradient(x, DerivativePath::Analytic) != nullptr);
  const Eigen::VectorXd kept = *obj.lastPotentialGradient(x, DerivativePath::Analytic);
  CHECK((kept - potential).lpNorm<Eigen::Infinity>() <= 1e-12 * potential.lpNorm<Eigen::Infinity>());
  CHECK((all - kept).lpNorm<Eigen::Infinity>() > 0.0);  // the transient terms are not in it
  // Other positions, another derivative path: nothing.
  CHECK(obj.lastPotentialGradient(y, DerivativePath::Analytic) == nullptr);
  CHECK(obj.lastPotentialGradient(x, DerivativePath::AutoDiff) == nullptr);
  // An energy-only evaluation elsewhere keeps it; a gradient elsewhere replaces it.
  obj.evaluate(y, nullptr, false, EvalOptions{});
  CHECK(obj.lastPotentialGradient(x, DerivativePath::Analytic) != nullptr);
  Eigen::VectorXd g;
  obj.evaluate(y, &g, false, EvalOptions{});
  CHECK(obj.lastPotentialGradient(x, DerivativePath::Analytic) == nullptr);
  CHECK(obj.lastPotentialGradient(y, DerivativePath::Analytic) != nullptr);
}

TEST_CASE("objective: a second term of the same name is refused, however many terms came before", "[objective]") {
  ShellProblem problem = testing::cantileverPlate(4, 2, 0.01);
  ShellSystem system(problem, AnalysisKind::DynamicRelaxation);
  REQUIRE(system.membrane);
  Objective obj(static_cast<int>(system.restPositions().size() / 3));
  obj.addTerm(system.membrane);
  obj.addTerm(system.inertia);
  CHECK_THROWS_WITH(obj.addTerm(system.membrane),
                    "objective: duplicate term name '" + system.membrane->name() + "'");
}

TEST_CASE("objective: each term's calls and time are counted by the kind of request it answered", "[objective]") {
  ShellProblem problem = testing::cantileverPlate(4, 2, 0.01);
  ShellSystem system(problem, AnalysisKind::DynamicRelaxation);
  Objective& obj = system.objective();
  const Eigen::VectorXd x = system.restPositions();
  const std::vector<std::string> names = obj.activeTermNames();
  const auto bending = static_cast<std::size_t>(
      std::find(names.begin(), names.end(), system.bending->name()) - names.begin());
  REQUIRE(bending < names.size());
  using Kind = Objective::RequestKind;
  const auto calls = [&](Kind k) { return obj.termRequests()[bending].calls[static_cast<std::size_t>(k)]; };
  Eigen::VectorXd g;
  EvalOptions projected;
  projected.projection = PsdProjection::Clamp;
  obj.evaluate(x, nullptr, false, EvalOptions{});
  obj.evaluate(x, nullptr, false, EvalOptions{});
  obj.evaluate(x, &g, false, projected);  // no Hessian: a gradient, whatever the projection
  obj.evaluate(x, &g, true, EvalOptions{});
  obj.evaluate(x, &g, true, projected);
  obj.evaluate(x, &g, true, projected);
  CHECK(calls(Kind::Value) == 2);
  CHECK(calls(Kind::Gradient) == 1);
  CHECK(calls(Kind::Hessian) == 1);
  CHECK(calls(Kind::ProjectedHessian) == 2);
  double seconds = 0.0;
  for (double s : obj.termRequests()[bending].seconds) {
    CHECK(s >= 0.0);
    seconds += s;
  }
  CHECK(seconds == Approx(obj.termSeconds()[bending]).epsilon(1e-9));
}
