#include "core/math_constants.h"
#include "core/mesh_generators.h"
#include "energies/end_moment_term.h"
#include "tools/checks/term_check.h"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <vector>

using namespace jetshell;

namespace {

/// The tip edge (x = L) of a makeRectangleGrid strip, in order of increasing y.
std::vector<int> tipChain(int nx, int ny) {
  std::vector<int> chain;
  for (int j = 0; j <= ny; ++j) chain.push_back(j * (nx + 1) + nx);
  return chain;
}

/// Rotates every vertex about the line x = pivotX, z = 0 by angle θ about −y (x towards z: rolling up).
Eigen::VectorXd rolled(const TriMesh& mesh, double theta, double pivotX) {
  Eigen::VectorXd x = flatten(mesh.V);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double dx = mesh.V(v, 0) - pivotX, dz = mesh.V(v, 2);
    x[3 * v] = pivotX + std::cos(theta) * dx - std::sin(theta) * dz;
    x[3 * v + 2] = std::sin(theta) * dx + std::cos(theta) * dz;
  }
  return x;
}

}  // namespace

TEST_CASE("end moment: the energy is -lambda M theta for a rigid rotation of the loaded edge") {
  const TriMesh mesh = makeRectangleGrid(3.0, 1.0, 6, 2);
  auto term = makeEndMomentTerm(mesh, tipChain(6, 2), Eigen::Vector3d(0, -1, 0), 2.5);
  term->setLoadFactor(0.4);
  for (double theta : {0.3, 1.0, 2.5, -0.7}) {
    const Eigen::VectorXd x = rolled(mesh, theta, 1.0);
    CHECK(term->meanRotation(x) == Approx(theta).margin(1e-12));
    CHECK(term->evaluate(x, EvalRequest{}, EvalOptions{}) == Approx(-0.4 * 2.5 * theta).margin(1e-12));
  }
}

TEST_CASE("end moment: advance() unwraps the rotation past pi and 2 pi") {
  const TriMesh mesh = makeRectangleGrid(3.0, 1.0, 3, 1);
  auto term = makeEndMomentTerm(mesh, tipChain(3, 1), Eigen::Vector3d(0, -1, 0), 1.0);
  double theta = 0.0;
  for (int step = 1; step <= 16; ++step) {
    theta = step * (2.5 * kPi / 16);  // steps of < π
    const Eigen::VectorXd x = rolled(mesh, theta, 2.0);
    CHECK(term->meanRotation(x) == Approx(theta).margin(1e-10));
    term->advance(x);
  }
  CHECK(theta > 2.0 * kPi);
  // Without unwrapping the same configuration reads as θ − 2π.
  auto fresh = makeEndMomentTerm(mesh, tipChain(3, 1), Eigen::Vector3d(0, -1, 0), 1.0);
  CHECK(fresh->meanRotation(rolled(mesh, theta, 2.0)) == Approx(theta - 2.0 * kPi).margin(1e-10));
}

TEST_CASE("end moment: Jet gradient, Hessian and load-factor derivatives match finite differences") {
  const TriMesh mesh = makeRectangleGrid(2.0, 1.0, 2, 2);
  auto term = makeEndMomentTerm(mesh, tipChain(2, 2), Eigen::Vector3d(0.1, -1, 0.05), 1.7);
  Eigen::VectorXd x = rolled(mesh, 2.2, 0.5);
  term->advance(x);  // the origin differs from x below, so the atan2 part is exercised away from zero
  srand(11);
  x += 0.2 * Eigen::VectorXd::Random(x.size());
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  term->evaluate(x, EvalRequest{&g, nullptr, -1}, EvalOptions{});
  REQUIRE(g.norm() > 0.1);
  for (const std::string& failure : termCheckFailures(*term, x)) FAIL_CHECK(failure);
}

TEST_CASE("end moment: a segment that is not a boundary edge, or perpendicular to the axis, is rejected") {
  const TriMesh mesh = makeRectangleGrid(2.0, 1.0, 2, 2);
  CHECK_THROWS_AS(makeEndMomentTerm(mesh, {1, 4}, Eigen::Vector3d(0, -1, 0), 1.0), InputError);
  CHECK_THROWS_AS(makeEndMomentTerm(mesh, tipChain(2, 2), Eigen::Vector3d(1, 0, 0), 1.0), InputError);
}

TEST_CASE("end moment: twisting the loaded edge about the strip's axis is not a rotation about the edge") {
  // A fixed moment axis would read this twist as a rotation (and release energy through its pole); the
  // segment's own direction does not.
  const TriMesh mesh = makeRectangleGrid(3.0, 1.0, 6, 2);
  auto term = makeEndMomentTerm(mesh, tipChain(6, 2), Eigen::Vector3d(0, -1, 0), 2.0);
  for (double phi : {0.4, 1.2, 1.6, 3.0}) {
    Eigen::VectorXd x = flatten(mesh.V);
    for (int v = 0; v < mesh.numVertices(); ++v) {
      const double y = mesh.V(v, 1), z = mesh.V(v, 2);
      x[3 * v + 1] = std::cos(phi) * y - std::sin(phi) * z;
      x[3 * v + 2] = std::sin(phi) * y + std::cos(phi) * z;
    }
    CHECK(term->meanRotation(x) == Approx(0.0).margin(1e-12));
  }
}
