#include "tools/bench/wavy_grid.h"

#include "core/math_constants.h"
#include "core/mesh_generators.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

TEST_CASE("bench grid: the waves in z, the shear in x only when asked, y untouched") {
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, 4, 4);
  const Eigen::VectorXd plain = wavyGridPositions(mesh, false), sheared = wavyGridPositions(mesh, true);
  REQUIRE(plain.size() == 3 * mesh.numVertices());
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double x = mesh.V(v, 0), y = mesh.V(v, 1);
    const double z = 0.05 * std::sin(6.0 * kPi * x) * std::cos(4.0 * kPi * y);
    CHECK(plain[3 * v] == x);
    CHECK(plain[3 * v + 1] == y);
    CHECK(plain[3 * v + 2] == Approx(z).margin(1e-15));
    CHECK(sheared[3 * v] == Approx(x + 0.01 * std::sin(2.0 * kPi * y)).margin(1e-15));
    CHECK(sheared[3 * v + 1] == y);
    CHECK(sheared[3 * v + 2] == plain[3 * v + 2]);
  }
}
