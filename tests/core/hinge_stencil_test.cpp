#include "core/hinge_stencil.h"
#include "core/mesh_generators.h"
#include "core/topology.h"

#include <catch2/catch.hpp>

using namespace jetshell;

TEST_CASE("hinge stencils: one per interior edge, (a, b) in face A's order, corners in each face's order") {
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  const Topology topo = buildTopology(m);
  const HingeStencils h = hingeStencils(m, topo);
  REQUIRE(h.size() == 1);
  const int* ids = h.table.element(0);
  const int fa = h.faces[0][0], fb = h.faces[0][1];
  CHECK(topo.edgeFaces(h.edge[0], 0) == fa);
  CHECK(topo.edgeFaces(h.edge[0], 1) == fb);
  // The edge (0, 2), in face A's cyclic order, then A's third vertex and B's.
  const int third[2] = {fa == 0 ? 1 : 3, fa == 0 ? 3 : 1};
  CHECK(((ids[0] == 0 && ids[1] == 2) || (ids[0] == 2 && ids[1] == 0)));
  CHECK(ids[2] == third[0]);
  CHECK(ids[3] == third[1]);
  bool cyclic = false;
  for (int k = 0; k < 3; ++k) cyclic = cyclic || (m.F(fa, k) == ids[0] && m.F(fa, (k + 1) % 3) == ids[1]);
  CHECK(cyclic);
  for (int s = 0; s < 2; ++s)
    for (int k = 0; k < 3; ++k) CHECK(ids[h.corners[0][s][k]] == m.F(h.faces[0][s], k));

  // A grid: every interior edge once, no boundary edge.
  const TriMesh grid = makeRectangleGrid(1.0, 1.0, 4, 3);
  const Topology gt = buildTopology(grid);
  const HingeStencils gh = hingeStencils(grid, gt);
  int interior = 0;
  for (int e = 0; e < gt.numEdges(); ++e) interior += gt.isBoundaryEdge(e) ? 0 : 1;
  CHECK(gh.size() == interior);
  for (int i = 0; i < gh.size(); ++i) CHECK_FALSE(gt.isBoundaryEdge(gh.edge[static_cast<std::size_t>(i)]));
}
