// A staged energy as a graph of layers over mesh entities, declared at compile time and differentiated by the
// framework: the fast form of the stage mechanism (core/stage.h), with no chain rule written by the term.
//
// The declaration (types only):
//   using Graph = StageGraph<K,                                   // the element stencil's width
//       Shared<FaceNormalStage, 3, Difference, Difference>,        // layer 0: one node per face, on ≤ 3 vertices
//       Shared<KelvinStage, 4, From<0>, From<0>>,                  // layer 1: one node per edge, on ≤ 4 vertices
//       Local<SecondFormStage, Difference, Difference, From<1>, From<1>, From<1>>,  // per element
//       Local<BendingDensityStage, From<2>>>;                      // the last layer: the element's energy (M = 1)
// A layer applies one stage S (N inputs, M outputs) to each of its entities. Its input groups, in order, fill
// the stage's N inputs: Difference (x_j − x_i, 3 values), Vertex (x_v, 3 values) or From<L> (the M_L outputs of
// a node of an earlier layer L). A Shared layer's nodes are computed once per evaluation and read by every
// node that names them (a face normal by the four bending stencils around it); W bounds the mesh vertices a
// node depends on (its support). A Local layer has one node per element, evaluated inside the element; its
// support is the element's stencil. The last layer is Local, with one output: the element energy.
//
// The set-up (runtime, once per mesh): the entity count of each Shared layer and every node's inputs
// (difference(i, j), vertex(v) with mesh vertex ids, node(entity) of the layer named by From), then the elements
// (the term's stencil table) with their Local nodes' inputs, then finalize(): supports, slot maps, and the lists
// the sweeps read. Nothing in an evaluation allocates once the buffers have their size.
//
// Data flow of one evaluation (StageGraphEvaluator, core/stage_graph_evaluator.h):
//   forward, per Shared layer in order (parallel over its nodes): value y; with derivatives the local Jacobian
//     J = ∂y/∂z and the total Jacobian T = Σ_groups J_g T_g over the node's support (M × 3W, a Difference's T is
//     ±I, a Vertex's I); at order 2, for a per-element exact Hessian, the stage Hessians ∇²y_k.
//   per element (the coloured element loop): the Local layers forward over the element's 3K coordinates (their
//     T rows are full width), or over the 3(K−1) differences x_k − x_0 when every leaf is a Difference (the
//     energy is then translation invariant, and slot 0's gradient and Hessian blocks follow from the others');
//     the root's T is the element gradient. Hessian:
//     H_e = Σ_nodes Z_νᵀ (Σ_k w̄_ν,k ∇²y_ν,k) Z_ν, Z_ν the stacked T of node ν's input groups, w̄_ν its adjoint:
//     - Gauss–Newton: the root's term only (J_sᵀ W'' J_s);
//     - exact, per element (a projection reads each element's own block): w̄ by a reverse sweep over the
//       element's own nodes (its Local nodes and the Shared nodes it reads, directly or not);
//     - exact, contracted (no projection): a first element sweep sends each Local node's adjoint to the
//       Shared nodes it reads; a reverse sweep over the Shared layers sums each node's adjoint over all its
//       readers; each Shared node's curvature is then contracted and added once, by the one element that reads
//       it as its owner (whose stencil holds the node's support), into that element's block: nothing is kept per
//       node but its adjoint. The same Hessian, each term in another block. On a mesh of four lanes or more
//       (core/stage_window_plan.h, built by finalize()) these four sweeps run window by window, each node
//       forwarded, gathered and used while its neighbourhood is in cache; the same terms, summed in the order the
//       plan fixes. When every leaf is a Difference, the Shared nodes keep no T: each element forms the T of the
//       nodes it reads from their Jacobians, by coordinate (the evaluator's elementWhole).
//   a gradient alone: the Shared layers forward (values and Jacobians), a reverse sweep per element (its leaf
//     adjoints into its gradient, what it sends to Shared nodes kept), each Shared node's adjoint and Jᵀw̄ gathered
//     over its readers (last layer first), then each vertex's share of those; with a window plan these passes run
//     window by window as the contracted Hessian's do.
//   a value alone: each Shared node's stage, then each element's Local stages, called on doubles (no Jacobian).
// Each fact lives in one place: a node's inputs and support in its layer's tables; its value, Jacobians and
// adjoint in the layer's per-evaluation buffers; the element's slots in the stencil table.
#pragma once

#include "core/stage.h"
#include "core/stage_window_plan.h"
#include "core/stencil.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace jetshell {

// ---- input groups ------------------------------------------------------------------------------------------
struct Difference {};  // x_j − x_i of mesh vertices (i, j)
struct Vertex {};      // x_v
template <int L>
struct From {};  // the outputs of a node of layer L

/// One input group of one node, at set-up: mesh vertex ids (Difference: i, j; Vertex: v) or an entity of the
/// layer the group's From names.
struct InputRef {
  int a = -1, b = -1;
};
inline InputRef difference(int i, int j) { return {i, j}; }
inline InputRef vertex(int v) { return {v, -1}; }
inline InputRef node(int entity) { return {entity, -1}; }

// ---- layers ------------------------------------------------------------------------------------------------
template <typename S, int W, typename... In>
struct Shared {
  using Stage = S;
  static constexpr bool kShared = true;
  static constexpr int kWidth = W;
  using Inputs = std::tuple<In...>;
};
template <typename S, typename... In>
struct Local {
  using Stage = S;
  static constexpr bool kShared = false;
  static constexpr int kWidth = 0;  // the element's stencil
  using Inputs = std::tuple<In...>;
};

namespace stage_graph_detail {

template <typename G>
struct GroupKind {
  static constexpr int kLayer = -1;  // a leaf
  static constexpr bool kDifference = std::is_same_v<G, Difference>;
  static_assert(std::is_same_v<G, Difference> || std::is_same_v<G, Vertex>, "an input group is Difference, Vertex or From<L>");
};
template <int L>
struct GroupKind<From<L>> {
  static constexpr int kLayer = L;
  static constexpr bool kDifference = false;
};

/// s[g] = Σ_{i<g} v[i], for g = 0 … n.
template <std::size_t n>
constexpr std::array<int, n + 1> prefixSums(const std::array<int, n>& v) {
  std::array<int, n + 1> s{};
  for (std::size_t i = 0; i < n; ++i) s[i + 1] = s[i] + v[i];
  return s;
}

}  // namespace stage_graph_detail

/// The compile-time shape of layer I of a graph of layers Ls... over K-vertex elements.
template <int K, int I, typename... Ls>
struct LayerShape {
  using Layer = std::tuple_element_t<I, std::tuple<Ls...>>;
  using Stage = typename Layer::Stage;
  static constexpr int M = Stage::kOutputs, N = Stage::kInputs;
  static constexpr bool kShared = Layer::kShared;
  static constexpr int W = kShared ? Layer::kWidth : K;  // support width
  static constexpr int G = static_cast<int>(std::tuple_size_v<typename Layer::Inputs>);

  template <typename In>
  static constexpr int layerOf() { return stage_graph_detail::GroupKind<In>::kLayer; }
  template <typename In>
  static constexpr int sizeOf() {
    constexpr int l = layerOf<In>();
    if constexpr (l < 0) {
      return 3;
    } else {
      static_assert(l < I, "From<L> names an earlier layer");
      return std::tuple_element_t<l, std::tuple<Ls...>>::Stage::kOutputs;
    }
  }
  template <typename In>
  static constexpr int supportOf() {
    constexpr int l = layerOf<In>();
    if constexpr (l < 0) {
      return std::is_same_v<In, Difference> ? 2 : 1;
    } else {
      using From = std::tuple_element_t<l, std::tuple<Ls...>>;
      return From::kShared ? From::kWidth : K;
    }
  }
  template <typename In>
  static constexpr bool fromSharedOf() {
    constexpr int l = layerOf<In>();
    if constexpr (l < 0) {
      return false;
    } else {
      return std::tuple_element_t<l, std::tuple<Ls...>>::kShared;
    }
  }
  template <typename Tuple>
  struct Table;
  template <typename... In>
  struct Table<std::tuple<In...>> {
    static constexpr std::array<int, sizeof...(In)> layer{{layerOf<In>()...}};
    static constexpr std::array<int, sizeof...(In)> size{{sizeOf<In>()...}};
    static constexpr std::array<int, sizeof...(In)> support{{supportOf<In>()...}};
    static constexpr std::array<bool, sizeof...(In)> isDifference{{std::is_same_v<In, Difference>...}};
    static constexpr std::array<bool, sizeof...(In)> fromShared{{fromSharedOf<In>()...}};
  };
  using Groups = Table<typename Layer::Inputs>;
  // Where each group starts in the stage's inputs and in a node's slot map: tables, so that a group index known
  // only at run time (a reader's group) costs one lookup, not a loop.
  static constexpr auto kOffsets = stage_graph_detail::prefixSums(Groups::size);
  static constexpr auto kSlotOffsets = stage_graph_detail::prefixSums(Groups::support);
  static constexpr int offset(int g) { return kOffsets[static_cast<std::size_t>(g)]; }
  static constexpr int slotOffset(int g) { return kSlotOffsets[static_cast<std::size_t>(g)]; }
  static constexpr int kSlots = slotOffset(G);  // slot-map entries per node
  // The part of a Local node's input adjoint that the Shared layers gather (its From-Shared groups'), where
  // each such group starts in it, and its length: the rest (leaves, Local inputs) is never read back.
  static constexpr std::array<int, G> sharedSizes() {
    std::array<int, G> v{};
    for (int g = 0; g < G; ++g)
      v[static_cast<std::size_t>(g)] = Groups::fromShared[static_cast<std::size_t>(g)] ? Groups::size[static_cast<std::size_t>(g)] : 0;
    return v;
  }
  static constexpr auto kSentOffsets = stage_graph_detail::prefixSums(sharedSizes());
  static constexpr int sentOffset(int g) { return kSentOffsets[static_cast<std::size_t>(g)]; }
  static constexpr int kSent = sentOffset(G);
  static_assert(offset(G) == N, "the layer's input groups must fill its stage's inputs");
  static constexpr bool readsLocal() {
    for (int g = 0; g < G; ++g)
      if (Groups::layer[static_cast<std::size_t>(g)] >= 0 && !Groups::fromShared[static_cast<std::size_t>(g)]) return true;
    return false;
  }
  static_assert(!kShared || !readsLocal(), "a Shared layer reads leaves and Shared layers only");
};

/// The shared, mesh-level part of a staged energy: its layers' inputs, supports and the lists its sweeps read.
/// The stages themselves (with their data) live in stages(); evaluation is StageGraphEvaluator's.
template <int K, typename... Ls>
class StageGraph {
 public:
  static constexpr int kVertices = K;
  static constexpr int kLayers = static_cast<int>(sizeof...(Ls));
  static constexpr int kRoot = kLayers - 1;
  template <int I>
  using Shape = LayerShape<K, I, Ls...>;
  using Stages = std::tuple<typename Ls::Stage...>;
  static_assert(!Shape<kRoot>::kShared && Shape<kRoot>::M == 1, "the last layer is Local with one output");
  /// Most Shared nodes of one layer an element may read (directly or not).
  static constexpr int kMaxElementNodes = 16;
  /// True when every leaf input group of every layer is a Difference: the energy then depends on the vertices'
  /// differences only, so it is invariant under a common translation (the evaluator uses this).
  static constexpr bool leavesAreDifferences() { return leavesAreDifferencesIn(std::make_integer_sequence<int, kLayers>()); }

  /// Per layer: the node inputs and supports (set-up), and the per-element lists of the sweeps.
  struct LayerTables {
    int count = 0;                     // Shared: entities; Local: elements
    std::vector<InputRef> inputs;      // count × G
    std::vector<int> support;          // Shared: count × W mesh ids (−1: none)
    std::vector<std::int8_t> slots;    // count × kSlots: per group, per slot of its support, the node's slot
    // Shared layers: per listed node and group; Local layers: per element and group. The index of the
    // group's input node in the element's list of the group's layer (−1 for leaves and Local inputs).
    std::vector<std::int8_t> elementInputs;
    // Shared layers only:
    std::vector<int> elementStart, elementNode;  // per element, the layer's nodes it reads (CSR, ascending)
    // Per listed node, kSlots entries: per group, per slot of its support, the element's slot (−1: none), read
    // in list order by the element's sweeps (the node's slot map composed with its support's place in the
    // stencil, once here).
    std::vector<std::int8_t> elementGroupSlots;
    std::vector<int> owner;                      // per node: the element whose block takes its curvature (−1: a
                                                 // node no element reads, which adds nothing)
    std::vector<int> ownedStart, ownedIndex;     // per element, its owned nodes as indices into its list
    std::vector<int> readerStart;                // per node: readers (CSR, by layer), each a (layer, entity, group)
    std::vector<std::array<int, 3>> readers;
  };

  explicit StageGraph(int numVertices = 0) : numVertices_(numVertices) {}

  int numVertices() const { return numVertices_; }
  Stages& stages() { return stages_; }
  const Stages& stages() const { return stages_; }
  template <int I>
  auto& stage() { return std::get<I>(stages_); }
  template <int I>
  const auto& stage() const { return std::get<I>(stages_); }
  const LayerTables& tables(int layer) const { return tables_[static_cast<std::size_t>(layer)]; }
  /// The leaf inputs of Shared nodes that read each vertex (CSR over vertices), each a (layer, entity, group,
  /// sign): a reverse sweep gathers a vertex's gradient from them.
  const std::vector<int>& vertexReaderStart() const { return vertexReaderStart_; }
  const std::vector<std::array<int, 4>>& vertexReaders() const { return vertexReaders_; }
  const StencilTable& elements() const { return elements_; }
  int numElements() const { return elements_.size(); }
  bool finalized() const { return finalized_; }
  /// The order of the contracted exact Hessian's and a gradient's sweeps (core/stage_window_plan.h), built by
  /// finalize() with the default sizes (windowPlanLaneElements); empty on a mesh of fewer than
  /// 4 × kWindowPlanMinLaneElements elements.
  const StageWindowPlan& windowPlan() const { return windowPlan_; }
  /// Builds the window plan again with other sizes (laneElements ≤ 0: none), for tests and measurements.
  void replanWindows(int laneElements, int window = kWindowPlanWindow) {
    if (!finalized_) throw std::logic_error("stage graph: finalize() before planning its windows");
    std::vector<StageWindowPlan::SharedReads> shared;
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (Shape<I>::kShared) {
        const LayerTables& t = tables_[I];
        shared.push_back({I, t.count, &t.elementStart, &t.elementNode, &t.ownedStart, &t.ownedIndex});
      }
    });
    windowPlan_ = planWindows(elements_, numVertices_, kLayers, shared, laneElements, window);
  }

  /// Sizes Shared layer I for `count` entities (their inputs unset).
  template <int I>
  void resize(int count) {
    static_assert(Shape<I>::kShared, "resize() sizes a Shared layer; Local layers have one node per element");
    LayerTables& t = tables_[I];
    t.count = count;
    t.inputs.assign(static_cast<std::size_t>(count) * Shape<I>::G, InputRef{});
    finalized_ = false;
  }
  /// The elements (K vertex ids each, −1 absent): one node of every Local layer each.
  void setElements(StencilTable elements) {
    if (elements.width != K) throw std::invalid_argument("stage graph: the element table's width must be K");
    elements_ = std::move(elements);
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (!Shape<I>::kShared) {
        LayerTables& t = tables_[I];
        t.count = elements_.size();
        t.inputs.assign(static_cast<std::size_t>(t.count) * Shape<I>::G, InputRef{});
      }
    });
    finalized_ = false;
  }
  /// The inputs of node `entity` of layer I (Local layers: entity = element), one per group in order.
  template <int I>
  void setInputs(int entity, std::initializer_list<InputRef> inputs) {
    LayerTables& t = tables_[I];
    if (entity < 0 || entity >= t.count) throw std::out_of_range("stage graph: entity out of range");
    if (static_cast<int>(inputs.size()) != Shape<I>::G)
      throw std::invalid_argument("stage graph: one input per group of the layer");
    std::size_t k = static_cast<std::size_t>(entity) * Shape<I>::G;
    for (const InputRef& r : inputs) t.inputs[k++] = r;
    finalized_ = false;
  }

  /// Computes supports, slot maps and the sweeps' lists; std::invalid_argument names what does not fit.
  void finalize();

 private:
  template <typename F, int... Is>
  static void forEachLayerImpl(F&& f, std::integer_sequence<int, Is...>) {
    (f(std::integral_constant<int, Is>()), ...);
  }
  template <typename F>
  static void forEachLayer(F&& f) {
    forEachLayerImpl(f, std::make_integer_sequence<int, kLayers>());
  }

  template <int I>
  static constexpr bool layerLeavesAreDifferences() {
    for (int g = 0; g < Shape<I>::G; ++g) {
      const auto k = static_cast<std::size_t>(g);
      if (Shape<I>::Groups::layer[k] < 0 && !Shape<I>::Groups::isDifference[k]) return false;
    }
    return true;
  }
  template <int... Is>
  static constexpr bool leavesAreDifferencesIn(std::integer_sequence<int, Is...>) {
    return (layerLeavesAreDifferences<Is>() && ...);
  }

  template <int I>
  void finalizeSupports();
  template <int I>
  void collectElementNodes(int e, std::array<std::vector<int>, kLayers>& lists) const;
  template <int... Is>
  void collectBackwards(int e, std::array<std::vector<int>, kLayers>& lists, std::integer_sequence<int, Is...>) const {
    (collectElementNodes<kRoot - Is>(e, lists), ...);
  }
  template <int I>
  void addReaders(std::vector<std::vector<std::array<int, 3>>>& perNode, int layer) const;

  int numVertices_ = 0;
  std::vector<int> vertexReaderStart_;
  std::vector<std::array<int, 4>> vertexReaders_;
  Stages stages_;
  std::array<LayerTables, kLayers> tables_;
  StencilTable elements_{K, {}};
  bool finalized_ = false;
  StageWindowPlan windowPlan_;
};

// ---- set-up ------------------------------------------------------------------------------------------------

template <int K, typename... Ls>
template <int I>
void StageGraph<K, Ls...>::finalizeSupports() {
  using S = Shape<I>;
  LayerTables& t = tables_[I];
  t.slots.assign(static_cast<std::size_t>(t.count) * S::kSlots, std::int8_t{-1});
  if constexpr (S::kShared) t.support.assign(static_cast<std::size_t>(t.count) * S::W, -1);
  const auto where = [&](const char* what, int entity) {
    return "stage graph: layer " + std::to_string(I) + ", " + (S::kShared ? "entity " : "element ") +
           std::to_string(entity) + ": " + what;
  };
  for (int i = 0; i < t.count; ++i) {
    int* support = S::kShared ? t.support.data() + static_cast<std::size_t>(i) * S::W : nullptr;
    const int* stencil = S::kShared ? nullptr : elements_.element(i);
    int used = 0;
    // The node's slot of mesh vertex v: Shared nodes add it to their support, Local nodes find it in the stencil.
    const auto slotOf = [&](int v) -> int {
      if (v < 0) return -1;
      if (v >= numVertices_) throw std::invalid_argument(where("a vertex id is out of range", i));
      if constexpr (S::kShared) {
        for (int s = 0; s < used; ++s)
          if (support[s] == v) return s;
        if (used == S::W) throw std::invalid_argument(where("the inputs span more vertices than the layer's width", i));
        support[used] = v;
        return used++;
      } else {
        for (int s = 0; s < K; ++s)
          if (stencil[s] == v) return s;
        throw std::invalid_argument(where("an input's vertex is not in the element's stencil", i));
      }
    };
    std::int8_t* slots = t.slots.data() + static_cast<std::size_t>(i) * S::kSlots;
    for (int g = 0; g < S::G; ++g) {
      const InputRef& r = t.inputs[static_cast<std::size_t>(i) * S::G + g];
      const int l = S::Groups::layer[static_cast<std::size_t>(g)];
      std::int8_t* gs = slots + S::slotOffset(g);
      if (l < 0) {
        if (r.a < 0 || (S::Groups::isDifference[static_cast<std::size_t>(g)] && r.b < 0))
          throw std::invalid_argument(where("a leaf input is unset", i));
        gs[0] = static_cast<std::int8_t>(slotOf(r.a));
        if (S::Groups::isDifference[static_cast<std::size_t>(g)]) gs[1] = static_cast<std::int8_t>(slotOf(r.b));
        continue;
      }
      const int w = S::Groups::support[static_cast<std::size_t>(g)];
      if (!S::Groups::fromShared[static_cast<std::size_t>(g)]) {
        // A Local layer read by a later Local layer: the element's own node, over the same stencil.
        if (r.a >= 0 && r.a != i) throw std::invalid_argument(where("a Local layer's node is the element's own", i));
        t.inputs[static_cast<std::size_t>(i) * S::G + g].a = i;
        for (int s = 0; s < w; ++s) gs[s] = static_cast<std::int8_t>(s);
        continue;
      }
      const LayerTables& from = tables_[static_cast<std::size_t>(l)];
      if (r.a < 0 || r.a >= from.count) throw std::invalid_argument(where("a From input names no node", i));
      for (int s = 0; s < w; ++s) gs[s] = static_cast<std::int8_t>(slotOf(from.support[static_cast<std::size_t>(r.a) * w + s]));
    }
  }
}

template <int K, typename... Ls>
template <int I>
void StageGraph<K, Ls...>::collectElementNodes(int e, std::array<std::vector<int>, kLayers>& lists) const {
  // Layers from last to first: every node of layer I an element reads is in lists[I] once the layers after I
  // have been visited; its From inputs are added to their layers' lists.
  using S = Shape<I>;
  const LayerTables& t = tables_[I];
  const auto visit = [&](int entity) {
    for (int g = 0; g < S::G; ++g) {
      const int l = S::Groups::layer[static_cast<std::size_t>(g)];
      if (l < 0 || !S::Groups::fromShared[static_cast<std::size_t>(g)]) continue;
      std::vector<int>& list = lists[static_cast<std::size_t>(l)];
      const int from = t.inputs[static_cast<std::size_t>(entity) * S::G + g].a;
      bool seen = false;
      for (int n : list) seen = seen || n == from;
      if (!seen) list.push_back(from);
    }
  };
  if constexpr (S::kShared) {
    for (int n : lists[I]) visit(n);
  } else {
    visit(e);
  }
}

template <int K, typename... Ls>
template <int I>
void StageGraph<K, Ls...>::addReaders(std::vector<std::vector<std::array<int, 3>>>& perNode, int layer) const {
  using S = Shape<I>;
  const LayerTables& t = tables_[I];
  for (int i = 0; i < t.count; ++i)
    for (int g = 0; g < S::G; ++g)
      if (S::Groups::layer[static_cast<std::size_t>(g)] == layer)
        perNode[static_cast<std::size_t>(t.inputs[static_cast<std::size_t>(i) * S::G + g].a)].push_back({I, i, g});
}

template <int K, typename... Ls>
void StageGraph<K, Ls...>::finalize() {
  forEachLayer([&](auto layer) { finalizeSupports<decltype(layer)::value>(); });
  const int ne = elements_.size();
  // Per element: the Shared nodes it reads, per layer (ascending), their slots in the element, and their inputs
  // as indices into the element's lists.
  for (auto& t : tables_) {
    t.elementStart.assign(1, 0);
    t.elementNode.clear();
    t.elementGroupSlots.clear();
    t.elementInputs.clear();
    t.ownedStart.assign(1, 0);
    t.ownedIndex.clear();
    t.owner.assign(static_cast<std::size_t>(t.support.empty() ? 0 : t.count), -1);
  }
  std::array<std::vector<int>, kLayers> lists;
  for (int e = 0; e < ne; ++e) {
    for (auto& l : lists) l.clear();
    collectBackwards(e, lists, std::make_integer_sequence<int, kLayers>());
    const int* stencil = elements_.element(e);
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      if constexpr (S::kShared) {
        LayerTables& t = tables_[I];
        std::vector<int>& list = lists[I];
        std::sort(list.begin(), list.end());
        if (static_cast<int>(list.size()) > kMaxElementNodes)
          throw std::invalid_argument("stage graph: element " + std::to_string(e) + " reads more than " +
                                      std::to_string(kMaxElementNodes) + " nodes of layer " + std::to_string(I));
        for (std::size_t index = 0; index < list.size(); ++index) {
          const int n = list[index];
          t.elementNode.push_back(n);
          std::array<int, S::W> nodeSlot{};
          for (int s = 0; s < S::W; ++s) {
            const int v = t.support[static_cast<std::size_t>(n) * S::W + s];
            int slot = -1;
            for (int k = 0; k < K && v >= 0; ++k)
              if (stencil[k] == v) {
                slot = k;
                break;
              }
            if (v >= 0 && slot < 0)
              throw std::invalid_argument("stage graph: layer " + std::to_string(I) + ", entity " + std::to_string(n) +
                                          ": its support is not in the stencil of element " + std::to_string(e));
            nodeSlot[static_cast<std::size_t>(s)] = slot;
          }
          const std::int8_t* groupSlot = t.slots.data() + static_cast<std::size_t>(n) * S::kSlots;
          for (int j = 0; j < S::kSlots; ++j)
            t.elementGroupSlots.push_back(
                static_cast<std::int8_t>(groupSlot[j] >= 0 ? nodeSlot[static_cast<std::size_t>(groupSlot[j])] : -1));
          if (t.owner[static_cast<std::size_t>(n)] < 0) {
            t.owner[static_cast<std::size_t>(n)] = e;
            t.ownedIndex.push_back(static_cast<int>(index));
          }
        }
        t.elementStart.push_back(static_cast<int>(t.elementNode.size()));
        t.ownedStart.push_back(static_cast<int>(t.ownedIndex.size()));
      }
    });
    // The inputs of each listed node and of the element's Local nodes, as indices into the element's lists
    // (sorted above).
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      LayerTables& t = tables_[I];
      const auto add = [&](int n) {
        for (int g = 0; g < S::G; ++g) {
          const int l = S::Groups::layer[static_cast<std::size_t>(g)];
          int index = -1;
          if (l >= 0 && S::Groups::fromShared[static_cast<std::size_t>(g)]) {
            const std::vector<int>& from = lists[static_cast<std::size_t>(l)];
            const int entity = t.inputs[static_cast<std::size_t>(n) * S::G + g].a;
            index = static_cast<int>(std::lower_bound(from.begin(), from.end(), entity) - from.begin());
          }
          t.elementInputs.push_back(static_cast<std::int8_t>(index));
        }
      };
      if constexpr (S::kShared) {
        for (int n : lists[I]) add(n);
      } else {
        add(e);
      }
    });
  }
  // Readers of every Shared node (the contracted adjoint sweep sums over them).
  forEachLayer([&](auto layer) {
    constexpr int I = decltype(layer)::value;
    if constexpr (Shape<I>::kShared) {
      LayerTables& t = tables_[I];
      std::vector<std::vector<std::array<int, 3>>> perNode(static_cast<std::size_t>(t.count));
      forEachLayer([&](auto reader) {
        constexpr int J = decltype(reader)::value;
        if constexpr (J > I) addReaders<J>(perNode, I);
      });
      t.readerStart.assign(1, 0);
      t.readers.clear();
      for (auto& r : perNode) {
        std::sort(r.begin(), r.end());  // by reader layer: a sweep handles each layer's readers in one run
        t.readers.insert(t.readers.end(), r.begin(), r.end());
        t.readerStart.push_back(static_cast<int>(t.readers.size()));
      }
    }
  });
  // The leaf inputs of the Shared layers, per vertex (x_j − x_i: +1 at j, −1 at i).
  std::vector<std::vector<std::array<int, 4>>> perVertex(static_cast<std::size_t>(numVertices_));
  forEachLayer([&](auto layer) {
    constexpr int I = decltype(layer)::value;
    using S = Shape<I>;
    if constexpr (S::kShared) {
      const LayerTables& t = tables_[I];
      for (int n = 0; n < t.count; ++n)
        for (int g = 0; g < S::G; ++g) {
          if (S::Groups::layer[static_cast<std::size_t>(g)] >= 0) continue;
          const InputRef& r = t.inputs[static_cast<std::size_t>(n) * S::G + g];
          if (S::Groups::isDifference[static_cast<std::size_t>(g)]) {
            perVertex[static_cast<std::size_t>(r.a)].push_back({I, n, g, -1});
            perVertex[static_cast<std::size_t>(r.b)].push_back({I, n, g, 1});
          } else {
            perVertex[static_cast<std::size_t>(r.a)].push_back({I, n, g, 1});
          }
        }
    }
  });
  vertexReaderStart_.assign(1, 0);
  vertexReaders_.clear();
  for (const auto& r : perVertex) {
    vertexReaders_.insert(vertexReaders_.end(), r.begin(), r.end());
    vertexReaderStart_.push_back(static_cast<int>(vertexReaders_.size()));
  }
  finalized_ = true;
  replanWindows(windowPlanLaneElements(elements_.size()));
}

}  // namespace jetshell
