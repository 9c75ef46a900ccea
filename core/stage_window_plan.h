// The order in which the contracted exact Hessian of a stage graph (core/stage_graph_evaluator.h), and a gradient
// alone, visit its Shared nodes and its elements, so that what one sweep writes is still in cache when the next
// reads it. (A gradient alone: in step 4 an element adds the leaf adjoints its step 2 kept, no curvature.)
//
// Without a plan the contracted Hessian runs four sweeps, each over the whole mesh: the Shared nodes forward,
// the elements' adjoints, the Shared nodes' adjoints, the elements' curvature and assembly. Past a few thousand
// elements the Shared buffers the first sweep writes have left the cache when the last one reads them. With a
// plan the elements are cut into lanes (contiguous ranges of the lanes' order, below; their number depends on
// the mesh alone, never on the thread count) and each lane into windows. The lanes run in two phases, the first
// phase's lanes in parallel, then the second's (phases below); a lane runs its windows in order, and in each window:
//   1. forwards the nodes it forwards whose first reader there is in the window (layers in order);
//   2. runs the adjoint sweep of its elements in the window;
//   3. gathers the adjoints of the nodes it gathers whose last reader there is in the window (last layer first);
//   4. assembles the elements whose owned nodes are now complete (their curvature and blocks).
// A node read from one lane is that lane's. A node read from two lanes of different phases is forwarded by the
// first phase's lane and gathered by the second phase's (when the first lane's readers are done), which also
// assembles its owner. A node read from two lanes of one phase, or from more lanes (a cross node), is forwarded
// before the phases and gathered after them; a node no element reads contributes nothing, and only its adjoint
// and Jacobian are set (to zero). An element that owns a cross node, or whose vertex another lane of its phase
// also writes, is deferred to after the phases and runs in a coloured schedule of its own. Each gradient and
// matrix entry thus receives its terms in an order fixed by the mesh: the same bits for every thread count. The
// plan is topology only; the graph builds it in finalize() (core/stage_graph.h).
//
// The lanes' order. Lanes are cut in the elements' numbering, which suits a mesh numbered row by row: a window's
// elements and nodes are then contiguous in memory. A mesh numbered without regard to its connectivity (faces
// shuffled, or many parts one after another) has lanes that touch every other lane, and most of its elements
// deferred; past a quarter of them deferred the plan cuts the lanes in bands of the connectivity instead
// (elements by breadth-first level over shared vertices, from an element at an end of a longest path; within a
// lane by number) when that defers fewer. Measured on the staged bending Hessian (BENCHMARKS.md, Elements,
// "Session 97"): a grid with shuffled faces (84% deferred) runs 1.9-2.2x faster on the bands, one numbered in 32
// blocks in random order (45%) 1.1-1.3x; the T-shirt (front panel then back) and a grid in 8 blocks run as fast
// or faster on the numbering, whose windows read memory in long runs.
//
// The phases. Lanes alternate between the phases, which suits lanes that meet only the next and the previous
// one. Where that defers elements, the lanes' graph (lanes joined when their elements share a vertex) is
// two-coloured if it can be with half of the lanes in each phase, and the colouring is kept when it defers fewer:
// a garment numbered panel by panel has its front's lanes meet the back's across the seams, and alternating lanes
// put a front lane and the back lane it meets in one phase: the T-shirt's 11,008 elements have 1,375 deferred with
// alternating lanes and 44 with the phases chosen (the same mesh at twice the resolution, eight lanes: 2,719 and
// 87; BENCHMARKS.md, Elements, "Session 98").
#pragma once

#include "core/assembly.h"
#include "core/stencil.h"

#include <array>
#include <vector>

namespace jetshell {

/// Elements per lane on a large mesh, at least: the lanes are a multiple of four (an even number per phase).
inline constexpr int kWindowPlanLaneElements = 4096;
/// Elements per lane, at least, on a mesh too small for four lanes of kWindowPlanLaneElements: such a mesh gets
/// four lanes, and one of fewer than four lanes of this many elements gets no plan (its elements run through the
/// ordinary coloured loop). The whole-mesh sweeps cost the staged bending Hessian 1.2–1.5× the windowed ones on
/// 1,800 to 11,000 faces at two threads, where it is not in cache and four passes each wait on a parallel
/// region's slowest thread (BENCHMARKS.md, Elements, "Session 96").
inline constexpr int kWindowPlanMinLaneElements = 256;
/// Elements per window: the Shared data of a window and its neighbours stay within a core's cache.
inline constexpr int kWindowPlanWindow = 1024;

/// The lane size a graph of `elements` elements is planned with (StageGraph::finalize): kWindowPlanLaneElements,
/// or on a smaller mesh a quarter of it (four lanes), or 0 (no plan) below four lanes of
/// kWindowPlanMinLaneElements.
inline int windowPlanLaneElements(int elements) {
  if (elements >= 4 * kWindowPlanLaneElements) return kWindowPlanLaneElements;
  if (elements >= 4 * kWindowPlanMinLaneElements) return elements / 4;
  return 0;
}

struct StageWindowPlan {
  /// What the plan reads of one Shared layer (StageGraph::LayerTables): its node count, per element the nodes
  /// it reads (CSR, every layer the element reads, directly or not) and the ones it owns.
  struct SharedReads {
    int layer = 0, count = 0;
    const std::vector<int>* elementStart = nullptr;
    const std::vector<int>* elementNode = nullptr;
    const std::vector<int>* ownedStart = nullptr;
    const std::vector<int>* ownedIndex = nullptr;
  };
  /// One lane: its elements order[begin, end), and per window (CSR over the lane's windows) what it does. The
  /// per-layer vectors are indexed by layer (empty for Local layers).
  struct Lane {
    int begin = 0, end = 0;
    std::vector<std::vector<int>> forwardStart, forward;  // nodes forwarded in the window
    std::vector<std::vector<int>> gatherStart, gather;    // nodes whose adjoints are gathered in the window
    std::vector<int> readyStart, ready;                   // elements assembled in the window (a neighbour's too)
  };
  int window = 0;
  std::vector<Lane> lanes;               // none: no plan; else a multiple of four
  std::vector<int> order;                // every element once, lane by lane, ascending within a lane
  std::array<std::vector<int>, 2> phaseLanes;  // the lanes of each phase, ascending (half of the lanes each)
  std::vector<std::vector<int>> cross;   // per layer: nodes forwarded before the lanes and gathered after them
  std::vector<std::vector<int>> unread;  // per layer: nodes no element reads (a zero adjoint, set before the lanes)
  std::vector<int> deferred;             // elements run after the lanes, ascending
  ElementSchedule deferredSchedule;      // over positions in `deferred`

  bool empty() const { return lanes.empty(); }
};

/// The plan for `elements` (K vertex ids each) over `numLayers` layers, `shared` naming the Shared ones.
/// laneElements ≤ 0, or a mesh of fewer than 4 × laneElements elements: no plan.
StageWindowPlan planWindows(const StencilTable& elements, int numVertices, int numLayers,
                            const std::vector<StageWindowPlan::SharedReads>& shared,
                            int laneElements = kWindowPlanLaneElements, int window = kWindowPlanWindow);

}  // namespace jetshell
