#include "core/mesh_generators.h"
#include "core/stage_window_plan.h"
#include "core/topology.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>
#include <vector>

using namespace jetshell;

namespace {

// The reading tables of a bending-like graph on a grid, built as StageGraph::finalize() builds them: elements
// are faces (their 6-vertex bending stencils) in the order given, layer 0 one node per face, layer 1 one node
// per edge reading its two faces; each element reads its face's three edges (layer 1) and, through them, their
// faces (layer 0); a node's owner is its first reading element.
struct Tables {
  TriMesh mesh = makeRectangleGrid(1.0, 1.0, 30, 30);
  Topology topo = buildTopology(mesh);
  StencilTable elements{6, {}};
  std::vector<int> start[2], node[2], ownedStart[2], ownedIndex[2];

  explicit Tables(bool shuffled = false, bool halves = false) {
    const int nf = mesh.numFaces();
    std::vector<int> order(static_cast<std::size_t>(nf));
    std::iota(order.begin(), order.end(), 0);
    if (shuffled) std::shuffle(order.begin(), order.end(), std::mt19937(5));
    if (halves) {
      // The faces left of the grid's middle column first (row by row), then the others.
      const auto left = [&](int f) {
        const double cx = (mesh.V(mesh.F(f, 0), 0) + mesh.V(mesh.F(f, 1), 0) + mesh.V(mesh.F(f, 2), 0)) / 3.0;
        return cx < 0.5 * (mesh.V.col(0).minCoeff() + mesh.V.col(0).maxCoeff());
      };
      std::stable_partition(order.begin(), order.end(), left);
    }
    const int counts[2] = {nf, topo.numEdges()};
    std::vector<char> owned[2];
    for (int l = 0; l < 2; ++l) {
      start[l] = {0};
      ownedStart[l] = {0};
      owned[l].assign(static_cast<std::size_t>(counts[l]), 0);
    }
    for (int f : order) {
      for (int k = 0; k < 6; ++k) elements.ids.push_back(topo.bendingStencil(f, k));
      std::set<int> reads[2];
      for (int i = 0; i < 3; ++i) {
        const int e = topo.faceEdges(f, i);
        reads[1].insert(e);
        for (int s = 0; s < 2; ++s)
          if (topo.edgeFaces(e, s) >= 0) reads[0].insert(topo.edgeFaces(e, s));
      }
      for (int l = 0; l < 2; ++l) {
        int index = 0;
        for (int n : reads[l]) {
          node[l].push_back(n);
          if (!owned[l][static_cast<std::size_t>(n)]) {
            owned[l][static_cast<std::size_t>(n)] = 1;
            ownedIndex[l].push_back(index);
          }
          ++index;
        }
        start[l].push_back(static_cast<int>(node[l].size()));
        ownedStart[l].push_back(static_cast<int>(ownedIndex[l].size()));
      }
    }
  }
  int count(int l) const { return l == 0 ? mesh.numFaces() : topo.numEdges(); }
  std::vector<StageWindowPlan::SharedReads> reads() const {
    return {{0, count(0), &start[0], &node[0], &ownedStart[0], &ownedIndex[0]},
            {1, count(1), &start[1], &node[1], &ownedStart[1], &ownedIndex[1]}};
  }
};

/// Where something happens: phase (0: before the lanes, 1: the lanes' first phase, 2: their second, 3: after
/// them), lane, window.
struct When {
  int phase = -1, lane = -1, window = 0;
};
/// a no later than b, and never at the same time in two lanes.
bool notAfter(const When& a, const When& b) {
  if (a.phase != b.phase) return a.phase < b.phase;
  return a.phase == 0 || a.phase == 3 || (a.lane == b.lane && a.window <= b.window);
}

/// Checks the plan's promises against the tables, and returns the number of deferred elements.
int checkPlan(const Tables& t, const StageWindowPlan& plan, int window) {
  const int ne = t.elements.size(), nv = t.mesh.numVertices();
  // The lanes cover the order's positions once, in turn; the order holds every element once, ascending in a lane.
  REQUIRE(plan.order.size() == static_cast<std::size_t>(ne));
  std::vector<int> laneOf(static_cast<std::size_t>(ne), -1), position(static_cast<std::size_t>(ne), -1);
  int next = 0;
  for (std::size_t k = 0; k < plan.lanes.size(); ++k) {
    CHECK(plan.lanes[k].begin == next);
    next = plan.lanes[k].end;
    for (int p = plan.lanes[k].begin; p < plan.lanes[k].end; ++p) {
      const auto e = static_cast<std::size_t>(plan.order[static_cast<std::size_t>(p)]);
      CHECK(laneOf[e] == -1);
      laneOf[e] = static_cast<int>(k);
      position[e] = p;
      if (p > plan.lanes[k].begin) CHECK(plan.order[static_cast<std::size_t>(p) - 1] < plan.order[static_cast<std::size_t>(p)]);
    }
  }
  CHECK(next == ne);
  // Each lane runs in one phase; half of the lanes in each.
  std::vector<int> lanePhase(plan.lanes.size(), -1);
  for (int phase = 0; phase < 2; ++phase) {
    CHECK(2 * plan.phaseLanes[static_cast<std::size_t>(phase)].size() == plan.lanes.size());
    for (int k : plan.phaseLanes[static_cast<std::size_t>(phase)]) {
      REQUIRE(k >= 0);
      REQUIRE(static_cast<std::size_t>(k) < plan.lanes.size());
      CHECK(lanePhase[static_cast<std::size_t>(k)] == -1);
      lanePhase[static_cast<std::size_t>(k)] = phase;
    }
  }
  for (int p : lanePhase) REQUIRE(p >= 0);
  const auto phaseOf = [&](int lane) { return 1 + lanePhase[static_cast<std::size_t>(lane)]; };
  // Each element's adjoint sweep: its lane, its window there.
  std::vector<When> adjoint(static_cast<std::size_t>(ne));
  for (int e = 0; e < ne; ++e) {
    const int k = laneOf[static_cast<std::size_t>(e)];
    REQUIRE(k >= 0);
    adjoint[static_cast<std::size_t>(e)] = {phaseOf(k), k,
                                            (position[static_cast<std::size_t>(e)] - plan.lanes[static_cast<std::size_t>(k)].begin) / window};
  }
  // Each element's assembly: once, in a lane's window or after the lanes.
  std::vector<When> assembled(static_cast<std::size_t>(ne));
  for (std::size_t k = 0; k < plan.lanes.size(); ++k) {
    const StageWindowPlan::Lane& lane = plan.lanes[k];
    for (std::size_t w = 0; w + 1 < lane.readyStart.size(); ++w)
      for (int i = lane.readyStart[w]; i < lane.readyStart[w + 1]; ++i) {
        When& a = assembled[static_cast<std::size_t>(lane.ready[static_cast<std::size_t>(i)])];
        CHECK(a.phase == -1);
        a = {phaseOf(static_cast<int>(k)), static_cast<int>(k), static_cast<int>(w)};
      }
  }
  for (int e : plan.deferred) {
    CHECK(assembled[static_cast<std::size_t>(e)].phase == -1);
    assembled[static_cast<std::size_t>(e)] = {3, -1, 0};
  }
  for (int e = 0; e < ne; ++e) {
    CHECK(assembled[static_cast<std::size_t>(e)].phase != -1);
    CHECK(notAfter(adjoint[static_cast<std::size_t>(e)], assembled[static_cast<std::size_t>(e)]));
  }
  // Two lanes of one phase never assemble elements on a common vertex.
  std::vector<std::set<int>> writers[2] = {std::vector<std::set<int>>(static_cast<std::size_t>(nv)),
                                           std::vector<std::set<int>>(static_cast<std::size_t>(nv))};
  for (int e = 0; e < ne; ++e) {
    const When& a = assembled[static_cast<std::size_t>(e)];
    if (a.phase == 3) continue;
    for (int k = 0; k < 6; ++k)
      if (t.elements.element(e)[k] >= 0) writers[a.phase - 1][static_cast<std::size_t>(t.elements.element(e)[k])].insert(a.lane);
  }
  for (const auto& w : writers)
    for (const auto& lanes : w) CHECK(lanes.size() <= 1);

  std::vector<When> forwardedIn[2], gatheredIn[2];
  for (int l = 0; l < 2; ++l) {
    const auto L = static_cast<std::size_t>(l);
    std::vector<When>& forwarded = forwardedIn[l];
    std::vector<When>& gathered = gatheredIn[l];
    forwarded.resize(static_cast<std::size_t>(t.count(l)));
    gathered = forwarded;
    for (std::size_t k = 0; k < plan.lanes.size(); ++k) {
      const StageWindowPlan::Lane& lane = plan.lanes[k];
      for (std::size_t w = 0; w + 1 < lane.forwardStart[L].size(); ++w) {
        const When at{phaseOf(static_cast<int>(k)), static_cast<int>(k), static_cast<int>(w)};
        for (int i = lane.forwardStart[L][w]; i < lane.forwardStart[L][w + 1]; ++i) {
          When& f = forwarded[static_cast<std::size_t>(lane.forward[L][static_cast<std::size_t>(i)])];
          CHECK(f.phase == -1);
          f = at;
        }
        for (int i = lane.gatherStart[L][w]; i < lane.gatherStart[L][w + 1]; ++i) {
          When& g = gathered[static_cast<std::size_t>(lane.gather[L][static_cast<std::size_t>(i)])];
          CHECK(g.phase == -1);
          g = at;
        }
      }
    }
    for (int n : plan.cross[L]) {
      CHECK(forwarded[static_cast<std::size_t>(n)].phase == -1);
      CHECK(gathered[static_cast<std::size_t>(n)].phase == -1);
      forwarded[static_cast<std::size_t>(n)] = {0, -1, 0};
      gathered[static_cast<std::size_t>(n)] = {3, -1, 0};
    }
    CHECK(plan.unread[L].empty());  // every face and edge is read
    for (int n = 0; n < t.count(l); ++n) {
      CHECK(forwarded[static_cast<std::size_t>(n)].phase != -1);
      CHECK(gathered[static_cast<std::size_t>(n)].phase != -1);
    }
    for (int e = 0; e < ne; ++e) {
      // A node is forwarded before its readers' adjoint sweeps, and gathered after them; an owned node is
      // gathered before its owner is assembled (a cross node's owner is deferred).
      for (int i = t.start[l][static_cast<std::size_t>(e)]; i < t.start[l][static_cast<std::size_t>(e) + 1]; ++i) {
        const auto n = static_cast<std::size_t>(t.node[l][static_cast<std::size_t>(i)]);
        CHECK(notAfter(forwarded[n], adjoint[static_cast<std::size_t>(e)]));
        CHECK(notAfter(adjoint[static_cast<std::size_t>(e)], gathered[n]));
      }
      for (int o = t.ownedStart[l][static_cast<std::size_t>(e)]; o < t.ownedStart[l][static_cast<std::size_t>(e) + 1]; ++o) {
        const auto n = static_cast<std::size_t>(
            t.node[l][static_cast<std::size_t>(t.start[l][static_cast<std::size_t>(e)] + t.ownedIndex[l][static_cast<std::size_t>(o)])]);
        CHECK(notAfter(gathered[n], assembled[static_cast<std::size_t>(e)]));
      }
    }
  }
  // An edge node reads its faces' nodes: they are forwarded no later than it, and gathered no earlier (a face's
  // adjoint sums its edges'; in one window the layers go forward in order, backward last first).
  for (int edge = 0; edge < t.topo.numEdges(); ++edge)
    for (int s = 0; s < 2; ++s) {
      const int f = t.topo.edgeFaces(edge, s);
      if (f < 0) continue;
      CHECK(notAfter(forwardedIn[0][static_cast<std::size_t>(f)], forwardedIn[1][static_cast<std::size_t>(edge)]));
      CHECK(notAfter(gatheredIn[1][static_cast<std::size_t>(edge)], gatheredIn[0][static_cast<std::size_t>(f)]));
    }

  // The deferred elements' schedule covers them once; blocks of one colour share no vertex.
  std::vector<int> seen(plan.deferred.size(), 0);
  for (const auto& color : plan.deferredSchedule.colors) {
    std::set<int> used;
    for (const ElementRange& r : color) {
      std::set<int> block;
      for (int p = r.begin; p < r.end; ++p) {
        ++seen[static_cast<std::size_t>(p)];
        for (int k = 0; k < 6; ++k) {
          const int v = t.elements.element(plan.deferred[static_cast<std::size_t>(p)])[k];
          if (v >= 0) block.insert(v);
        }
      }
      for (int v : block) CHECK(used.insert(v).second);
    }
  }
  for (int s : seen) CHECK(s == 1);
  return static_cast<int>(plan.deferred.size());
}

}  // namespace

TEST_CASE("stage window plan: every node forwarded and gathered once, every element assembled once, in order",
          "[stages]") {
  SECTION("elements in row order: lanes of 7.5 rows, nothing deferred") {
    const Tables t;
    const StageWindowPlan plan = planWindows(t.elements, t.mesh.numVertices(), 3, t.reads(), 450, 64);
    REQUIRE(plan.lanes.size() == 4);
    CHECK(checkPlan(t, plan, 64) == 0);
    CHECK(plan.cross[0].empty());
    CHECK(plan.cross[1].empty());
  }
  SECTION("elements in row order: lanes of about one row, nodes read from three lanes") {
    const Tables t;
    const StageWindowPlan plan = planWindows(t.elements, t.mesh.numVertices(), 3, t.reads(), 50, 7);
    REQUIRE(plan.lanes.size() == 36);
    CHECK_FALSE(plan.cross[0].empty());
    const int deferred = checkPlan(t, plan, 7);
    CHECK(deferred > 0);
    CHECK(deferred < t.elements.size());
  }
  SECTION("elements shuffled: the lanes follow the mesh's connectivity, not the numbering") {
    const Tables t(true);
    const StageWindowPlan plan = planWindows(t.elements, t.mesh.numVertices(), 3, t.reads(), 450, 64);
    REQUIRE(plan.lanes.size() == 4);
    // Cut in the numbering, most elements would be deferred (every lane touches every other); in breadth-first
    // bands of 450 faces (7.5 rows' worth) none are, and no node is read from three lanes.
    CHECK(checkPlan(t, plan, 64) == 0);
    CHECK(plan.cross[0].empty());
    CHECK(plan.cross[1].empty());
    std::vector<int> sorted = plan.order;
    std::sort(sorted.begin(), sorted.end());
    CHECK(sorted != plan.order);
  }
  SECTION("two parts numbered one after the other, joined along a seam (a garment's panels): the numbering kept, "
          "the lanes that meet across the seam in different phases") {
    // The left half's faces row by row, then the right half's: lanes 0 and 1 are the left half's lower and upper
    // rows, 2 and 3 the right half's. Alternating phases would put 0 and 2, which meet along the lower half of
    // the middle column, in one phase, and defer the elements there; the phases pair 0 with 3 and 1 with 2, which
    // meet only around the middle point, so the few elements deferred are there.
    const Tables t(false, true);
    const StageWindowPlan plan = planWindows(t.elements, t.mesh.numVertices(), 3, t.reads(), 450, 64);
    REQUIRE(plan.lanes.size() == 4);
    const int deferred = checkPlan(t, plan, 64);
    CHECK(deferred > 0);
    CHECK(deferred < 60);  // fewer than the faces of one column of squares along the seam
    for (int e = 0; e < t.elements.size(); ++e) CHECK(plan.order[static_cast<std::size_t>(e)] == e);
    const auto together = [&](int a, int b) {
      for (const std::vector<int>& lanes : plan.phaseLanes)
        if (std::count(lanes.begin(), lanes.end(), a) + std::count(lanes.begin(), lanes.end(), b) == 2) return true;
      return false;
    };
    CHECK(together(0, 3));
    CHECK(together(1, 2));
  }
  SECTION("elements in row order: the lanes alternate between the phases") {
    const Tables t;
    const StageWindowPlan plan = planWindows(t.elements, t.mesh.numVertices(), 3, t.reads(), 450, 64);
    CHECK(plan.phaseLanes[0] == std::vector<int>{0, 2});
    CHECK(plan.phaseLanes[1] == std::vector<int>{1, 3});
  }
}

TEST_CASE("stage window plan: none on a mesh smaller than four lanes, or when switched off", "[stages]") {
  const Tables t;
  const int ne = t.elements.size(), nv = t.mesh.numVertices();
  CHECK(planWindows(t.elements, nv, 3, t.reads(), ne / 4 + 1, 64).empty());
  CHECK(planWindows(t.elements, nv, 3, t.reads(), 0, 64).empty());
  CHECK(planWindows(t.elements, nv, 3, t.reads(), ne / 4, 64).lanes.size() == 4);
  CHECK(planWindows(t.elements, nv, 3, t.reads(), ne / 9, 64).lanes.size() == 8);  // a multiple of four
  CHECK_THROWS_WITH(planWindows(t.elements, nv, 3, t.reads(), ne / 4, 0), Catch::Contains("window"));
}

TEST_CASE("stage window plan: the default lane size plans four lanes on a small mesh and none on a tiny one",
          "[stages]") {
  CHECK(windowPlanLaneElements(4 * kWindowPlanMinLaneElements - 1) == 0);
  CHECK(windowPlanLaneElements(4 * kWindowPlanMinLaneElements) == kWindowPlanMinLaneElements);
  CHECK(windowPlanLaneElements(11008) == 2752);  // the T-shirt's 11,008 faces: four lanes
  CHECK(windowPlanLaneElements(4 * kWindowPlanLaneElements - 1) == kWindowPlanLaneElements - 1);
  CHECK(windowPlanLaneElements(4 * kWindowPlanLaneElements) == kWindowPlanLaneElements);
  CHECK(windowPlanLaneElements(80000) == kWindowPlanLaneElements);  // 16 lanes, as before
  const Tables t;
  const int ne = t.elements.size();
  REQUIRE(ne >= 4 * kWindowPlanMinLaneElements);
  CHECK(planWindows(t.elements, t.mesh.numVertices(), 3, t.reads(), windowPlanLaneElements(ne)).lanes.size() == 4);
}
