#include "core/mesh.h"
#include "energies/kinetic_terms.h"
#include "solvers/objective.h"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

using namespace jetshell;

TEST_CASE("kinetic terms: value, gradient and diagonal Hessian of ½ c Σ m |x − y|²") {
  const Eigen::VectorXd mass = (Eigen::VectorXd(3) << 0.5, 1.0, 2.0).finished();
  auto term = makeInertiaTerm(mass);
  Eigen::VectorXd y(9), x(9);
  y << 0, 1, 2, 3, 4, 5, 6, 7, 8;
  x = y;
  x[4] += 0.1;
  x[8] -= 0.2;
  term->setCentre(y, 4.0);
  HessianAssembler A;
  const int slot = A.addStencils(term->stencils());
  A.finalize(3);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(9);
  const double E = term->evaluate(x, {&g, &A, slot}, EvalOptions{});
  CHECK(E == Approx(0.5 * 4.0 * (1.0 * 0.01 + 2.0 * 0.04)));
  CHECK(g[4] == Approx(4.0 * 1.0 * 0.1));
  CHECK(g[8] == Approx(4.0 * 2.0 * -0.2));
  CHECK(g.cwiseAbs().sum() == Approx(0.4 + 1.6));
  const Eigen::MatrixXd H(A.matrix());
  for (int i = 0; i < 9; ++i) CHECK(H(i, i) == Approx(4.0 * mass[i / 3]));
  CHECK((H - Eigen::MatrixXd(H.diagonal().asDiagonal())).norm() == 0.0);
  CHECK_THROWS_AS(term->setCentre(y, -1.0), InputError);
  CHECK_THROWS_AS(makeMassDampingTerm((Eigen::VectorXd(1) << -1.0).finished()), InputError);
}

TEST_CASE("objective: fixed dofs are eliminated and terms are listed by name") {
  const Eigen::VectorXd mass = Eigen::VectorXd::Ones(2);
  Objective obj(2);
  auto inertia = makeInertiaTerm(mass);
  inertia->setCentre(Eigen::VectorXd::Zero(6), 1.0);
  obj.addTerm(inertia, TermRole::Transient);
  CHECK_THROWS_AS(obj.addTerm(makeInertiaTerm(mass)), InputError);  // duplicate name
  PrescribedPositions p;
  p.fix(1, 2, [](double t) { return 2.0 * t; });
  CHECK_THROWS_AS(p.fix(0, 3, 1.0), InputError);
  obj.setPrescribed(p);
  CHECK(obj.numFreeDofs() == 5);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(6), g;
  obj.applyPrescribed(0.25, x);
  CHECK(x[5] == 0.5);
  obj.evaluate(x, &g, true, EvalOptions{});
  CHECK(g[5] == 0.0);
  CHECK(g[4] == 1.0);
  const Eigen::MatrixXd H(obj.assembler().matrix());
  CHECK(H(5, 5) == 1.0);
  CHECK(obj.activeTermNames() == std::vector<std::string>{"inertia"});
  CHECK(obj.evaluate(x, nullptr, false, EvalOptions{}, TermSelection::PotentialOnly) == 0.0);
  CHECK_THROWS_AS(obj.addTerm(makeMassDampingTerm(mass)), InputError);  // after finalize
  PrescribedPositions outOfRange;
  outOfRange.fix(5, 0, 0.0);
  Objective other(2);
  CHECK_THROWS_AS(other.setPrescribed(outOfRange), InputError);
}
