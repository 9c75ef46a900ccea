#include "tests/test_util.h"
#include "energies/examples/seam_spring.h"

#include <catch2/catch.hpp>

using namespace jetshell;
using namespace jetshell::test;

TEST_CASE("seam spring example: energy, force and stiffness of one spring") {
  TriMesh mesh;
  mesh.V.resize(3, 3);
  mesh.V << 0, 0, 0, 2, 0, 0, 0, 1, 0;
  const EnergyTermPtr term = makeSeamSpringTerm(mesh, {{0, 1}}, 5.0);
  Eigen::VectorXd x = flatten(mesh.V);
  x[3] = 3.0;  // stretched from L = 2 to 3 along x
  const DenseDerivatives d = evaluateDense(*term, x, EvalOptions{});
  CHECK(d.energy == Approx(0.5 * 5.0 * 1.0 * 1.0));
  // Force on vertex 1 is −k(|d| − L) along +x; vertex 2 is untouched.
  CHECK(d.gradient[3] == Approx(5.0));
  CHECK(d.gradient[0] == Approx(-5.0));
  CHECK(d.gradient.segment<3>(6).norm() == 0.0);
  CHECK(d.gradient[1] == Approx(0.0).margin(1e-15));
  // Along the spring the stiffness is k; across it k(1 − L/|d|) = 5/3.
  CHECK(d.hessian(3, 3) == Approx(5.0));
  CHECK(d.hessian(4, 4) == Approx(5.0 / 3.0));
  CHECK(d.hessian(3, 0) == Approx(-5.0));
}

TEST_CASE("seam spring example: bad pairs are rejected") {
  const TriMesh mesh = makeBendingStencilPatch();
  CHECK_THROWS_AS(makeSeamSpringTerm(mesh, {{0, 6}}, 1.0), InputError);
  CHECK_THROWS_AS(makeSeamSpringTerm(mesh, {{-1, 2}}, 1.0), InputError);
  CHECK_THROWS_WITH(makeSeamSpringTerm(mesh, {{2, 2}}, 1.0), Catch::Contains("(2, 2)"));
}
