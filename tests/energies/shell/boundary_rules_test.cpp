#include "energies/shell/boundary_rules.h"

#include "core/mesh_generators.h"
#include "energies/shell/shell_terms.h"

#include <catch2/catch.hpp>

using namespace jetshell;

namespace {

/// The rule of the boundary edge between vertices a and b.
EdgeRule ruleOf(const BendingTerm& t, const Topology& topo, int a, int b) {
  for (int e = 0; e < topo.numEdges(); ++e)
    if ((topo.edges(e, 0) == a && topo.edges(e, 1) == b) || (topo.edges(e, 0) == b && topo.edges(e, 1) == a))
      return t.edgeRule(e);
  FAIL("no edge " << a << "-" << b);
  return EdgeRule::Count;
}

}  // namespace

TEST_CASE("boundary rules: clamp over symmetry plane over moment-loaded over free, each on its own edges") {
  // 3 × 2 quads on [0, 3] × [0, 2]: vertex (i, j) is j * 4 + i. Clamped x = 0, plane y = 0, moment on x = 3.
  const TriMesh mesh = makeRectangleGrid(3.0, 2.0, 3, 2);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  BendingTerm t(mesh, topo, ref, 0.3, 0.7);
  std::vector<char> clamped(12, 0), loaded(12, 0);
  for (int j = 0; j <= 2; ++j) {
    clamped[j * 4] = 1;
    loaded[j * 4 + 3] = 1;
  }
  BoundaryRuleChoice choice;
  choice.symmetryPlanes.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, -3.0, 0.0)});
  const BoundaryRuleCounts c = applyBoundaryRules(t, mesh, clamped, loaded, choice);
  CHECK(c.free == 10);
  CHECK(c.momentLoaded == 2);
  CHECK(c.symmetry == 3);
  CHECK(c.clamped == 2);
  CHECK(ruleOf(t, topo, 0, 4) == EdgeRule::MirroredClamp);
  CHECK(ruleOf(t, topo, 0, 1) == EdgeRule::SymmetryPlane);  // on the plane, one end clamped: the plane's
  CHECK(ruleOf(t, topo, 2, 3) == EdgeRule::SymmetryPlane);  // on the plane and moment-loaded: the plane's
  CHECK(ruleOf(t, topo, 3, 7) == EdgeRule::PageFree);       // moment-loaded
  CHECK(ruleOf(t, topo, 9, 10) == EdgeRule::SecondOrderFree);
  CHECK_FALSE(t.rigidInvariant());

  choice.free = EdgeRule::MirroredClamp;
  CHECK_THROWS_WITH(applyBoundaryRules(t, mesh, clamped, loaded, choice), Catch::Contains("free edge rule"));
  choice.free = EdgeRule::PageFree;
  choice.clamp = EdgeRule::SymmetryPlane;
  CHECK_THROWS_WITH(applyBoundaryRules(t, mesh, clamped, loaded, choice), Catch::Contains("clamp edge rule"));
  choice.clamp = EdgeRule::ReferenceClamp;
  choice.symmetryPlanes[0].normal.setZero();
  CHECK_THROWS_WITH(applyBoundaryRules(t, mesh, clamped, loaded, choice), Catch::Contains("symmetry plane"));
}
