#include "core/mesh.h"
#include "solvers/cholmod_factor.h"
#include "solvers/linear_solver.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

using namespace jetshell;

TEST_CASE("fill ordering: every ordering gives the same solution and reports its fill and flops", "[solvers]") {
  testing::SingleThread single;
  ShellSystem shell(testing::hangingCloth(0.3, 0.3, 8, 8), AnalysisKind::Dynamics);
  Eigen::VectorXd x = shell.restPositions(), g;
  shell.inertia->setCentre(x, 3600.0);
  shell.objective().evaluate(x, &g, true, EvalOptions{});
  const Eigen::SparseMatrix<double>& H = shell.objective().assembler().matrix();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(H.rows(), -1.0, 1.0);
  Eigen::VectorXd first;
  for (FillOrdering o : {FillOrdering::AMD, FillOrdering::METIS, FillOrdering::NESDIS, FillOrdering::Auto}) {
    INFO(toString(o));
    CholmodFactor f(o);
    REQUIRE(f.analyze(H) == CholmodFactor::Status::Ok);
    REQUIRE(f.factorize(H, 0.0) == CholmodFactor::Status::Ok);
    Eigen::VectorXd sol;
    REQUIRE(f.solve(b, sol) == CholmodFactor::Status::Ok);
    if (first.size() == 0) first = sol;
    CHECK((sol - first).norm() <= 1e-9 * first.norm());
    const FactorStatistics& s = f.statistics();
    CHECK(s.nnzL >= static_cast<double>(H.rows()));  // at least the diagonal
    CHECK(s.nnzL >= s.nnzA);                          // L holds A's pattern (plus fill)
    CHECK(s.flops > s.nnzL);
    if (o == FillOrdering::AMD) CHECK(s.ordering == "amd");
  }
}

TEST_CASE("fill ordering: names parse, and a bad name is an input error naming it", "[solvers]") {
  for (FillOrdering o : {FillOrdering::Auto, FillOrdering::AMD, FillOrdering::METIS, FillOrdering::NESDIS})
    CHECK(fillOrderingFromString(toString(o)) == o);
  CHECK_THROWS_AS(fillOrderingFromString("colamd"), InputError);
  CHECK_THROWS_WITH(fillOrderingFromString("colamd"), Catch::Contains("colamd"));
}
