#include "tools/checks/check_configurations.h"
#include "core/mesh_generators.h"
#include "core/input_limits.h"
#include "core/topology.h"

#include <catch2/catch.hpp>

#include <limits>
#include <map>
#include <set>

using namespace jetshell;

namespace {

TriMesh twoTriangles() {
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  return m;
}

}  // namespace

TEST_CASE("topology: each bad mesh is rejected with a message naming the problem and the element") {
  SECTION("empty mesh") {
    TriMesh m;
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("no vertices"));
    m.V.resize(3, 3);
    m.V.setZero();
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("no faces"));
  }
  SECTION("out-of-range index") {
    TriMesh m = twoTriangles();
    m.F(1, 2) = 7;
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("face 1") && Catch::Contains("index 7 out of range"));
    m.F(1, 2) = -1;
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("face 1") && Catch::Contains("out of range"));
  }
  SECTION("repeated vertex") {
    TriMesh m = twoTriangles();
    m.F.row(0) << 0, 1, 1;
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("face 0") && Catch::Contains("repeats a vertex"));
  }
  SECTION("NaN coordinate") {
    TriMesh m = twoTriangles();
    m.V(2, 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("vertex 2") && Catch::Contains("non-finite"));
    m.V(2, 1) = std::numeric_limits<double>::infinity();
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("vertex 2"));
  }
  SECTION("degenerate face") {
    TriMesh m = twoTriangles();
    m.V.row(3) << 2, 2, 0;  // collinear with vertices 0 and 2
    CHECK_THROWS_WITH(buildTopology(m), Catch::Contains("face 1") && Catch::Contains("degenerate"));
  }
  SECTION("non-manifold edge") {
    TriMesh m = twoTriangles();
    m.V.conservativeResize(5, 3);
    m.V.row(4) << 0.5, 0.5, 1.0;
    m.F.conservativeResize(3, 3);
    m.F.row(2) << 2, 0, 4;  // a third face on edge (0, 2)
    CHECK_THROWS_WITH(buildTopology(m), "mesh: face 2 (2, 0, 4) uses the non-manifold edge between vertices 0 and 2, "
                                        "also used by face 0 (0, 1, 2) and face 1 (0, 2, 3) (an edge joins at most two "
                                        "faces)");
  }
  SECTION("inconsistent orientation") {
    TriMesh m = twoTriangles();
    m.F.row(1) << 0, 3, 2;
    CHECK_THROWS_WITH(buildTopology(m), "mesh: face 1 (0, 3, 2) is oriented against face 0 (0, 1, 2) (both run from "
                                        "vertex 2 to vertex 0 along their shared edge; neighbours must run it in "
                                        "opposite directions)");
  }
  SECTION("duplicate and reversed-duplicate faces") {
    TriMesh m = twoTriangles();
    m.F.row(1) << 1, 2, 0;
    CHECK_THROWS_WITH(buildTopology(m), "mesh: face 1 (1, 2, 0) duplicates face 0 (0, 1, 2)");
    m.F.row(1) << 2, 1, 0;
    CHECK_THROWS_WITH(buildTopology(m), "mesh: face 1 (2, 1, 0) is face 0 (0, 1, 2) reversed (two faces on the same "
                                        "three vertices)");
  }
  SECTION("a face folded flat onto its neighbour (the rest curvature would be NaN)") {
    TriMesh m = twoTriangles();
    m.V.row(3) << 0.8, 0.2, 0.0;  // across edge (0, 2) but on face 0's side: the faces overlap
    CHECK_THROWS_WITH(buildTopology(m), "mesh: face 1 (0, 2, 3) is folded flat onto face 0 (0, 1, 2) across the edge "
                                        "between vertices 0 and 2 (normals 180.000 degrees apart, at most 179.9: the "
                                        "rest curvature is undefined there)");
    m.V.row(3) << 0.8, 0.2, 0.01;  // lifted: normals about 178 degrees apart, a sharp but valid fold
    CHECK_NOTHROW(buildTopology(m));
  }
  SECTION("more vertices or faces than the limits") {
    const InputLimits saved = inputLimits();
    inputLimits().maxVertices = 3;
    CHECK_THROWS_WITH(buildTopology(twoTriangles()), "mesh: 4 vertices, too many (at most 3)");
    inputLimits() = saved;
    inputLimits().maxFaces = 1;
    CHECK_THROWS_WITH(buildTopology(twoTriangles()), "mesh: 2 faces, too many (at most 1)");
    inputLimits() = saved;
  }
  SECTION("the exceptions are InputError") {
    TriMesh m = twoTriangles();
    m.F(0, 0) = 4;
    CHECK_THROWS_AS(validateMesh(m), InputError);
  }
}

TEST_CASE("topology: edges, adjacency and bending stencils of a small grid") {
  const int nx = 3, ny = 2;
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, nx, ny);
  const Topology t = buildTopology(mesh);
  // Euler: V − E + F = 1 for a disc; boundary edges = 2(nx + ny).
  CHECK(t.numEdges() == mesh.numVertices() + mesh.numFaces() - 1);
  int boundary = 0;
  for (int e = 0; e < t.numEdges(); ++e) boundary += t.isBoundaryEdge(e);
  CHECK(boundary == 2 * (nx + ny));

  std::set<std::pair<int, int>> unique;
  for (int e = 0; e < t.numEdges(); ++e) {
    CHECK(t.edges(e, 0) < t.edges(e, 1));
    CHECK(unique.insert({t.edges(e, 0), t.edges(e, 1)}).second);
  }
  for (int f = 0; f < mesh.numFaces(); ++f) {
    for (int i = 0; i < 3; ++i) {
      INFO("face " << f << " edge " << i);
      const int a = mesh.F(f, (i + 1) % 3), b = mesh.F(f, (i + 2) % 3);
      const int e = t.faceEdges(f, i);
      CHECK(std::min(a, b) == t.edges(e, 0));
      CHECK(std::max(a, b) == t.edges(e, 1));
      const int g = t.faceNeighbors(f, i);
      CHECK(t.bendingStencil(f, i) == mesh.F(f, i));
      if (g < 0) {
        CHECK(t.isBoundaryEdge(e));
        CHECK(t.bendingStencil(f, 3 + i) == -1);
        continue;
      }
      // The neighbour shares the edge and traverses it the other way; the stencil holds its third vertex.
      CHECK((t.edgeFaces(e, 0) == f || t.edgeFaces(e, 1) == f));
      CHECK((t.edgeFaces(e, 0) == g || t.edgeFaces(e, 1) == g));
      const int opposite = t.bendingStencil(f, 3 + i);
      std::set<int> gVerts{mesh.F(g, 0), mesh.F(g, 1), mesh.F(g, 2)};
      CHECK(gVerts == std::set<int>{a, b, opposite});
      bool reversed = false;
      for (int k = 0; k < 3; ++k) reversed |= mesh.F(g, k) == b && mesh.F(g, (k + 1) % 3) == a;
      CHECK(reversed);
    }
  }
  // edgeFaces column 0 traverses the edge from smaller to larger id.
  for (int e = 0; e < t.numEdges(); ++e) {
    const int f = t.edgeFaces(e, 0);
    bool forward = false;
    for (int k = 0; k < 3; ++k) forward |= mesh.F(f, k) == t.edges(e, 0) && mesh.F(f, (k + 1) % 3) == t.edges(e, 1);
    if (!t.isBoundaryEdge(e)) CHECK(forward);
  }
}

TEST_CASE("topology: the bending stencil patch is face 0 with its three neighbours") {
  const TriMesh mesh = makeBendingStencilPatch();
  const Topology t = buildTopology(mesh);
  for (int k = 0; k < 6; ++k) CHECK(t.bendingStencil(0, k) == k);
  for (int f = 1; f < 4; ++f) {
    int absent = 0;
    for (int k = 3; k < 6; ++k) absent += t.bendingStencil(f, k) < 0;
    CHECK(absent == 2);  // each outer face has one interior edge
  }
}
