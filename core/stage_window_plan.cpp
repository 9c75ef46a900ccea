#include "core/stage_window_plan.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace jetshell {
namespace {

/// Counting sort of items 0 … key.size()−1 by key (in [0, buckets), or −1: left out), ascending within a bucket.
void bucketByKey(const std::vector<int>& key, int buckets, std::vector<int>& start, std::vector<int>& items) {
  start.assign(static_cast<std::size_t>(buckets) + 1, 0);
  for (int k : key)
    if (k >= 0) ++start[static_cast<std::size_t>(k) + 1];
  for (int b = 0; b < buckets; ++b) start[static_cast<std::size_t>(b) + 1] += start[static_cast<std::size_t>(b)];
  items.assign(static_cast<std::size_t>(start.back()), 0);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < key.size(); ++i)
    if (key[i] >= 0) items[static_cast<std::size_t>(fill[static_cast<std::size_t>(key[i])]++)] = static_cast<int>(i);
}

constexpr int kNone = -1;      // a node's or element's lane: not set
constexpr int kCross = -2;     // a node forwarded before the phases and gathered after them
constexpr int kUnread = -3;    // a node no element reads
constexpr int kDeferred = -2;  // an element assembled after the phases

/// Where a node is forwarded or gathered: a lane and a window of it, or kCross / kUnread in `lane`.
struct Place {
  int lane = kNone, window = 0;
};

/// Lane k's range [begin, end) of `ne` elements cut into `numLanes` lanes.
std::pair<int, int> laneRange(int k, int ne, int numLanes) {
  return {static_cast<int>(static_cast<std::int64_t>(k) * ne / numLanes),
          static_cast<int>(static_cast<std::int64_t>(k + 1) * ne / numLanes)};
}

/// The elements in bands of the mesh's connectivity, cut into `numLanes` lanes: breadth-first over elements that
/// share a vertex, each connected part from the last element of a breadth-first sweep from its lowest-numbered
/// one (an end of a longest path, nearly), the parts one after another; each lane's range then ascending.
std::vector<int> bandOrder(const StencilTable& elements, int numVertices, int numLanes) {
  const int ne = elements.size(), K = elements.width;
  std::vector<int> start(static_cast<std::size_t>(numVertices) + 1, 0);
  for (int v : elements.ids)
    if (v >= 0) ++start[static_cast<std::size_t>(v) + 1];
  for (int v = 0; v < numVertices; ++v) start[static_cast<std::size_t>(v) + 1] += start[static_cast<std::size_t>(v)];
  std::vector<int> readers(static_cast<std::size_t>(start.back()));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int e = 0; e < ne; ++e)
    for (int k = 0; k < K; ++k) {
      const int v = elements.element(e)[k];
      if (v >= 0) readers[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = e;
    }
  std::vector<int> mark(static_cast<std::size_t>(ne), -1), queue, order;
  queue.reserve(static_cast<std::size_t>(ne));
  order.reserve(static_cast<std::size_t>(ne));
  int sweep = 0;
  const auto breadthFirst = [&](int from) {
    queue.assign(1, from);
    mark[static_cast<std::size_t>(from)] = sweep;
    for (std::size_t h = 0; h < queue.size(); ++h)
      for (int k = 0; k < K; ++k) {
        const int v = elements.element(queue[h])[k];
        if (v < 0) continue;
        for (int i = start[static_cast<std::size_t>(v)]; i < start[static_cast<std::size_t>(v) + 1]; ++i) {
          int& m = mark[static_cast<std::size_t>(readers[static_cast<std::size_t>(i)])];
          if (m != sweep) {
            m = sweep;
            queue.push_back(readers[static_cast<std::size_t>(i)]);
          }
        }
      }
    ++sweep;
  };
  std::vector<char> placed(static_cast<std::size_t>(ne), 0);
  for (int e = 0; e < ne; ++e) {
    if (placed[static_cast<std::size_t>(e)]) continue;
    breadthFirst(e);
    breadthFirst(queue.back());
    for (int f : queue) placed[static_cast<std::size_t>(f)] = 1;
    order.insert(order.end(), queue.begin(), queue.end());
  }
  for (int k = 0; k < numLanes; ++k) {
    const auto [begin, end] = laneRange(k, ne, numLanes);
    std::sort(order.begin() + begin, order.begin() + end);
  }
  return order;
}

/// Phases for the lanes cut in `order`, half of the lanes in each, so that few vertices are touched by two lanes
/// of one phase (each such vertex defers the elements on it): from lanes alternating, the swap of a lane of each
/// phase that lowers that count most, until none does. Empty when it finds nothing better than alternating. A
/// mesh numbered row by row keeps its lanes alternating; a mesh numbered part by part (a garment's front panel,
/// then its back) gets the lanes that meet across a seam in different phases.
std::vector<int> balancedLanePhases(const StencilTable& elements, int numVertices, const std::vector<int>& order,
                                    int numLanes) {
  const int ne = elements.size(), K = elements.width;
  const auto L = static_cast<std::size_t>(numLanes);
  // shared[a·L + b]: the vertices lanes a and b both touch (lanesOf: the lanes touching each vertex)
  std::vector<std::vector<int>> lanesOf(static_cast<std::size_t>(numVertices));
  for (int k = 0; k < numLanes; ++k) {
    const auto [begin, end] = laneRange(k, ne, numLanes);
    for (int p = begin; p < end; ++p)
      for (int i = 0; i < K; ++i) {
        const int v = elements.element(order[static_cast<std::size_t>(p)])[i];
        if (v < 0) continue;
        std::vector<int>& l = lanesOf[static_cast<std::size_t>(v)];
        if (l.empty() || l.back() != k) l.push_back(k);
      }
  }
  std::vector<std::int64_t> shared(L * L, 0);
  for (const std::vector<int>& l : lanesOf)
    for (std::size_t i = 0; i < l.size(); ++i)
      for (std::size_t j = i + 1; j < l.size(); ++j) {
        ++shared[static_cast<std::size_t>(l[i]) * L + static_cast<std::size_t>(l[j])];
        ++shared[static_cast<std::size_t>(l[j]) * L + static_cast<std::size_t>(l[i])];
      }
  std::vector<int> phase(L);
  for (int k = 0; k < numLanes; ++k) phase[static_cast<std::size_t>(k)] = k % 2;
  // d[a]: the vertices lane a shares with the other lanes of its phase, less those it shares with the other
  // phase's lanes; swapping the phases of lanes a and b (of different phases) lowers the within-phase count by
  // d[a] + d[b] + 2 shared(a, b).
  const auto at = [&](int a, int b) { return shared[static_cast<std::size_t>(a) * L + static_cast<std::size_t>(b)]; };
  const auto same = [&](int a, int b) { return phase[static_cast<std::size_t>(a)] == phase[static_cast<std::size_t>(b)]; };
  std::vector<std::int64_t> d(L);
  bool improved = false;
  for (int round = 0; round < numLanes; ++round) {
    for (int a = 0; a < numLanes; ++a) {
      d[static_cast<std::size_t>(a)] = 0;
      for (int c = 0; c < numLanes; ++c)
        if (c != a) d[static_cast<std::size_t>(a)] += same(a, c) ? at(a, c) : -at(a, c);
    }
    int bestA = -1, bestB = -1;
    std::int64_t best = 0;
    for (int a = 0; a < numLanes; ++a)
      for (int b = 0; b < numLanes; ++b)
        if (phase[static_cast<std::size_t>(a)] == 0 && phase[static_cast<std::size_t>(b)] == 1) {
          const std::int64_t gain = d[static_cast<std::size_t>(a)] + d[static_cast<std::size_t>(b)] + 2 * at(a, b);
          if (gain > best) {
            best = gain;
            bestA = a;
            bestB = b;
          }
        }
    if (bestA < 0) break;
    std::swap(phase[static_cast<std::size_t>(bestA)], phase[static_cast<std::size_t>(bestB)]);
    improved = true;
  }
  if (!improved) return {};
  return phase;
}

/// The plan with the lanes cut in `order` (planWindows' checks done), lane k running in phase lanePhase[k].
StageWindowPlan planInOrder(const StencilTable& elements, int numVertices, int numLayers,
                            const std::vector<StageWindowPlan::SharedReads>& shared, int numLanes, int window,
                            std::vector<int> order, const std::vector<int>& lanePhase) {
  StageWindowPlan plan;
  const int ne = elements.size();
  plan.window = window;
  plan.order = std::move(order);
  plan.lanes.resize(static_cast<std::size_t>(numLanes));
  std::vector<int> laneOf(static_cast<std::size_t>(ne)), position(static_cast<std::size_t>(ne));
  for (int p = 0; p < ne; ++p) position[static_cast<std::size_t>(plan.order[static_cast<std::size_t>(p)])] = p;
  for (int k = 0; k < numLanes; ++k) {
    StageWindowPlan::Lane& lane = plan.lanes[static_cast<std::size_t>(k)];
    std::tie(lane.begin, lane.end) = laneRange(k, ne, numLanes);
    for (int p = lane.begin; p < lane.end; ++p) laneOf[static_cast<std::size_t>(plan.order[static_cast<std::size_t>(p)])] = k;
    lane.forwardStart.resize(static_cast<std::size_t>(numLayers));
    lane.forward.resize(static_cast<std::size_t>(numLayers));
    lane.gatherStart.resize(static_cast<std::size_t>(numLayers));
    lane.gather.resize(static_cast<std::size_t>(numLayers));
  }
  const auto lane = [&](int e) { return laneOf[static_cast<std::size_t>(e)]; };
  const auto windowOf = [&](int e) {
    return (position[static_cast<std::size_t>(e)] - plan.lanes[static_cast<std::size_t>(lane(e))].begin) / window;
  };
  const auto firstPhase = [&](int k) { return lanePhase[static_cast<std::size_t>(k)] == 0; };
  for (int k = 0; k < numLanes; ++k)
    plan.phaseLanes[static_cast<std::size_t>(lanePhase[static_cast<std::size_t>(k)])].push_back(k);

  // Per Shared layer, per node: where it is forwarded and gathered. Its readers are elements of one lane (that
  // lane does both), of two lanes of different phases (the first phase's lane forwards it, at its first reader
  // there; the second phase's lane gathers it, at its last reader there, when the other lane's readers are
  // done), of two lanes of one phase or more lanes (a cross node), or of none.
  plan.cross.resize(static_cast<std::size_t>(numLayers));
  plan.unread.resize(static_cast<std::size_t>(numLayers));
  std::vector<std::vector<Place>> forwardAt(static_cast<std::size_t>(numLayers)), gatherAt(static_cast<std::size_t>(numLayers));
  for (const StageWindowPlan::SharedReads& s : shared) {
    if (s.layer < 0 || s.layer >= numLayers) throw std::invalid_argument("stage window plan: layer out of range");
    const auto L = static_cast<std::size_t>(s.layer);
    const std::vector<int>& start = *s.elementStart;
    const std::vector<int>& node = *s.elementNode;
    const auto count = static_cast<std::size_t>(s.count);
    // first and last readers, the last reader in the first reader's lane, the first in the last reader's lane
    std::vector<int> first(count, -1), last(count, -1), lastInLow(count, -1), firstInHigh(count, -1);
    std::vector<int> lanesRead(count, 0);  // the lanes reading the node (they come one after another)
    for (const int e : plan.order)
      for (int l = start[static_cast<std::size_t>(e)]; l < start[static_cast<std::size_t>(e) + 1]; ++l) {
        const auto n = static_cast<std::size_t>(node[static_cast<std::size_t>(l)]);
        if (first[n] < 0) first[n] = e;
        if (last[n] < 0 || lane(last[n]) != lane(e)) {
          firstInHigh[n] = e;
          ++lanesRead[n];
        }
        last[n] = e;
        if (lane(e) == lane(first[n])) lastInLow[n] = e;
      }
    forwardAt[L].resize(count);
    gatherAt[L].resize(count);
    for (std::size_t n = 0; n < count; ++n) {
      Place& f = forwardAt[L][n];
      Place& g = gatherAt[L][n];
      if (first[n] < 0) {
        f.lane = g.lane = kUnread;
        plan.unread[L].push_back(static_cast<int>(n));
        continue;
      }
      const int low = lane(first[n]), high = lane(last[n]);
      if (low == high) {
        f = {low, windowOf(first[n])};
        g = {low, windowOf(last[n])};
      } else if (lanesRead[n] == 2 && firstPhase(low) != firstPhase(high)) {
        const int e0 = firstPhase(low) ? first[n] : firstInHigh[n];
        const int e1 = firstPhase(low) ? last[n] : lastInLow[n];
        f = {lane(e0), windowOf(e0)};
        g = {lane(e1), windowOf(e1)};
      } else {
        f.lane = g.lane = kCross;
        plan.cross[L].push_back(static_cast<int>(n));
      }
    }
  }

  // Per element: the lane that assembles it, once its owned nodes are gathered: its own lane, or the second
  // phase's lane that gathers an owned node it shares with the element's lane (then of the first phase); deferred
  // when it owns a cross node or nodes gathered by two other lanes.
  std::vector<Place> assembleAt(static_cast<std::size_t>(ne));
  for (int e = 0; e < ne; ++e) {
    Place& a = assembleAt[static_cast<std::size_t>(e)];
    a = {lane(e), windowOf(e)};
    int other = kNone, otherWindow = 0;
    for (const StageWindowPlan::SharedReads& s : shared) {
      const auto L = static_cast<std::size_t>(s.layer);
      const std::vector<int>& start = *s.elementStart;
      for (int o = (*s.ownedStart)[static_cast<std::size_t>(e)]; o < (*s.ownedStart)[static_cast<std::size_t>(e) + 1]; ++o) {
        const auto n = static_cast<std::size_t>((*s.elementNode)[static_cast<std::size_t>(
            start[static_cast<std::size_t>(e)] + (*s.ownedIndex)[static_cast<std::size_t>(o)])]);
        const Place& g = gatherAt[L][n];
        if (g.lane == kCross) {
          a.lane = kDeferred;
        } else if (g.lane == lane(e)) {
          a.window = std::max(a.window, g.window);
        } else if (other == kNone || other == g.lane) {
          other = g.lane;
          otherWindow = std::max(otherWindow, g.window);
        } else {
          a.lane = kDeferred;
        }
      }
    }
    if (a.lane != kDeferred && other != kNone) a = {other, otherWindow};  // the owned nodes of its own lane
                                                                           // are gathered in the first phase
  }
  // Lanes of one phase run at the same time: an element whose vertex another lane of its phase also writes is
  // deferred (both are).
  std::vector<int> writer[2] = {std::vector<int>(static_cast<std::size_t>(numVertices), kNone),
                                std::vector<int>(static_cast<std::size_t>(numVertices), kNone)};
  const int K = elements.width;
  for (int e = 0; e < ne; ++e) {
    const Place& a = assembleAt[static_cast<std::size_t>(e)];
    if (a.lane < 0) continue;
    for (int k = 0; k < K; ++k) {
      const int v = elements.element(e)[k];
      if (v < 0) continue;
      int& w = writer[lanePhase[static_cast<std::size_t>(a.lane)]][static_cast<std::size_t>(v)];
      w = w == kNone || w == a.lane ? a.lane : kDeferred;
    }
  }
  for (int e = 0; e < ne; ++e) {
    Place& a = assembleAt[static_cast<std::size_t>(e)];
    if (a.lane < 0) continue;
    for (int k = 0; k < K; ++k) {
      const int v = elements.element(e)[k];
      if (v >= 0 && writer[lanePhase[static_cast<std::size_t>(a.lane)]][static_cast<std::size_t>(v)] == kDeferred) {
        a.lane = kDeferred;
        break;
      }
    }
  }

  // Each lane's windows: per layer the nodes it forwards and gathers, and the elements it assembles. One
  // counting sort per list over all lanes' windows (numbered lane by lane), then each lane takes its range.
  std::vector<int> windowBase(static_cast<std::size_t>(numLanes) + 1, 0);
  for (int k = 0; k < numLanes; ++k) {
    const StageWindowPlan::Lane& l = plan.lanes[static_cast<std::size_t>(k)];
    windowBase[static_cast<std::size_t>(k) + 1] =
        windowBase[static_cast<std::size_t>(k)] + (l.end - l.begin + window - 1) / window;
  }
  // Lane k's share of `at`, by window: start (its windows + 1 offsets into items) and items.
  const auto split = [&](const std::vector<Place>& at, const auto& lists) {
    std::vector<int> key(at.size(), -1);
    for (std::size_t i = 0; i < at.size(); ++i)
      if (at[i].lane >= 0) key[i] = windowBase[static_cast<std::size_t>(at[i].lane)] + at[i].window;
    std::vector<int> start, items;
    bucketByKey(key, windowBase.back(), start, items);
    for (int k = 0; k < numLanes; ++k) {
      auto [laneStart, laneItems] = lists(plan.lanes[static_cast<std::size_t>(k)]);
      const auto first = start.begin() + windowBase[static_cast<std::size_t>(k)];
      const auto last = start.begin() + windowBase[static_cast<std::size_t>(k) + 1] + 1;
      laneItems->assign(items.begin() + *first, items.begin() + *(last - 1));
      laneStart->assign(first, last);
      for (int& s : *laneStart) s -= *first;
    }
  };
  for (const StageWindowPlan::SharedReads& s : shared) {
    const auto L = static_cast<std::size_t>(s.layer);
    split(forwardAt[L], [L](StageWindowPlan::Lane& l) { return std::pair{&l.forwardStart[L], &l.forward[L]}; });
    split(gatherAt[L], [L](StageWindowPlan::Lane& l) { return std::pair{&l.gatherStart[L], &l.gather[L]}; });
  }
  split(assembleAt, [](StageWindowPlan::Lane& l) { return std::pair{&l.readyStart, &l.ready}; });
  // The deferred elements, in a coloured schedule of their own (blocks sharing no vertex run in parallel).
  StencilTable table{K, {}};
  for (int e = 0; e < ne; ++e)
    if (assembleAt[static_cast<std::size_t>(e)].lane == kDeferred) {
      plan.deferred.push_back(e);
      table.ids.insert(table.ids.end(), elements.element(e), elements.element(e) + K);
    }
  plan.deferredSchedule = scheduleElements(table, numVertices);
  return plan;
}

}  // namespace

StageWindowPlan planWindows(const StencilTable& elements, int numVertices, int numLayers,
                            const std::vector<StageWindowPlan::SharedReads>& shared, int laneElements,
                            int window) {
  const int ne = elements.size();
  if (laneElements <= 0) return {};
  const int numLanes = ne / laneElements / 4 * 4;  // an even number of lanes in each phase
  if (numLanes < 4) return {};
  if (window <= 0) throw std::invalid_argument("stage window plan: the window must hold at least one element");
  std::vector<int> numbering(static_cast<std::size_t>(ne)), alternate(static_cast<std::size_t>(numLanes));
  for (int e = 0; e < ne; ++e) numbering[static_cast<std::size_t>(e)] = e;
  for (int k = 0; k < numLanes; ++k) alternate[static_cast<std::size_t>(k)] = k % 2;
  StageWindowPlan plan = planInOrder(elements, numVertices, numLayers, shared, numLanes, window, numbering, alternate);
  if (!plan.deferred.empty()) {
    const std::vector<int> phases = balancedLanePhases(elements, numVertices, numbering, numLanes);
    if (!phases.empty()) {
      StageWindowPlan other =
          planInOrder(elements, numVertices, numLayers, shared, numLanes, window, numbering, phases);
      if (other.deferred.size() < plan.deferred.size()) plan = std::move(other);
    }
  }
  if (4 * plan.deferred.size() <= static_cast<std::size_t>(ne)) return plan;
  StageWindowPlan bands = planInOrder(elements, numVertices, numLayers, shared, numLanes, window,
                                      bandOrder(elements, numVertices, numLanes), alternate);
  return bands.deferred.size() < plan.deferred.size() ? bands : plan;
}

}  // namespace jetshell
