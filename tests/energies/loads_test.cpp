#include "energies/shell/shell_terms.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace jetshell;

TEST_CASE("gravity: the load factor scales the energy, the gradient and the density derivative", "[gravity]") {
  const Eigen::VectorXd mass = (Eigen::VectorXd(3) << 0.5, 1.0, 2.0).finished();
  auto term = makeGravityTerm(mass, Eigen::Vector3d(0.3, -9.81, 0.1), 800.0);
  const Eigen::VectorXd x = (Eigen::VectorXd(9) << 0.1, 0.2, -0.3, 1.0, 0.4, 0.2, -0.5, 1.5, 0.7).finished();
  auto evaluateAt = [&](double lambda, Eigen::VectorXd& g, ParameterDerivatives& d) {
    term->setLoadFactor(lambda);
    g = Eigen::VectorXd::Zero(9);
    EvalRequest request;
    request.gradient = &g;
    const double e = term->evaluate(x, request, EvalOptions{});
    term->evaluateParameterDerivatives(x, d);
    return e;
  };
  Eigen::VectorXd gFull, gHalf;
  ParameterDerivatives dFull, dHalf;
  const double eFull = evaluateAt(1.0, gFull, dFull), eHalf = evaluateAt(0.5, gHalf, dHalf);
  CHECK(term->loadFactor() == 0.5);
  REQUIRE(std::abs(eFull) > 1.0);
  CHECK(eHalf == Approx(0.5 * eFull).epsilon(1e-14));
  CHECK((gHalf - 0.5 * gFull).norm() <= 1e-14 * gFull.norm());
  CHECK(dHalf.energy[0] == Approx(0.5 * dFull.energy[0]).epsilon(1e-14));
  CHECK((dHalf.mixed - 0.5 * dFull.mixed).norm() <= 1e-14 * dFull.mixed.norm());
  // At λ = 1 the energy is −Σ m g·x.
  double expected = 0.0;
  for (int v = 0; v < 3; ++v) expected -= mass[v] * Eigen::Vector3d(0.3, -9.81, 0.1).dot(x.segment<3>(3 * v));
  CHECK(eFull == Approx(expected).epsilon(1e-14));
}

TEST_CASE("gravity: a non-finite load factor is rejected and leaves the term unchanged, a negative one reverses it",
          "[gravity]") {
  auto term = makeGravityTerm(Eigen::VectorXd::Ones(2), Eigen::Vector3d(0, 0, -9.81));
  term->setLoadFactor(0.25);
  CHECK_THROWS_AS(term->setLoadFactor(std::nan("")), InputError);
  CHECK_THROWS_AS(term->setLoadFactor(std::numeric_limits<double>::infinity()), InputError);
  CHECK_THROWS_AS(term->setLoadFactor(-std::numeric_limits<double>::infinity()), InputError);
  CHECK(term->loadFactor() == 0.25);
  // Arc-length control may take λ below 0 (a path turning back past a limit point): the weight reverses.
  const Eigen::VectorXd x = (Eigen::VectorXd(6) << 0.0, 0.0, 1.0, 0.0, 0.0, 2.0).finished();
  const double up = term->evaluate(x, EvalRequest{}, EvalOptions{});
  term->setLoadFactor(-0.25);
  CHECK(term->loadFactor() == -0.25);
  CHECK(term->evaluate(x, EvalRequest{}, EvalOptions{}) == Approx(-up).epsilon(1e-14));
}
