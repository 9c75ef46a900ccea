#include "core/math_constants.h"
#include "core/mesh_generators.h"
#include "core/topology.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

namespace {

double totalArea(const TriMesh& m) {
  double a = 0;
  for (int f = 0; f < m.numFaces(); ++f) {
    const Eigen::Vector3d x0 = m.V.row(m.F(f, 0)), x1 = m.V.row(m.F(f, 1)), x2 = m.V.row(m.F(f, 2));
    a += 0.5 * (x1 - x0).cross(x2 - x0).norm();
  }
  return a;
}

/// Smallest dot product of a face normal with the direction `outward(face centroid)`.
template <typename Direction>
double worstAlignment(const TriMesh& m, Direction outward) {
  double worst = 1;
  for (int f = 0; f < m.numFaces(); ++f) {
    const Eigen::Vector3d x0 = m.V.row(m.F(f, 0)), x1 = m.V.row(m.F(f, 1)), x2 = m.V.row(m.F(f, 2));
    const Eigen::Vector3d n = (x1 - x0).cross(x2 - x0).normalized();
    worst = std::min(worst, n.dot(outward((x0 + x1 + x2) / 3.0).normalized()));
  }
  return worst;
}

int boundaryEdges(const Topology& t) {
  int b = 0;
  for (int e = 0; e < t.numEdges(); ++e) b += t.isBoundaryEdge(e);
  return b;
}

}  // namespace

TEST_CASE("generators: the slit annulus is cut along the slit and oriented +z") {
  const int rings = 5, nodes = 65;
  const TriMesh m = makeSlitAnnulus(0.6, 1.0, rings, nodes);
  REQUIRE(m.numVertices() == 325);
  REQUIRE(m.numFaces() == 2 * 4 * 64);
  const Topology t = buildTopology(m);
  // Boundary: inner and outer circles (64 edges each) plus the two slit sides (4 edges each).
  CHECK(boundaryEdges(t) == 2 * 64 + 2 * 4);
  for (int r = 0; r < rings; ++r) {
    CHECK((m.V.row(r * nodes) - m.V.row(r * nodes + nodes - 1)).norm() < 1e-14);
    CHECK(std::abs(m.V.row(r * nodes).norm() - (0.6 + 0.1 * r)) < 1e-14);
  }
  CHECK(worstAlignment(m, [](const Eigen::Vector3d&) { return Eigen::Vector3d(0, 0, 1); }) > 0.999);
  CHECK(totalArea(m) == Approx(kPi * (1.0 - 0.36)).epsilon(0.01));
}

TEST_CASE("generators: cosine ring spacing is fine at both free edges, with the same numbering") {
  const int rings = 5, nodes = 9;
  const TriMesh u = makeSlitAnnulus(6.0, 10.0, rings, nodes);
  const TriMesh c = makeSlitAnnulus(6.0, 10.0, rings, nodes, QuadDiagonals::Uniform, RingSpacing::Cosine);
  REQUIRE(c.numVertices() == u.numVertices());
  CHECK(c.F == u.F);
  for (int r = 0; r < rings; ++r) {
    const double expected = 6.0 + 4.0 * 0.5 * (1.0 - std::cos(kPi * r / (rings - 1)));
    for (int j = 0; j < nodes; ++j) CHECK(c.V.row(r * nodes + j).norm() == Approx(expected).epsilon(1e-14));
  }
  // The first ring spacing is 4 · ½(1 − cos(π/4)) = 0.586 against the uniform 1; the middle one is wider.
  CHECK(c.V.row(nodes).norm() - 6.0 == Approx(0.5857864376).epsilon(1e-9));
  CHECK(ringSpacingFromString("cosine") == RingSpacing::Cosine);
  CHECK(std::string(toString(RingSpacing::Uniform)) == "uniform");
  CHECK_THROWS_WITH(ringSpacingFromString("log"), "ringSpacing = \"log\": must be \"uniform\" or \"cosine\"");
}

TEST_CASE("generators: a closed cylinder has no seam, a panel has one, both face outward") {
  const TriMesh tube = makeCylinder(2.0, 3.0, 2 * kPi, 12, 4);
  CHECK(tube.numVertices() == 12 * 5);
  CHECK(boundaryEdges(buildTopology(tube)) == 2 * 12);
  auto radial = [](const Eigen::Vector3d& c) { return Eigen::Vector3d(c.x(), 0, c.z()); };
  CHECK(worstAlignment(tube, radial) > 0.95);
  const TriMesh panel = makeCylinder(2.0, 3.0, 0.2 * kPi, 6, 4);
  CHECK(panel.numVertices() == 7 * 5);
  CHECK(boundaryEdges(buildTopology(panel)) == 2 * 6 + 2 * 4);
  CHECK(worstAlignment(panel, radial) > 0.99);
  CHECK(panel.V.col(2).maxCoeff() == Approx(2.0));
}

TEST_CASE("generators: hemispheres, closed or with a hole, face outward and end at the equator") {
  auto radial = [](const Eigen::Vector3d& c) { return c; };
  const TriMesh closed = makeHemisphere(1.0, 8, 16);
  CHECK(closed.numVertices() == 1 + 8 * 16);
  CHECK(boundaryEdges(buildTopology(closed)) == 16);
  CHECK(worstAlignment(closed, radial) > 0.95);
  CHECK(totalArea(closed) == Approx(2 * kPi).epsilon(0.03));
  const TriMesh open = makeHemisphere(10.0, 8, 16, 18.0 * kPi / 180.0, 0.5 * kPi);
  CHECK(open.numVertices() == 9 * 17);
  buildTopology(open);
  CHECK(worstAlignment(open, radial) > 0.95);
  CHECK(open.V.col(2).minCoeff() == 0.0);
  CHECK(open.V.col(2).maxCoeff() == Approx(10.0 * std::cos(18.0 * kPi / 180.0)));
}

TEST_CASE("generators: invalid parameters name the parameter") {
  CHECK_THROWS_WITH(makeSlitAnnulus(1.0, 0.6, 5, 65), "slit annulus: outerRadius must be > innerRadius");
  CHECK_THROWS_WITH(makeSlitAnnulus(0.6, 1.0, 1, 65), "slit annulus: rings = 1: must be >= 2");
  CHECK_THROWS_WITH(makeCylinder(-1.0, 1.0, kPi, 4, 4), "cylinder: radius = -1: must be finite and > 0");
  CHECK_THROWS_WITH(makeHemisphere(1.0, 4, 8, 0.0, kPi),
                    "hemisphere: a partial azimuth needs a hole angle > 0 (the pole would be degenerate)");
}

TEST_CASE("generators: uniform diagonals (the default) split every quad along (i, j)–(i+1, j+1)") {
  const TriMesh alternating = makeRectangleGrid(2.0, 1.0, 4, 2, QuadDiagonals::Alternating);
  const TriMesh uniform = makeRectangleGrid(2.0, 1.0, 4, 2, QuadDiagonals::Uniform);
  CHECK(makeRectangleGrid(2.0, 1.0, 4, 2).F == uniform.F);
  CHECK(uniform.V == alternating.V);
  CHECK(uniform.F != alternating.F);
  for (int f = 0; f < uniform.numFaces(); f += 2) {
    const int j = f / 2 / 4, i = f / 2 % 4, v00 = j * 5 + i, v11 = v00 + 6;
    CHECK(uniform.F.row(f) == Eigen::RowVector3i(v00, v00 + 1, v11));
    CHECK(uniform.F.row(f + 1) == Eigen::RowVector3i(v00, v11, v00 + 5));
  }
  CHECK(makeRectangleGrid(2.0, 1.0, 4, 2, QuadDiagonals::Alternating).F == alternating.F);
  for (const TriMesh& m : {makeSlitAnnulus(0.6, 1.0, 3, 9, QuadDiagonals::Uniform),
                           makeCylinder(1.0, 2.0, 2 * kPi, 6, 3, QuadDiagonals::Uniform),
                           makeHemisphere(1.0, 4, 8, 0.0, 2 * kPi, QuadDiagonals::Uniform)}) {
    buildTopology(m);  // valid and consistently oriented
  }
  CHECK(quadDiagonalsFromString("uniform") == QuadDiagonals::Uniform);
  CHECK_THROWS_WITH(quadDiagonalsFromString("random"), "diagonals = \"random\": must be \"alternating\" or \"uniform\"");
}
