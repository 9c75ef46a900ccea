#include "core/mesh_generators.h"
#include "solvers/vertex_bisection.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

using namespace jetshell;

namespace {

/// Edges of the triangles whose ends lie in different parts.
int cutEdges(const Eigen::MatrixXi& F, const std::vector<std::int8_t>& part) {
  std::set<std::pair<int, int>> cut;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (part[static_cast<std::size_t>(a)] != part[static_cast<std::size_t>(b)]) cut.insert(std::minmax(a, b));
    }
  return static_cast<int>(cut.size());
}

}  // namespace

TEST_CASE("vertex bisection: a grid splits into two halves of about equal size along a short cut", "[solvers]") {
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, 40, 40);  // 41 × 41 vertices
  const int n = mesh.numVertices();
  const std::vector<std::int8_t> part = bisectVertices(vertexNeighbours(mesh.F, n));
  REQUIRE(static_cast<int>(part.size()) == n);
  const auto ones = static_cast<int>(std::count(part.begin(), part.end(), std::int8_t{1}));
  CHECK(std::count(part.begin(), part.end(), std::int8_t{0}) + ones == n);  // every vertex in part 0 or 1
  CHECK(ones >= 0.45 * n);
  CHECK(ones <= 0.55 * n);
  // A straight cut crosses about 3 edges per grid row; a poor split (by index, at random) cuts hundreds more.
  CHECK(cutEdges(mesh.F, part) <= 4 * 41);
  CHECK(cutEdges(mesh.F, part) > 0);
  // The same mesh gives the same parts (the preconditioner, and so a run, must not depend on chance).
  CHECK(bisectVertices(vertexNeighbours(mesh.F, n)) == part);
}

TEST_CASE("vertex bisection: a small mesh stays whole, and bad triangles are refused", "[solvers]") {
  const TriMesh small = makeRectangleGrid(1.0, 1.0, 10, 10);
  REQUIRE(small.numVertices() < kMinBisectedVertices);
  const std::vector<std::int8_t> part = bisectVertices(vertexNeighbours(small.F, small.numVertices()));
  CHECK(part.size() == static_cast<std::size_t>(small.numVertices()));
  CHECK(std::all_of(part.begin(), part.end(), [](std::int8_t p) { return p == 0; }));

  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, 40, 40);
  Eigen::MatrixXi F = mesh.F;
  F(3, 1) = mesh.numVertices();
  CHECK_THROWS_WITH(vertexNeighbours(F, mesh.numVertices()), Catch::Contains("out of range"));
}
