// Evaluation of a StageGraph (core/stage_graph.h): value, gradient and Hessian of the element energies, every
// derivative from the stages' own (Jets, or a stage's checked analytic twin) by the chain rule written here once.
//
// Input:  positions x (3N), the request (gradient and Hessian sinks), the options (derivative path, projection,
//         Gauss–Newton), the term's element schedule (core/assembly.h).
// Output: the energy; the gradient added into *request.gradient; element blocks into *request.hessian through
//         the coloured element loop (core/element_loop.h), projected there when the options ask (or by the
//         term's own element projector, setElementProjector).
// Which sweep runs for which request is described at the top of core/stage_graph.h. A gradient without a
// Hessian comes from a reverse sweep over each element's nodes (adjoints through the local Jacobians, no total
// Jacobians formed; on the analytic path through the stages' pullback twins where declared, whose forward passes
// then compute values only: pulls); with a Hessian, from the root's total Jacobian. An element's curvature goes
// in 3×3 blocks of its slots: only the upper triangle's unless a projection needs the whole block. The contracted
// exact Hessian of a translation-invariant graph (kWhole, the shell's terms), and its Gauss–Newton Hessian (the
// root's curvature only), are formed by whole elements instead (elementWhole): the Shared layers keep their
// Jacobians only, and each element forms the totals of the nodes it reads stored by coordinate (one row per working
// coordinate, padded to whole vectors; a layer of leaves only that no curvature reads forms none, its readers
// composing its Jacobian into theirs: kComposedLeaves) and adds every curvature term as products of those into one
// full block, of which the element's upper triangle is kept (BENCHMARKS.md, sessions 88, 101 and 103). Only a
// projected Hessian stores the Shared layers' totals and stage Hessians, released when it ends. A node's curvature
// C = Σ_k w_k ∇²y_k is contracted in core/stage_contraction.h and added to the element's block by
// core/stage_block_curvature.h (3×3 blocks of its slots) or core/stage_whole_curvature.h (the whole block); this
// file holds the sweeps, the buffers and the chain rule's totals.
// Buffers per Shared layer (value, local Jacobian, total Jacobian, stage Hessians, adjoint) are sized on first
// use and reused; an element's Local nodes live on its thread's stack. The contracted exact Hessian and a gradient
// alone, on a graph with a window plan (core/stage_window_plan.h), run their sweeps lane by lane and window by
// window (contractedInWindows, gradientInWindows) instead of each over the whole mesh. A value alone calls the
// stages on doubles and touches no derivative buffer (valueSweep).
#pragma once

#include "core/element_loop.h"
#include "core/flatten.h"
#include "core/parallel_errors.h"
#include "core/psd_projection.h"
#include "core/stage_block_curvature.h"
#include "core/stage_graph.h"
#include "core/stage_whole_curvature.h"
#include "core/term.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstddef>
#include <functional>
#include <tuple>
#include <vector>

namespace jetshell {

template <typename Graph>
class StageGraphEvaluator {
 public:
  static constexpr int K = Graph::kVertices;
  static constexpr int D = 3 * K;
  static constexpr int kLayers = Graph::kLayers;
  static constexpr int kRoot = Graph::kRoot;
  template <int I>
  using Shape = typename Graph::template Shape<I>;
  using Gradient = Eigen::Matrix<double, D, 1>;
  using Hessian = Eigen::Matrix<double, D, D>;
  /// True when every leaf input of every layer is a Difference: the energy is then a function of the
  /// differences x_k − x_0 alone (invariant under a common translation), and the Hessian path works in those
  /// K − 1 reduced coordinates u_k = x_k − x_0 of the element's slots 1 … K−1 (slot 0 the base). Totals of the
  /// Local layers and the curvature blocks are formed there, (K−1)² blocks instead of K², and the element's
  /// gradient and Hessian follow as g_0 = −Σ_k g_k, H = Lᵀ H_u L (u = L x): exact, not an approximation.
  static constexpr bool kReduced = K >= 2 && Graph::leavesAreDifferences();
  static constexpr int Kw = kReduced ? K - 1 : K;  // the element's working slots (reduced: slots 1 … K−1)
  static constexpr int Dw = 3 * Kw;
  /// The working coordinates padded to whole vectors (a multiple of 4 rows): the row count of an element's totals
  /// stored by coordinate in the whole-element path (elementWhole).
  static constexpr int Rw = (Dw + 3) / 4 * 4;
  /// Where the sweeps add curvature: the element's block over its working slots (reduced: the corner of slots
  /// 1 … K−1, the base's row and column following in expandHessian).
  using WorkHessian = std::conditional_t<kReduced, Eigen::Block<Hessian, Dw, Dw>, Hessian>;

  explicit StageGraphEvaluator(Graph& graph) : graph_(graph) {}

  /// The element's Hessian over its working slots, as an element projector receives it.
  using WorkBlock = Eigen::Matrix<double, Dw, Dw>;
  /// An optional projection that knows the structure of the term's element blocks (as the membrane's splits its
  /// block into an in-plane and a normal part, energies/shell/membrane_projection.h): project(x, e, ids, block,
  /// mode) receives element e's Hessian over its working slots (a translation-invariant graph: the corner over
  /// the differences x_k − x_0, before the base's row and column follow from it, which keeps it positive
  /// semi-definite exactly when the corner is) and returns true when it left that block positive
  /// semi-definite under `mode` (projected, or proved so); false hands the element's whole block to the generic
  /// projection (core/psd_projection.h). Called only when a projection is asked, from the element loop's
  /// threads: it must not write shared state.
  using ElementProjector =
      std::function<bool(const Eigen::VectorXd& x, int e, const int* ids, WorkBlock& block, PsdProjection mode)>;
  void setElementProjector(ElementProjector projector) { projector_ = std::move(projector); }

  /// The energy at x; gradient and Hessian as requested (see the file comment).
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options,
                  const ElementSchedule& schedule, std::vector<double>& elementEnergy) {
    if (!graph_.finalized()) throw std::logic_error("stage graph: finalize() before evaluating");
    const bool wantG = request.gradient != nullptr, wantH = request.hessian != nullptr;
    Mode mode;
    mode.path = options.path;
    mode.order = wantH ? 2 : wantG ? 1 : 0;
    mode.totals = wantH;
    mode.exact = options.hessianModel == HessianModel::Exact;
    mode.full = wantH && options.projection != PsdProjection::None;
    mode.contracted = wantH && mode.exact && !mode.full;
    mode.sharedHessians = wantH && mode.exact && mode.full;
    mode.pullback = wantG && !wantH && options.path == DerivativePath::Analytic;
    // A Hessian without projection (the contracted exact one, or Gauss–Newton) by whole elements forms every total
    // inside the element (elementWhole): the Shared layers keep their Jacobians only, no totals stored.
    mode.whole = kWhole && wantH && !mode.full;
    if (mode.whole) mode.totals = false;
    if constexpr (kHasShared) {
      // A mesh with a window plan: the contracted Hessian's sweeps, or a gradient's, in windows, while their data
      // are in cache.
      if (!graph_.windowPlan().empty()) {
        if (mode.contracted) return contractedInWindows(x, request, mode, elementEnergy);
        if (wantG && !wantH) return gradientInWindows(x, request, mode, elementEnergy);
      }
    }
    if (!wantG && !wantH) return valueSweep(x, elementEnergy);
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (Shape<I>::kShared) forwardShared<I>(x, mode);
    });
    if (wantG && !wantH) return gradientSweep(x, request, schedule, elementEnergy, mode);
    // Without Shared layers (every node the element's own, as the membrane's) the contracted Hessian is the
    // per-element one: no first sweep to send adjoints.
    if (mode.contracted && kHasShared) {
      sendLocalAdjoints(x, mode);
      forEachLayerBackwards([&](auto layer) {
        constexpr int I = decltype(layer)::value;
        if constexpr (Shape<I>::kShared) gatherAdjoints<I>(x, mode);
      });
    }
    // With an element projector the element projects its own block; the loop then projects nothing.
    const PsdProjection own = projector_ && mode.full ? options.projection : PsdProjection::None;
    const double energy =
        runElementLoop<K>(graph_.elements(), schedule, x, request,
                          own == PsdProjection::None ? options.projection : PsdProjection::None, elementEnergy,
                          [&](int e, const int* ids, bool g_, bool h_, Gradient& g, Hessian& H) {
                            return element(x, e, ids, mode, own, g_, h_, g, H);
                          });
    if (mode.full) releaseProjectedBuffers();
    return energy;
  }

  /// The values of Local layer L at every element of x (no derivatives), serially: store(e, y) with y its M
  /// outputs. The same code as a value-only evaluate() (valueSweep), and the same stages as its derivative
  /// paths: an origin taken this way cancels there, to the bit on a build that does not fuse multiply-adds (on one
  /// that does, -march=native, to about 1e-30 of the energy's scale).
  template <int L, typename Store>
  void localValues(const Eigen::VectorXd& x, Store&& store) {
    static_assert(!Shape<L>::kShared, "localValues reads a Local layer");
    if (!graph_.finalized()) throw std::logic_error("stage graph: finalize() before evaluating");
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (Shape<I>::kShared) sharedValues<I>(x);
    });
    for (int e = 0; e < graph_.numElements(); ++e) {
      LocalValues values;
      elementValues<L>(x, e, values);
      store(e, std::get<L>(values).data());
    }
  }

 private:
  struct Mode {
    DerivativePath path = DerivativePath::AutoDiff;
    int order = 0;                // 0 values, 1 + Jacobians, 2 + Hessians
    bool totals = false;          // total Jacobians (a Hessian's curvature terms read them)
    bool exact = true;            // false: Gauss–Newton (the root's curvature only)
    bool full = false;            // whole element blocks (a projection reads them), not the upper triangle
    bool contracted = false;      // exact, Shared curvature added once per node (no projection)
    bool sharedHessians = false;  // exact per-element Hessian: the Shared stages' Hessians are kept
    bool pullback = false;        // analytic, and Jacobians read only as Jᵀw̄ (pulls)
    bool whole = false;           // a Hessian without projection of a translation-invariant graph (elementWhole)
  };
  /// Whether layer I's adjoints are pulled back through its stage's pullback twin (core/stage.h): when the
  /// stage declares one, on the analytic path, where nothing reads its Jacobian but Jᵀw̄ (a gradient alone; the
  /// contracted Hessian's first-order sweep of the Local layers). Its forward pass then computes values only; a
  /// Shared node's gather reads its inputs again for the pullback, a Local node keeps them (LocalNode::input).
  template <int I>
  static bool pulls(const Mode& mode) {
    return HasPullbackTwin<typename Shape<I>::Stage>::value && mode.pullback;
  }

  // ---- per Shared layer: buffers ----
  template <int I>
  struct SharedBuffers {
    using S = Shape<I>;
    static constexpr int M = S::M, N = S::N, W = S::W;
    std::vector<Eigen::Matrix<double, M, 1>> value;
    std::vector<Eigen::Matrix<double, M, N>> jacobian;
    std::vector<Eigen::Matrix<double, M, 3 * W>> total;
    std::vector<std::array<Eigen::Matrix<double, N, N>, M>> hessian;
    std::vector<Eigen::Matrix<double, M, 1>> adjoint;
    std::vector<Eigen::Matrix<double, N, 1>> inputAdjoint;  // gradient sweep: Jᵀw̄ over the node's inputs
  };
  // ---- per Local layer: one node of one element ----
  template <int I>
  struct LocalNode {
    using S = Shape<I>;
    // User-provided: std::tuple value-initializes its elements, which would zero the whole node (kilobytes of
    // stage Hessians) for every element.
    LocalNode() {}
    StageDerivatives<S::N, S::M> d;
    Eigen::Matrix<double, S::M, Dw> total;  // over the element's working slots
    Eigen::Matrix<double, S::M, 1> adjoint;
    double input[S::N];  // the stage's input z (a pullback's, pulls)
  };
  struct Empty {};
  template <int I>
  using SharedSlot = std::conditional_t<Shape<I>::kShared, SharedBuffers<I>, Empty>;
  template <int I>
  using LocalSlot = std::conditional_t<Shape<I>::kShared, Empty, LocalNode<I>>;
  template <int I>
  using Sent = std::vector<double>;
  template <typename Seq>
  struct Tuples;
  template <int... Is>
  struct Tuples<std::integer_sequence<int, Is...>> {
    using Shared = std::tuple<SharedSlot<Is>...>;
    using Local = std::tuple<LocalSlot<Is>...>;
    using Sent = std::tuple<StageGraphEvaluator::Sent<Is>...>;
  };
  using Seq = std::make_integer_sequence<int, kLayers>;
  template <int... Is>
  static constexpr bool anyShared(std::integer_sequence<int, Is...>) { return (Shape<Is>::kShared || ...); }
  /// Whether any layer is Shared: only then do the sweeps send adjoints across elements (sent_, gatherAdjoints).
  static constexpr bool kHasShared = anyShared(Seq());
  /// The contracted exact Hessian of a translation-invariant graph runs by whole elements (elementWhole): every
  /// total by coordinate over the element's padded working rows, every curvature a product of those, one full
  /// symmetric block.
  static constexpr bool kWhole = kReduced;
  /// Whether layer J reads layer l through one of its groups.
  template <int J, int l>
  static constexpr bool reads() {
    for (int g = 0; g < Shape<J>::G; ++g)
      if (Shape<J>::Groups::layer[static_cast<std::size_t>(g)] == l) return true;
    return false;
  }
  template <int l, int... Js>
  static constexpr bool readForCurvature(std::integer_sequence<int, Js...>) {
    return ((reads<Js, l>() && !IsAffineStage<typename Shape<Js>::Stage>::value) || ...);
  }
  template <int l, int... gs>
  static constexpr bool leavesOnly(std::integer_sequence<int, gs...>) {
    return ((Shape<l>::Groups::layer[gs] < 0) && ...);
  }
  /// A Shared layer of leaves only that no curvature term reads (its readers are affine, as the face normals'
  /// edge means): the whole-element path forms no totals for it; each reader composes the node's Jacobian into
  /// its own group's (M × N products of a few rows) and adds the result as leaf rows, instead of a product over
  /// every working row with a total formed first (elementWhole; BENCHMARKS.md, session 101).
  template <int l>
  static constexpr bool kComposedLeaves =
      Shape<l>::kShared && leavesOnly<l>(std::make_integer_sequence<int, Shape<l>::G>()) && !readForCurvature<l>(Seq());
  using Slots = std::array<std::int8_t, K>;

  /// The state of one element: its Local nodes, and (per-element reverse sweeps) the adjoints of the Shared
  /// nodes it reads, in the order of its lists.
  struct ElementState {
    typename Tuples<Seq>::Local nodes;
    std::array<std::array<double, Graph::kMaxElementNodes * kMaxStageOutputs>, kLayers> sharedAdjoint;
  };

  template <typename F, int... Is>
  static void forEachImpl(F&& f, std::integer_sequence<int, Is...>) {
    (f(std::integral_constant<int, Is>()), ...);
  }
  template <typename F, int... Is>
  static void forEachBackImpl(F&& f, std::integer_sequence<int, Is...>) {
    (f(std::integral_constant<int, kLayers - 1 - Is>()), ...);
  }
  template <typename F>
  static void forEachLayer(F&& f) { forEachImpl(f, Seq()); }
  template <typename F>
  static void forEachLayerBackwards(F&& f) { forEachBackImpl(f, Seq()); }
  template <int I, typename F>
  static void forEachGroup(F&& f) {
    forEachImpl(f, std::make_integer_sequence<int, Shape<I>::G>());
  }

  template <int I>
  SharedBuffers<I>& buffers() { return std::get<I>(shared_); }
  template <int I>
  const InputRef* inputs(int entity) const {
    return graph_.tables(I).inputs.data() + static_cast<std::size_t>(entity) * Shape<I>::G;
  }
  template <int I>
  const std::int8_t* slots(int entity) const {
    return graph_.tables(I).slots.data() + static_cast<std::size_t>(entity) * Shape<I>::kSlots;
  }

  /// The stage input z of node `entity` of layer I: leaves from x, From groups from their nodes' values (a
  /// Local input from the element's state).
  template <int I>
  JETSHELL_INLINE void gather(const Eigen::VectorXd& x, int entity, const ElementState* s, double* z) {
    gatherFrom<I>(x, entity, z, [&](auto layer) -> const auto& {
      return std::get<decltype(layer)::value>(s->nodes).d.value;
    });
  }
  /// gather's body: localValue(integral_constant<int, l>) gives the value of the element's node of Local layer l.
  template <int I, typename LocalValue>
  JETSHELL_INLINE void gatherFrom(const Eigen::VectorXd& x, int entity, double* z, LocalValue&& localValue) {
    const InputRef* in = inputs<I>(entity);
    forEachGroup<I>([&](auto group) {
      constexpr int g = decltype(group)::value;
      constexpr int l = Shape<I>::Groups::layer[g], off = Shape<I>::offset(g);
      const InputRef& r = in[g];
      if constexpr (l < 0) {
        for (int c = 0; c < 3; ++c)
          z[off + c] = Shape<I>::Groups::isDifference[g] ? x[3 * r.b + c] - x[3 * r.a + c] : x[3 * r.a + c];
      } else if constexpr (Shape<I>::Groups::fromShared[g]) {
        const auto& v = buffers<l>().value[static_cast<std::size_t>(r.a)];
        for (int c = 0; c < Shape<l>::M; ++c) z[off + c] = v[c];
      } else {
        const auto& v = localValue(std::integral_constant<int, l>());
        for (int c = 0; c < Shape<l>::M; ++c) z[off + c] = v[c];
      }
    });
  }

  /// The stage's derivatives at z up to `order` (a stage with constant Hessians: up to order 1; its Hessians
  /// are read from constantStageHessians()).
  template <int I>
  static void derivatives(const typename Shape<I>::Stage& stage, const double* z, int entity, int order,
                          DerivativePath path, StageDerivatives<Shape<I>::N, Shape<I>::M>& d) {
    using Stage = typename Shape<I>::Stage;
    evaluateStage(stage, z, entity, HasConstantHessian<Stage>::value ? std::min(order, 1) : order, path, d);
  }

  /// T = Σ_g J_g Z_g over the node's W slots (Shared) or the element's K (Local): a leaf's Z is ±I at its
  /// slots; a From group's is its node's T, the node's support slots mapped by `slot`.
  /// A Local layer's T is over the element's working slots (workSlot); a Shared layer's over its own support.
  template <int I, typename Jac, typename Total>
  JETSHELL_INLINE void addTotals(const Jac& J, const InputRef* in, const std::int8_t* slot, const ElementState* s, Total& T) {
    constexpr bool reduce = kReduced && !Shape<I>::kShared;
    T.setZero();
    forEachGroup<I>([&](auto group) {
      constexpr int g = decltype(group)::value;
      constexpr int l = Shape<I>::Groups::layer[g], off = Shape<I>::offset(g);
      const std::int8_t* gs = slot + Shape<I>::slotOffset(g);
      if constexpr (l < 0) {
        const auto Jg = J.template middleCols<3>(off);
        if constexpr (Shape<I>::Groups::isDifference[g]) {
          const int j = workSlot(gs[1], reduce), i = workSlot(gs[0], reduce);
          if (j >= 0) T.template middleCols<3>(3 * j) += Jg;
          if (i >= 0) T.template middleCols<3>(3 * i) -= Jg;
        } else {
          if (gs[0] >= 0) T.template middleCols<3>(3 * gs[0]) += Jg;
        }
      } else if constexpr (Shape<I>::Groups::fromShared[g]) {
        constexpr int Ml = Shape<l>::M, Wl = Shape<l>::W;
        const auto& Tl = buffers<l>().total[static_cast<std::size_t>(in[g].a)];
        const Eigen::Matrix<double, Shape<I>::M, 3 * Wl> JT = J.template middleCols<Ml>(off).lazyProduct(Tl);
        for (int t = 0; t < Wl; ++t) {
          const int w = workSlot(gs[t], reduce);
          if (w >= 0) T.template middleCols<3>(3 * w) += JT.template middleCols<3>(3 * t);
        }
      } else {
        constexpr int Ml = Shape<l>::M;
        T.noalias() += J.template middleCols<Ml>(off).lazyProduct(std::get<l>(s->nodes).total);
      }
    });
  }

  /// The Shared layers' total Jacobians and stage Hessians, which only a projected Hessian keeps (an unprojected one
  /// forms its totals inside the element, elementWhole), released after it: the solver's factorization, which
  /// follows, then does not find them resident (kilobytes per face; BENCHMARKS.md, session 103).
  void releaseProjectedBuffers() {
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (Shape<I>::kShared) {
        SharedBuffers<I>& b = buffers<I>();
        decltype(b.total)().swap(b.total);
        decltype(b.hessian)().swap(b.hessian);
      }
    });
  }

  // ---- forward over a Shared layer ----
  template <int I>
  bool resizeShared(const Mode& mode) {
    using S = Shape<I>;
    SharedBuffers<I>& b = buffers<I>();
    const auto n = static_cast<std::size_t>(graph_.tables(I).count);
    b.value.resize(n);
    // Zeros, not Eigen's uninitialized coefficients: an affine stage compares the stored Jacobian with the new one
    // before writing it (forwardSharedNode), so the first evaluation must not read indeterminate values.
    if (mode.order >= 1) b.jacobian.resize(n, Eigen::Matrix<double, S::M, S::N>::Zero());
    if (mode.totals) b.total.resize(n);
    const bool hessians = mode.sharedHessians && !HasConstantHessian<typename S::Stage>::value &&
                          !IsAffineStage<typename S::Stage>::value;
    if (hessians) b.hessian.resize(n);
    return hessians;
  }
  template <int I>
  JETSHELL_INLINE void forwardSharedNode(const Eigen::VectorXd& x, const Mode& mode, bool hessians, int i) {
    using S = Shape<I>;
    SharedBuffers<I>& b = buffers<I>();
    double z[S::N];
    gather<I>(x, i, nullptr, z);
    StageDerivatives<S::N, S::M> d;
    const bool pull = pulls<I>(mode);
    derivatives<I>(std::get<I>(graph_.stages()), z, i, pull ? 0 : hessians ? 2 : std::min(mode.order, 1), mode.path, d);
    const auto k = static_cast<std::size_t>(i);
    b.value[k] = d.value;
    if (mode.order < 1 || pull) return;
    if constexpr (IsAffineStage<typename S::Stage>::value) {
      // An affine stage's Jacobian does not depend on x: written only when it changed, its cache lines stay
      // clean (no write-back each evaluation; BENCHMARKS.md, session 92).
      if (b.jacobian[k] != d.jacobian) b.jacobian[k] = d.jacobian;
    } else {
      b.jacobian[k] = d.jacobian;
    }
    if (mode.totals) addTotals<I>(d.jacobian, inputs<I>(i), slots<I>(i), nullptr, b.total[k]);
    if (hessians) b.hessian[k] = d.hessians;
  }
  template <int I>
  void forwardShared(const Eigen::VectorXd& x, const Mode& mode) {
    const bool hessians = resizeShared<I>(mode);
    const int count = graph_.tables(I).count;
    ParallelErrors errors;
#pragma omp parallel for schedule(static) if (count >= kParallelMinElements)
    for (int i = 0; i < count; ++i) errors.run([&] { forwardSharedNode<I>(x, mode, hessians, i); });
    errors.rethrow();
  }

  // ---- the element's Local layers, forward up to layer L ----
  template <int L>
  void forwardLocals(const Eigen::VectorXd& x, int e, const Mode& mode, ElementState& s) {
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (!Shape<I>::kShared && I <= L) {
        LocalNode<I>& node = std::get<I>(s.nodes);
        gather<I>(x, e, &s, node.input);
        // Intermediate stages need Hessians only for an exact Hessian; the root always (its curvature is the
        // Gauss–Newton part). A node pulled back needs its value only.
        int order = pulls<I>(mode) ? 0 : std::min(mode.order, 1);
        if (mode.order == 2 && (mode.exact || I == kRoot)) order = 2;
        derivatives<I>(std::get<I>(graph_.stages()), node.input, e, order, mode.path, node.d);
        if (mode.totals) addTotals<I>(node.d.jacobian, inputs<I>(e), slots<I>(e), &s, node.total);
      }
    });
  }

  /// An element slot's working slot: itself, or (reduced) its reduced coordinate, slot − 1; negative: none
  /// (an absent vertex, or the base slot 0, whose rows follow from the others').
  static constexpr int workSlot(int slot, bool reduced) { return reduced ? (slot >= 1 ? slot - 1 : -1) : slot; }
  /// The element slots of every group of Local node I of element e; `reduced`: the working slots (workSlot; a
  /// Local group's are 0 … Kw−1).
  template <int I, bool reduced>
  JETSHELL_INLINE std::array<Slots, Shape<I>::G> localSlots(int e) const {
    std::array<Slots, Shape<I>::G> out{};
    const std::int8_t* sl = slots<I>(e);
    // Per group at compile time: its width and its place in the slot map are constants.
    forEachGroup<I>([&](auto group) {
      constexpr int g = decltype(group)::value;
      constexpr bool local = Shape<I>::Groups::layer[g] >= 0 && !Shape<I>::Groups::fromShared[g];
      constexpr int w = Shape<I>::Groups::support[g], offset = Shape<I>::slotOffset(g);
      for (int t = 0; t < w; ++t)
        out[g][static_cast<std::size_t>(t)] =
            static_cast<std::int8_t>(reduced && local ? (t < Kw ? t : -1) : workSlot(sl[offset + t], reduced));
    });
    return out;
  }
  /// The element slots of every group of the Shared node at `listed` in layer I's element lists (the graph's
  /// elementGroupSlots); `reduced`: the working slots.
  template <int I, bool reduced>
  JETSHELL_INLINE std::array<Slots, Shape<I>::G> sharedSlots(int listed) const {
    std::array<Slots, Shape<I>::G> out{};
    const std::int8_t* sl =
        graph_.tables(I).elementGroupSlots.data() + static_cast<std::size_t>(listed) * Shape<I>::kSlots;
    forEachGroup<I>([&](auto group) {
      constexpr int g = decltype(group)::value;
      constexpr int w = Shape<I>::Groups::support[g], offset = Shape<I>::slotOffset(g);
      for (int t = 0; t < w; ++t)
        out[g][static_cast<std::size_t>(t)] = static_cast<std::int8_t>(workSlot(sl[offset + t], reduced));
    });
    return out;
  }

  /// Sends a node's input adjoint zbar = Jᵀw (N) to its groups: leaves into the element gradient g at their
  /// element slots (when g is given), Local inputs into their nodes, Shared inputs into the element's copies
  /// (when toShared; `index(g)` gives the input's place in the element's list).
  template <int I, typename Index>
  JETSHELL_INLINE void sendAdjoint(const Eigen::Matrix<double, Shape<I>::N, 1>& zbar, const std::array<Slots, Shape<I>::G>& slot,
                   Index&& index, bool toShared, ElementState& s, Gradient* g) {
    using S = Shape<I>;
    forEachGroup<I>([&](auto group) {
      constexpr int gi = decltype(group)::value;
      constexpr int l = S::Groups::layer[gi], off = S::offset(gi);
      if constexpr (l < 0) {
        if (g == nullptr) return;
        const auto v = zbar.template segment<3>(off);
        if constexpr (S::Groups::isDifference[gi]) {
          if (slot[gi][1] >= 0) g->template segment<3>(3 * slot[gi][1]) += v;
          if (slot[gi][0] >= 0) g->template segment<3>(3 * slot[gi][0]) -= v;
        } else {
          if (slot[gi][0] >= 0) g->template segment<3>(3 * slot[gi][0]) += v;
        }
      } else if constexpr (!S::Groups::fromShared[gi]) {
        std::get<l>(s.nodes).adjoint += zbar.template segment<Shape<l>::M>(off);
      } else {
        if (!toShared) return;
        constexpr int Ml = Shape<l>::M;
        Eigen::Map<Eigen::Matrix<double, Ml, 1>>(s.sharedAdjoint[l].data() + Ml * index(group)) +=
            zbar.template segment<Ml>(off);
      }
    });
  }

  /// C = Σ_k w_k ∇²y_k of Shared node `entity` of layer I (a stage with non-constant Hessians) at x, on the mode's
  /// path (weightedStageHessian, core/stage.h: a composed stage contracts inside the composition, a stage with a
  /// weighted-Hessian twin takes it on the analytic path). False when w is zero (no curvature).
  template <int I>
  JETSHELL_INLINE bool contractShared(const Eigen::VectorXd& x, int entity, const double* w, const Mode& mode,
                      Eigen::Matrix<double, Shape<I>::N, Shape<I>::N>& C) {
    using S = Shape<I>;
    if (Eigen::Map<const Eigen::Matrix<double, S::M, 1>>(w).isZero(0.0)) return false;
    double z[S::N];
    gather<I>(x, entity, nullptr, z);
    weightedStageHessian(std::get<I>(graph_.stages()), z, entity, mode.path, w, C);
    return true;
  }

  /// The curvature of Shared node `entity` of layer I into H, at `listed` in the layer's element lists:
  /// C = Σ_k w_k ∇²y_k given (contracted: by the owner, from the total adjoint), or formed from the adjoint w and the stage
  /// Hessians h (per element: those kept by the forward sweep; null for a stage with constant ones).
  template <int I>
  JETSHELL_INLINE void addSharedCurvature(int entity, const Eigen::Matrix<double, Shape<I>::N, Shape<I>::N>* given, const double* w,
                          const std::array<Eigen::Matrix<double, Shape<I>::N, Shape<I>::N>, Shape<I>::M>* h,
                          int listed, const Mode& mode, WorkHessian& H) {
    using S = Shape<I>;
    if constexpr (IsAffineStage<typename S::Stage>::value) {
      return;
    } else {
      Eigen::Matrix<double, S::N, S::N> C;
      if (given == nullptr) {
        if (!contractCurvature<Shape<I>>(w, h, C)) return;
        given = &C;
      }
      const InputRef* in = inputs<I>(entity);
      const auto total = [&](auto group) -> const auto& {
        constexpr int l = std::max(S::Groups::layer[decltype(group)::value], 0);
        return buffers<l>().total[static_cast<std::size_t>(in[decltype(group)::value].a)];
      };
      if (mode.full) {
        addNodeCurvature<Shape<I>, Kw, true>(*given, sharedSlots<I, kReduced>(listed), total, H);
      } else {
        addNodeCurvature<Shape<I>, Kw, false>(*given, sharedSlots<I, kReduced>(listed), total, H);
      }
    }
  }

  /// The element's reverse sweep: from the root's adjoint 1 through its Local nodes, then (when `shared`) through
  /// the Shared nodes it reads, last layer first. Each node's curvature goes into H (when given; the
  /// Gauss–Newton model stops after the root), leaves' adjoints into g (when given).
  /// With H (a Hessian: no g), slots are the working ones; with g (a gradient alone: no H), the element's own.
  JETSHELL_FLATTEN_SWEEP void reverse(int e, const Mode& mode, bool shared, ElementState& s, Gradient* g, WorkHessian* H,
                                bool keep = false) {
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (!Shape<I>::kShared) std::get<I>(s.nodes).adjoint.setZero();
    });
    if (shared)
      forEachLayer([&](auto layer) {
        constexpr int I = decltype(layer)::value;
        if constexpr (Shape<I>::kShared) {
          const auto& t = graph_.tables(I);
          const int n = t.elementStart[static_cast<std::size_t>(e) + 1] - t.elementStart[static_cast<std::size_t>(e)];
          std::fill_n(s.sharedAdjoint[I].data(), n * Shape<I>::M, 0.0);
        }
      });
    std::get<kRoot>(s.nodes).adjoint[0] = 1.0;
    const bool curvature = H != nullptr;
    forEachLayerBackwards([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      if constexpr (!S::kShared) {
        if (curvature && !mode.exact && I != kRoot && g == nullptr) return;
        LocalNode<I>& node = std::get<I>(s.nodes);
        const std::array<Slots, S::G> slot = curvature ? localSlots<I, kReduced>(e) : localSlots<I, false>(e);
        const InputRef* in = inputs<I>(e);
        const std::int8_t* inputIndex = graph_.tables(I).elementInputs.data() + static_cast<std::size_t>(e) * S::G;
        if (curvature && (mode.exact || I == kRoot)) {
          Eigen::Matrix<double, S::N, S::N> C;
          const auto total = [&](auto group) -> const auto& {
            constexpr int gi = decltype(group)::value;
            constexpr int l = std::max(S::Groups::layer[gi], 0);
            if constexpr (S::Groups::fromShared[gi]) {
              return buffers<l>().total[static_cast<std::size_t>(in[gi].a)];
            } else {
              return std::get<l>(s.nodes).total;
            }
          };
          if (contractCurvature<Shape<I>>(node.adjoint.data(), &node.d.hessians, C)) {
            if (mode.full) {
              addNodeCurvature<Shape<I>, Kw, true>(C, slot, total, *H);
            } else {
              addNodeCurvature<Shape<I>, Kw, false>(C, slot, total, *H);
            }
          }
        }
        if (I == kRoot && curvature && !mode.exact) return;
        Eigen::Matrix<double, S::N, 1> zbar;
        pullLocal<I>(e, mode, node, zbar);
        if (keep) keepSentAdjoint<I>(e, zbar);
        sendAdjoint<I>(zbar, slot,
                       [&](auto group) { return static_cast<int>(inputIndex[decltype(group)::value]); },
                       shared, s, g);
      }
    });
    if (!shared) return;
    forEachLayerBackwards([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      if constexpr (S::kShared) {
        const auto& t = graph_.tables(I);
        forEachListedNode<I>(e, [&](int k, int listed, int entity) {
          const double* w = s.sharedAdjoint[I].data() + S::M * k;
          if (curvature) {
            constexpr bool stored = !HasConstantHessian<typename S::Stage>::value && !IsAffineStage<typename S::Stage>::value;
            addSharedCurvature<I>(entity, nullptr, w, stored ? &buffers<I>().hessian[static_cast<std::size_t>(entity)] : nullptr,
                                  listed, mode, *H);
          }
          const auto& J = buffers<I>().jacobian[static_cast<std::size_t>(entity)];
          const Eigen::Matrix<double, S::N, 1> zbar = J.transpose() * Eigen::Map<const Eigen::Matrix<double, S::M, 1>>(w);
          const std::int8_t* inputIndex = t.elementInputs.data() + static_cast<std::size_t>(listed) * S::G;
          sendAdjoint<I>(zbar, curvature ? sharedSlots<I, kReduced>(listed) : sharedSlots<I, false>(listed),
                         [&](auto group) { return static_cast<int>(inputIndex[decltype(group)::value]); }, true, s, g);
        });
      }
    });
  }

  // ---- one element ----
  /// `own`: the projection the element applies itself through the term's projector (None: the loop's, if any).
  JETSHELL_FLATTEN_SWEEP double element(const Eigen::VectorXd& x, int e, const int* ids, const Mode& mode,
                                        PsdProjection own, bool wantG, bool wantH, Gradient& gradient,
                                        Hessian& hessian) {
    if constexpr (kWhole) {
      if (wantH && mode.whole) return elementWhole(x, e, mode, wantG, gradient, hessian);
    }
    ElementState s;
    forwardLocals<kRoot>(x, e, mode, s);
    LocalNode<kRoot>& root = std::get<kRoot>(s.nodes);
    if (!wantH) return root.d.value[0];  // a gradient alone is gradientSweep's
    if (wantG) expandGradient(root.total, gradient);
    bool projected = own == PsdProjection::None;
    if constexpr (kReduced) {
      // Only the corner accumulates; expandHessian writes the base's row and column whole.
      WorkHessian work = hessian.template bottomRightCorner<Dw, Dw>();
      work.setZero();
      addCurvatures(x, e, mode, s, work);
      if (!projected) projected = projectOwn(x, e, ids, own, work);
      expandHessian(mode.full, hessian);
    } else {
      hessian.setZero();
      addCurvatures(x, e, mode, s, hessian);
      if (!projected) projected = projectOwn(x, e, ids, own, hessian);
    }
    if (!projected) projectPsd<D>(hessian, own);
    return root.d.value[0];
  }

  /// f(k, listed, entity) for each node of Shared layer I that element e reads: k its place in the element's
  /// list, listed its index in the layer's element lists.
  template <int I, typename F>
  JETSHELL_INLINE void forEachListedNode(int e, F&& f) const {
    const auto& t = graph_.tables(I);
    const int begin = t.elementStart[static_cast<std::size_t>(e)], end = t.elementStart[static_cast<std::size_t>(e) + 1];
    for (int listed = begin; listed < end; ++listed)
      f(listed - begin, listed, t.elementNode[static_cast<std::size_t>(listed)]);
  }
  /// The same for the nodes of Shared layer I that element e owns (whose curvature its block takes).
  template <int I, typename F>
  JETSHELL_INLINE void forEachOwnedNode(int e, F&& f) const {
    const auto& t = graph_.tables(I);
    const int begin = t.elementStart[static_cast<std::size_t>(e)];
    for (int o = t.ownedStart[static_cast<std::size_t>(e)]; o < t.ownedStart[static_cast<std::size_t>(e) + 1]; ++o) {
      const int k = t.ownedIndex[static_cast<std::size_t>(o)], listed = begin + k;
      f(k, listed, t.elementNode[static_cast<std::size_t>(listed)]);
    }
  }

  /// zbar = Jᵀw̄ of element e's node of Local layer I: by its stage's pullback twin when pulls<I>(mode), else from
  /// its Jacobian.
  template <int I>
  JETSHELL_INLINE void pullLocal(int e, const Mode& mode, const LocalNode<I>& node,
                                 Eigen::Matrix<double, Shape<I>::N, 1>& zbar) {
    if constexpr (HasPullbackTwin<typename Shape<I>::Stage>::value) {
      if (pulls<I>(mode)) {
        std::get<I>(graph_.stages()).pullback(node.input, node.d.value.data(), e, node.adjoint.data(), zbar.data());
        return;
      }
    }
    zbar.noalias() = node.d.jacobian.transpose() * node.adjoint;
  }
  /// The element's Local adjoints: zero, the root's 1 (the energy's own).
  JETSHELL_INLINE static void seedLocalAdjoints(ElementState& s) {
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (!Shape<I>::kShared) std::get<I>(s.nodes).adjoint.setZero();
    });
    std::get<kRoot>(s.nodes).adjoint[0] = 1.0;
  }
  /// Adds a Local node's input adjoint zbar = Jᵀw to the Local nodes it reads (its Shared inputs' go elsewhere).
  template <int I>
  JETSHELL_INLINE static void sendToLocalInputs(const Eigen::Matrix<double, Shape<I>::N, 1>& zbar, ElementState& s) {
    using S = Shape<I>;
    forEachGroup<I>([&](auto group) {
      constexpr int gi = decltype(group)::value;
      constexpr int l = S::Groups::layer[gi];
      if constexpr (l >= 0 && !S::Groups::fromShared[gi])
        std::get<l>(s.nodes).adjoint += zbar.template segment<Shape<l>::M>(S::offset(gi));
    });
  }

  // ---- the contracted exact Hessian by whole elements ----
  template <int M>
  using RowTotal = Eigen::Matrix<double, Rw, M>;  // a node's total, transposed: one row per working coordinate
  using WholeBlock = Eigen::Matrix<double, Rw, Rw>;
  template <int I>
  using WholeSlot = std::conditional_t<Shape<I>::kShared, std::array<RowTotal<Shape<I>::M>, Graph::kMaxElementNodes>,
                                       RowTotal<Shape<I>::M>>;
  /// User-provided constructor: std::tuple value-initializes its elements, which would zero every layer's totals
  /// (kilobytes) for every element.
  template <int I>
  struct WholeBox {
    WholeBox() {}
    WholeSlot<I> v;
  };
  template <typename Seq_>
  struct WholeTuples;
  template <int... Is>
  struct WholeTuples<std::integer_sequence<int, Is...>> {
    using Type = std::tuple<WholeBox<Is>...>;
  };
  /// Per layer: the totals by coordinate of the element's nodes (Shared: of each node in the element's list).
  using WholeTotals = typename WholeTuples<Seq>::Type;

  /// A From group's input of a kComposedLeaves layer l, whose totals are not formed: its Jacobian and the
  /// working slots of its groups in the element.
  template <int l>
  struct LeafInput {
    const Eigen::Matrix<double, Shape<l>::M, Shape<l>::N>& jacobian;
    std::array<Slots, Shape<l>::G> slot;
  };

  /// The total by coordinate of a node of layer I: T = Σ_g (leaf: ±J_gᵀ in its slots' rows; From: T_g J_gᵀ, or
  /// for an input of a kComposedLeaves layer (J_g J_in)ᵀ in the input's leaf rows). `slot` gives each group's
  /// working slots, `input(group)` a From group's total (a LeafInput for a kComposedLeaves layer).
  template <int I, typename Jac, typename Inputs>
  JETSHELL_INLINE static void wholeTotal(const Jac& J, const std::array<Slots, Shape<I>::G>& slot, Inputs&& input,
                                         RowTotal<Shape<I>::M>& T) {
    using S = Shape<I>;
    T.setZero();
    forEachGroup<I>([&](auto group) {
      constexpr int g = decltype(group)::value;
      constexpr int l = S::Groups::layer[g], off = S::offset(g);
      if constexpr (l < 0) {
        addLeafGroup<Shape<I>, g>(J, slot[g], T);
      } else if constexpr (kComposedLeaves<l>) {
        constexpr int Ml = Shape<l>::M;
        const LeafInput<l> in = input(group);
        const Eigen::Matrix<double, S::M, Shape<l>::N> Jc = J.template middleCols<Ml>(off).lazyProduct(in.jacobian);
        forEachGroup<l>([&](auto inner) {
          constexpr int h = decltype(inner)::value;
          addLeafGroup<Shape<l>, h>(Jc, in.slot[h], T);
        });
      } else {
        constexpr int Ml = Shape<l>::M;
        T.noalias() += input(group).lazyProduct(J.template middleCols<Ml>(off).transpose());
      }
    });
  }

  /// Element e's energy, gradient and contracted exact Hessian (Shared adjoints gathered), or its Gauss–Newton
  /// Hessian (the root's curvature alone: mode.exact false), by whole element: the totals of the Shared nodes it
  /// reads and of its Local nodes by coordinate over the padded working rows, each Local node's curvature (its own
  /// adjoint) and each owned Shared node's (its total adjoint) added as products of those into one full Rw × Rw
  /// block, expanded to the base slot at the end.
  double elementWhole(const Eigen::VectorXd& x, int e, const Mode& mode, bool wantG, Gradient& gradient,
                      Hessian& hessian) {
    Mode local = mode;
    local.totals = false;
    ElementState s;
    forwardLocals<kRoot>(x, e, local, s);
    WholeTotals T;
    // The Shared nodes the element reads, layer by layer, then its Local nodes.
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      if constexpr (S::kShared) {
        if constexpr (!kComposedLeaves<I>) {
          forEachListedNode<I>(e, [&](int k, int listed, int entity) {
            wholeTotal<I>(buffers<I>().jacobian[static_cast<std::size_t>(entity)], sharedSlots<I, true>(listed),
                          [&](auto group) -> decltype(auto) { return sharedInputTotal<I>(T, e, listed, entity, group); },
                          std::get<I>(T).v[static_cast<std::size_t>(k)]);
          });
        }
      } else {
        const std::int8_t* inputIndex = graph_.tables(I).elementInputs.data() + static_cast<std::size_t>(e) * S::G;
        wholeTotal<I>(std::get<I>(s.nodes).d.jacobian, localSlots<I, true>(e),
                      [&](auto group) -> decltype(auto) { return localInputTotal<I>(T, e, inputIndex, group); },
                      std::get<I>(T).v);
      }
    });
    const RowTotal<1>& rootTotal = std::get<kRoot>(T).v;
    if (wantG) expandGradient(rootTotal.template topRows<Dw>().transpose(), gradient);
    WholeBlock H = WholeBlock::Zero();
    // The Local nodes, root first, each with its adjoint in the element.
    seedLocalAdjoints(s);
    forEachLayerBackwards([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      if constexpr (!S::kShared) {
        LocalNode<I>& node = std::get<I>(s.nodes);
        const std::int8_t* inputIndex = graph_.tables(I).elementInputs.data() + static_cast<std::size_t>(e) * S::G;
        Eigen::Matrix<double, S::N, S::N> C;
        // Gauss–Newton: the root's curvature only.
        if ((mode.exact || I == kRoot) && contractCurvature<Shape<I>>(node.adjoint.data(), &node.d.hessians, C))
          addWholeCurvature<Shape<I>>(C, localSlots<I, true>(e),
                               [&](auto group) -> const auto& { return localInputTotal<I>(T, e, inputIndex, group); }, H);
        const Eigen::Matrix<double, S::N, 1> zbar = node.d.jacobian.transpose() * node.adjoint;
        sendToLocalInputs<I>(zbar, s);
      }
    });
    // The Shared nodes the element owns, each with its total adjoint (exact only: Gauss–Newton gathers none).
    if (mode.exact) forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      using Stage = typename S::Stage;
      if constexpr (S::kShared && !IsAffineStage<Stage>::value) {
        forEachOwnedNode<I>(e, [&](int, int listed, int entity) {
          const double* w = buffers<I>().adjoint[static_cast<std::size_t>(entity)].data();
          Eigen::Matrix<double, S::N, S::N> C;
          bool any;
          if constexpr (HasConstantHessian<Stage>::value) {
            any = contractCurvature<Shape<I>>(w, nullptr, C);
          } else {
            any = contractShared<I>(x, entity, w, mode, C);
          }
          if (!any) return;
          addWholeCurvature<Shape<I>>(C, sharedSlots<I, true>(listed),
                               [&](auto group) -> const auto& { return sharedInputTotal<I>(T, e, listed, entity, group); }, H);
        });
      }
    });
    expandWholeUpper<Kw>(H, hessian);
    return std::get<kRoot>(s.nodes).d.value[0];
  }

  /// A From group's total by coordinate for the Shared node `entity` of layer I at `listed` in the layer's element
  /// lists (element e's): its input's, found in the input layer's list (for a kComposedLeaves input layer, the
  /// input's LeafInput).
  template <int I, typename Group>
  JETSHELL_INLINE decltype(auto) sharedInputTotal(const WholeTotals& T, int e, int listed, int entity, Group) const {
    constexpr int g = Group::value;
    constexpr int l = std::max(Shape<I>::Groups::layer[g], 0);
    const std::int8_t* inputIndex = graph_.tables(I).elementInputs.data() + static_cast<std::size_t>(listed) * Shape<I>::G;
    if constexpr (kComposedLeaves<l>) {
      return leafInput<l>(e, inputIndex[g], inputs<I>(entity)[g].a);
    } else {
      return static_cast<const WholeSlot<l>&>(std::get<l>(T).v)[static_cast<std::size_t>(inputIndex[g])];
    }
  }
  /// A From group's total by coordinate for Local node I of element e: a Shared input's from its layer's list, a
  /// Local input's the node's own (for a kComposedLeaves input layer, the input's LeafInput).
  template <int I, typename Group>
  JETSHELL_INLINE decltype(auto) localInputTotal(const WholeTotals& T, int e, const std::int8_t* inputIndex, Group) const {
    constexpr int g = Group::value;
    constexpr int l = std::max(Shape<I>::Groups::layer[g], 0);
    if constexpr (kComposedLeaves<l>) {
      return leafInput<l>(e, inputIndex[g], inputs<I>(e)[g].a);
    } else if constexpr (Shape<l>::kShared) {
      return static_cast<const WholeSlot<l>&>(std::get<l>(T).v)[static_cast<std::size_t>(inputIndex[g])];
    } else {
      return static_cast<const WholeSlot<l>&>(std::get<l>(T).v);
    }
  }
  /// The node `entity` of kComposedLeaves layer l, at place k of element e's list of that layer: its Jacobian
  /// and its groups' working slots.
  template <int l>
  JETSHELL_INLINE LeafInput<l> leafInput(int e, int k, int entity) const {
    const int listed = graph_.tables(l).elementStart[static_cast<std::size_t>(e)] + k;
    return {std::get<l>(shared_).jacobian[static_cast<std::size_t>(entity)], sharedSlots<l, true>(listed)};
  }

  /// The term's projector on the element's working block (whole: a projection makes every block).
  template <typename Block>
  bool projectOwn(const Eigen::VectorXd& x, int e, const int* ids, PsdProjection own, Block& work) const {
    WorkBlock block = work;
    const bool done = projector_(x, e, ids, block, own);
    work = block;
    return done;
  }

  /// The element's curvature terms into `work` (its Hessian over the working slots).
  void addCurvatures(const Eigen::VectorXd& x, int e, const Mode& mode, ElementState& s, WorkHessian& work) {
    // Per-element exact Hessian: the element's own reverse sweep through every node it reads. Contracted or
    // Gauss–Newton: its Local nodes only, then (contracted) the Shared nodes it owns, with their total adjoints.
    reverse(e, mode, mode.sharedHessians, s, nullptr, &work);
    if (mode.contracted) {
      forEachLayer([&](auto layer) {
        constexpr int I = decltype(layer)::value;
        if constexpr (Shape<I>::kShared) {
          forEachOwnedNode<I>(e, [&](int, int listed, int entity) {
            const double* w = buffers<I>().adjoint[static_cast<std::size_t>(entity)].data();
            using Stage = typename Shape<I>::Stage;
            if constexpr (!HasConstantHessian<Stage>::value && !IsAffineStage<Stage>::value) {
              // The node's curvature with its total adjoint, contracted here by its one owner (not kept).
              Eigen::Matrix<double, Shape<I>::N, Shape<I>::N> C;
              if (contractShared<I>(x, entity, w, mode, C)) addSharedCurvature<I>(entity, &C, w, nullptr, listed, mode, work);
            } else {
              addSharedCurvature<I>(entity, nullptr, w, nullptr, listed, mode, work);
            }
          });
        }
      });
    }
  }

  /// The element gradient from the root's total Jacobian over the working slots: slots 1 … K−1 as they are,
  /// slot 0 (reduced) minus their sum (a common translation changes nothing).
  static void expandGradient(const Eigen::Matrix<double, 1, Dw>& total, Gradient& g) {
    if constexpr (kReduced) {
      g.template tail<Dw>() = total.transpose();
      Eigen::Vector3d base = Eigen::Vector3d::Zero();
      for (int k = 0; k < Kw; ++k) base -= total.template middleCols<3>(3 * k).transpose();
      g.template head<3>() = base;
    } else {
      g = total.transpose();
    }
  }
  /// H = Lᵀ H_u L for the reduced Hessian H_u (u_k = x_k − x_0) in H's corner of slots 1 … K−1. H_u holds every
  /// block when `full`, else its upper triangle's, whose transposes fill the lower ones first; the base's row and
  /// column then follow (core/psd_projection.h). The element's block comes out whole and symmetric in its blocks.
  static void expandHessian(bool full, Hessian& H) {
    if (!full)
      for (int c = 1; c < K; ++c)
        for (int r = c + 1; r < K; ++r) H.template block<3, 3>(3 * r, 3 * c) = H.template block<3, 3>(3 * c, 3 * r).transpose();
    completeTranslationInvariant(H);
  }

  // ---- a value alone: the stages called on doubles, inline ----
  /// Each Shared layer's node values over the mesh, then each element's Local stages; no derivative buffer is
  /// touched. The stages are the very calls every other path makes at order 0 (evaluateStage), here inlined into
  /// one body per node or element, so their inputs and outputs stay in registers instead of being stored and
  /// reloaded across calls (BENCHMARKS.md, Elements, "Session 96").
  double valueSweep(const Eigen::VectorXd& x, std::vector<double>& elementEnergy) {
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (Shape<I>::kShared) sharedValues<I>(x);
    });
    const int ne = graph_.numElements();
    elementEnergy.resize(static_cast<std::size_t>(ne));
    ParallelErrors errors;
#pragma omp parallel for schedule(static) if (ne >= kParallelMinElements)
    for (int e = 0; e < ne; ++e) errors.run([&] { elementEnergy[static_cast<std::size_t>(e)] = elementValue(x, e); });
    errors.rethrow();
    double total = 0.0;
    for (double v : elementEnergy) total += v;
    return total;
  }
  template <int I>
  void sharedValues(const Eigen::VectorXd& x) {
    auto& value = buffers<I>().value;
    const int count = graph_.tables(I).count;
    value.resize(static_cast<std::size_t>(count));
    ParallelErrors errors;
#pragma omp parallel for schedule(static) if (count >= kParallelMinElements)
    for (int i = 0; i < count; ++i) errors.run([&] { sharedNodeValue<I>(x, i, value[static_cast<std::size_t>(i)].data()); });
    errors.rethrow();
  }
  template <int I>
  JETSHELL_FLATTEN void sharedNodeValue(const Eigen::VectorXd& x, int i, double* y) {
    double z[Shape<I>::N];
    gather<I>(x, i, nullptr, z);  // a Shared node reads no Local node
    std::get<I>(graph_.stages())(static_cast<const double*>(z), y, i);
  }
  template <typename Seq_>
  struct LocalValueTuple;
  template <int... Is>
  struct LocalValueTuple<std::integer_sequence<int, Is...>> {
    using type = std::tuple<Eigen::Matrix<double, Shape<Is>::M, 1>...>;
  };
  /// An element's Local values, one per layer (a Shared layer's slot unused).
  using LocalValues = typename LocalValueTuple<Seq>::type;
  /// The element's Local layers up to L, on doubles.
  template <int L>
  JETSHELL_FLATTEN void elementValues(const Eigen::VectorXd& x, int e, LocalValues& values) {
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (!Shape<I>::kShared && I <= L) {
        double z[Shape<I>::N];
        gatherFrom<I>(x, e, z, [&](auto l) -> const auto& { return std::get<decltype(l)::value>(values); });
        std::get<I>(graph_.stages())(static_cast<const double*>(z), std::get<I>(values).data(), e);
      }
    });
  }
  JETSHELL_FLATTEN double elementValue(const Eigen::VectorXd& x, int e) {
    LocalValues values;
    elementValues<kRoot>(x, e, values);
    return std::get<kRoot>(values)[0];
  }

  // ---- a gradient alone: one reverse sweep over the whole graph ----
  /// The elements' Local nodes forward and backward (leaf adjoints into the gradient through the coloured loop,
  /// Jᵀw̄ of the Local layers kept per element), then each Shared layer's adjoints once per node, last layer
  /// first, then every vertex's share of the Shared nodes' leaf adjoints.
  double gradientSweep(const Eigen::VectorXd& x, const EvalRequest& request, const ElementSchedule& schedule,
                       std::vector<double>& elementEnergy, const Mode& mode) {
    if constexpr (kHasShared) keepSent(graph_.numElements());
    const double energy = runElementLoop<K>(
        graph_.elements(), schedule, x, request, PsdProjection::None, elementEnergy,
        [&](int e, const int*, bool, bool, Gradient& g, Hessian&) { return elementGradient(x, e, mode, g); });
    if constexpr (!kHasShared) return energy;  // every leaf adjoint went into the element gradients
    forEachLayerBackwards([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (Shape<I>::kShared) gatherAdjoints<I>(x, mode);
    });
    addSharedLeafAdjoints(request);
    return energy;
  }
  /// Element e's energy, and its leaf adjoints into g; what it sends to Shared nodes kept (keepSentAdjoint).
  JETSHELL_INLINE double elementGradient(const Eigen::VectorXd& x, int e, const Mode& mode, Gradient& g) {
    ElementState s;
    forwardLocals<kRoot>(x, e, mode, s);
    g.setZero();
    reverse(e, mode, false, s, &g, nullptr, kHasShared);
    return std::get<kRoot>(s.nodes).d.value[0];
  }
  /// Every vertex's share of the Shared nodes' leaf adjoints (their inputAdjoint), into the gradient.
  void addSharedLeafAdjoints(const EvalRequest& request) {
    const auto& start = graph_.vertexReaderStart();
    const auto& readers = graph_.vertexReaders();
    double* G = request.gradient->data();
    const int nv = graph_.numVertices();
#pragma omp parallel for schedule(static) if (nv >= kParallelMinElements)
    for (int v = 0; v < nv; ++v) {
      double gv[3] = {0.0, 0.0, 0.0};
      for (int r = start[static_cast<std::size_t>(v)]; r < start[static_cast<std::size_t>(v) + 1]; ++r) {
        // Named fields, not a structured binding: a lambda may not capture one before C++20 (g++ allows it,
        // clang rejects it).
        const std::array<int, 4>& reader = readers[static_cast<std::size_t>(r)];
        const int layer = reader[0], entity = reader[1], group = reader[2], sign = reader[3];
        forEachLayer([&](auto l) {
          constexpr int I = decltype(l)::value;
          if constexpr (Shape<I>::kShared) {
            if (layer != I) return;
            const double* a = buffers<I>().inputAdjoint[static_cast<std::size_t>(entity)].data() + Shape<I>::offset(group);
            for (int c = 0; c < 3; ++c) gv[c] += sign * a[c];
          }
        });
      }
      for (int c = 0; c < 3; ++c) G[3 * v + c] += gv[c];
    }
  }

  /// Sizes the per-element Jᵀw̄ of each Local layer (sent_).
  void keepSent(int ne) {
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (!Shape<I>::kShared) std::get<I>(sent_).resize(static_cast<std::size_t>(ne) * Shape<I>::kSent);
    });
  }
  /// Keeps the part of Local node I's input adjoint zbar at element e that the Shared layers gather (its
  /// From-Shared groups', Shape::sentOffset).
  template <int I>
  JETSHELL_INLINE void keepSentAdjoint(int e, const Eigen::Matrix<double, Shape<I>::N, 1>& zbar) {
    using S = Shape<I>;
    if constexpr (S::kSent > 0) {
      double* out = std::get<I>(sent_).data() + static_cast<std::size_t>(e) * S::kSent;
      forEachGroup<I>([&](auto group) {
        constexpr int g = decltype(group)::value;
        if constexpr (S::Groups::fromShared[g])
          for (int c = 0; c < S::Groups::size[g]; ++c) out[S::sentOffset(g) + c] = zbar[S::offset(g) + c];
      });
    }
  }

  // ---- contracted mode: the adjoints of the Shared nodes ----
  /// Per element: the Local nodes' adjoints (values and Jacobians only), and for each Local layer, Jᵀw over its
  /// From-Shared groups, kept per element for gatherAdjoints.
  void sendLocalAdjoints(const Eigen::VectorXd& x, const Mode& mode) {
    const int ne = graph_.numElements();
    keepSent(ne);
    Mode first = firstOrder(mode);
    ParallelErrors errors;
#pragma omp parallel for schedule(static) if (ne >= kParallelMinElements)
    for (int e = 0; e < ne; ++e) errors.run([&] { sendLocalAdjoint(x, first, e); });
    errors.rethrow();
  }
  static Mode firstOrder(Mode mode) {
    mode.order = 1;
    mode.totals = false;
    mode.pullback = mode.path == DerivativePath::Analytic;  // the Local Jacobians are read only as Jᵀw̄
    return mode;
  }
  /// Element e's share of sendLocalAdjoints (`first`: firstOrder(mode)).
  JETSHELL_INLINE void sendLocalAdjoint(const Eigen::VectorXd& x, const Mode& first, int e) {
    ElementState s;
    forwardLocals<kRoot>(x, e, first, s);
    seedLocalAdjoints(s);
    forEachLayerBackwards([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      using S = Shape<I>;
      if constexpr (!S::kShared) {
        LocalNode<I>& node = std::get<I>(s.nodes);
        Eigen::Matrix<double, S::N, 1> zbar;
        pullLocal<I>(e, first, node, zbar);
        keepSentAdjoint<I>(e, zbar);
        sendToLocalInputs<I>(zbar, s);
      }
    });
  }

  /// Each node of Shared layer I: its adjoint, summed over its readers (later Shared layers, whose adjoints
  /// are complete, and the elements' Local nodes).
  template <int I>
  void gatherAdjoints(const Eigen::VectorXd& x, const Mode& mode) {
    const auto& t = graph_.tables(I);
    const bool inputs = resizeAdjoints<I>(mode);
#pragma omp parallel for schedule(static) if (t.count >= kParallelMinElements)
    for (int n = 0; n < t.count; ++n) gatherNode<I>(x, mode, inputs, n);
  }
  template <int I>
  bool resizeAdjoints(const Mode& mode) {
    SharedBuffers<I>& b = buffers<I>();
    const auto n = static_cast<std::size_t>(graph_.tables(I).count);
    b.adjoint.resize(n);
    const bool inputs = !mode.contracted;  // the gradient sweep: Jᵀw̄ for the vertices' gather
    if (inputs) b.inputAdjoint.resize(n);
    return inputs;
  }
  /// `inputs`: also its input adjoint Jᵀw (a gradient's), by the stage's pullback twin when pulls<I>(mode).
  template <int I>
  JETSHELL_INLINE void gatherNode(const Eigen::VectorXd& x, const Mode& mode, bool inputs, int n) {
    using S = Shape<I>;
    SharedBuffers<I>& b = buffers<I>();
    const auto& t = graph_.tables(I);
    Eigen::Matrix<double, S::M, 1> w = Eigen::Matrix<double, S::M, 1>::Zero();
    // Readers come sorted by layer: each layer's run is summed with that layer's sizes known at compile time.
    int r = t.readerStart[static_cast<std::size_t>(n)];
    const int end = t.readerStart[static_cast<std::size_t>(n) + 1];
    forEachLayer([&](auto layer) {
      constexpr int J = decltype(layer)::value;
      if constexpr (J > I) {
        for (; r < end && t.readers[static_cast<std::size_t>(r)][0] == J; ++r) {
          const auto& reader = t.readers[static_cast<std::size_t>(r)];
          const int off = Shape<J>::offset(reader[2]);
          const auto k = static_cast<std::size_t>(reader[1]);
          if constexpr (Shape<J>::kShared) {
            // A gradient's reader already holds Jᵀw̄ (its input adjoint, gathered before this node): its rows
            // for this group, instead of the product again.
            const auto& bj = buffers<J>();
            if (inputs) {
              w += bj.inputAdjoint[k].template segment<S::M>(off);
            } else {
              w.noalias() += bj.jacobian[k].transpose().template middleRows<S::M>(off) * bj.adjoint[k];
            }
          } else {
            const double* sent = std::get<J>(sent_).data() + k * Shape<J>::kSent + Shape<J>::sentOffset(reader[2]);
            for (int c = 0; c < S::M; ++c) w[c] += sent[c];
          }
        }
      }
    });
    const auto k = static_cast<std::size_t>(n);
    b.adjoint[k] = w;
    if (!inputs) return;
    if constexpr (HasPullbackTwin<typename S::Stage>::value) {
      if (pulls<I>(mode)) {
        double z[S::N];
        gather<I>(x, n, nullptr, z);
        std::get<I>(graph_.stages()).pullback(z, b.value[k].data(), n, w.data(), b.inputAdjoint[k].data());
        return;
      }
    }
    b.inputAdjoint[k].noalias() = b.jacobian[k].transpose() * w;
  }

  // ---- the sweeps in windows (core/stage_window_plan.h) ----
  /// The window plan's schedule, shared by the contracted Hessian and a gradient alone: the cross nodes forward;
  /// the lanes, the first phase's then the second's (lanes of one phase write no common entry), each window by
  /// window (its nodes forward, its elements' adjoint sweeps, its nodes gathered, the elements now complete
  /// finished); the cross nodes gathered; the deferred elements colour by colour (blocks of one colour share no
  /// vertex).
  /// forward(layer, n) and gather(layer, n) take a node of a Shared layer (layer: std::integral_constant), sweep(e)
  /// and finish(e) an element.
  template <typename Forward, typename Sweep, typename Gather, typename Finish>
  void inWindows(bool parallel, Forward&& forward, Sweep&& sweep, Gather&& gather, Finish&& finish) {
    const StageWindowPlan& plan = graph_.windowPlan();
    ParallelErrors errors;
    const auto eachNode = [&](const std::vector<int>& nodes, auto&& f) {
      const int n = static_cast<int>(nodes.size());
#pragma omp parallel for schedule(static) if (parallel && n >= kParallelMinElements)
      for (int i = 0; i < n; ++i) errors.run([&] { f(nodes[static_cast<std::size_t>(i)]); });
      errors.rethrow();
    };
    forEachLayer([&](auto layer) {
      if constexpr (Shape<decltype(layer)::value>::kShared)
        eachNode(plan.cross[decltype(layer)::value], [&](int n) { forward(layer, n); });
    });
    for (const std::vector<int>& phaseLanes : plan.phaseLanes) {
      const int count = static_cast<int>(phaseLanes.size());
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
      for (int i = 0; i < count; ++i)
        errors.run([&] {
          runLane(plan, plan.lanes[static_cast<std::size_t>(phaseLanes[static_cast<std::size_t>(i)])], forward, sweep,
                  gather, finish);
        });
      errors.rethrow();
    }
    forEachLayerBackwards([&](auto layer) {
      if constexpr (Shape<decltype(layer)::value>::kShared)
        eachNode(plan.cross[decltype(layer)::value], [&](int n) { gather(layer, n); });
    });
#pragma omp parallel if (parallel)
    for (const std::vector<ElementRange>& color : plan.deferredSchedule.colors) {
      const int n = static_cast<int>(color.size());
#pragma omp for schedule(dynamic, 1)
      for (int i = 0; i < n; ++i)
        errors.run([&] {
          for (int p = color[static_cast<std::size_t>(i)].begin; p < color[static_cast<std::size_t>(i)].end; ++p)
            finish(plan.deferred[static_cast<std::size_t>(p)]);
        });
    }
    errors.rethrow();
  }
  /// One lane of the window plan (inWindows).
  template <typename Forward, typename Sweep, typename Gather, typename Finish>
  void runLane(const StageWindowPlan& plan, const StageWindowPlan::Lane& lane, Forward& forward, Sweep& sweep,
               Gather& gather, Finish& finish) {
    const int window = plan.window;
    const int windows = static_cast<int>(lane.readyStart.size()) - 1;
    for (int w = 0; w < windows; ++w) {
      const auto ww = static_cast<std::size_t>(w);
      forEachLayer([&](auto layer) {
        constexpr int I = decltype(layer)::value;
        if constexpr (Shape<I>::kShared)
          for (int k = lane.forwardStart[I][ww]; k < lane.forwardStart[I][ww + 1]; ++k)
            forward(layer, lane.forward[I][static_cast<std::size_t>(k)]);
      });
      const int end = std::min(lane.end, lane.begin + (w + 1) * window);
      for (int p = lane.begin + w * window; p < end; ++p) sweep(plan.order[static_cast<std::size_t>(p)]);
      forEachLayerBackwards([&](auto layer) {
        constexpr int I = decltype(layer)::value;
        if constexpr (Shape<I>::kShared)
          for (int k = lane.gatherStart[I][ww]; k < lane.gatherStart[I][ww + 1]; ++k)
            gather(layer, lane.gather[I][static_cast<std::size_t>(k)]);
      });
      for (int k = lane.readyStart[ww]; k < lane.readyStart[ww + 1]; ++k) finish(lane.ready[static_cast<std::size_t>(k)]);
    }
  }
  /// The Shared buffers a windowed evaluation writes, sized; a node no element reads gets a zero adjoint and
  /// Jacobian (and input adjoint, when kept): it sends J_nᵀ 0 to its inputs. Returns per layer whether its stage
  /// Hessians are kept.
  std::array<bool, kLayers> prepareWindows(const Mode& mode) {
    const StageWindowPlan& plan = graph_.windowPlan();
    std::array<bool, kLayers> hessians{};
    forEachLayer([&](auto layer) {
      constexpr int I = decltype(layer)::value;
      if constexpr (Shape<I>::kShared) {
        hessians[I] = resizeShared<I>(mode);
        const bool inputs = resizeAdjoints<I>(mode);
        SharedBuffers<I>& b = buffers<I>();
        for (int n : plan.unread[I]) {
          b.adjoint[static_cast<std::size_t>(n)].setZero();
          b.jacobian[static_cast<std::size_t>(n)].setZero();
          if (inputs) b.inputAdjoint[static_cast<std::size_t>(n)].setZero();
        }
      }
    });
    keepSent(graph_.numElements());
    return hessians;
  }

  /// The contracted exact Hessian in windows: forward with the stages' Hessians where kept, each element's
  /// first-order adjoint sweep, the nodes' adjoints, each element's curvature and block assembled.
  double contractedInWindows(const Eigen::VectorXd& x, const EvalRequest& request, const Mode& mode,
                             std::vector<double>& elementEnergy) {
    const int ne = graph_.numElements();
    const std::array<bool, kLayers> hessians = prepareWindows(mode);
    elementEnergy.resize(static_cast<std::size_t>(ne));
    const Mode first = firstOrder(mode);
    inWindows(
        ne >= kParallelMinElements,
        [&](auto layer, int n) JETSHELL_LAMBDA_INLINE { forwardSharedNode<decltype(layer)::value>(x, mode, hessians[decltype(layer)::value], n); },
        [&](int e) JETSHELL_LAMBDA_INLINE { sendLocalAdjoint(x, first, e); },
        [&](auto layer, int n) JETSHELL_LAMBDA_INLINE { gatherNode<decltype(layer)::value>(x, mode, false, n); },
        [&](int e) JETSHELL_LAMBDA_INLINE { assemble(x, request, mode, e, elementEnergy); });
    double total = 0.0;
    for (double v : elementEnergy) total += v;
    return total;
  }

  /// A gradient alone in windows: the gradient sweep's passes in the plan's order (forward with Jacobians, each
  /// element's reverse sweep with its leaf adjoints kept until the plan finishes it, when no other lane of its
  /// phase writes its vertices; each node's adjoint and Jᵀw̄ gathered), then every vertex's share of the Shared
  /// nodes' input adjoints. Each gradient entry receives its terms in an order fixed by the mesh: the same bits
  /// for any thread count.
  double gradientInWindows(const Eigen::VectorXd& x, const EvalRequest& request, const Mode& mode,
                           std::vector<double>& elementEnergy) {
    const int ne = graph_.numElements();
    prepareWindows(mode);
    elementGradient_.resize(static_cast<std::size_t>(ne) * D);
    elementEnergy.resize(static_cast<std::size_t>(ne));
    inWindows(
        ne >= kParallelMinElements,
        [&](auto layer, int n) JETSHELL_LAMBDA_INLINE { forwardSharedNode<decltype(layer)::value>(x, mode, false, n); },
        [&](int e) JETSHELL_LAMBDA_INLINE {
          Gradient g;
          elementEnergy[static_cast<std::size_t>(e)] = elementGradient(x, e, mode, g);
          Eigen::Map<Gradient>(elementGradient_.data() + static_cast<std::size_t>(e) * D) = g;
        },
        [&](auto layer, int n) JETSHELL_LAMBDA_INLINE { gatherNode<decltype(layer)::value>(x, mode, true, n); },
        [&](int e) JETSHELL_LAMBDA_INLINE {
          addElementResult<K>(request, e, graph_.elements().element(e),
                              elementGradient_.data() + static_cast<std::size_t>(e) * D, nullptr);
        });
    addSharedLeafAdjoints(request);
    double total = 0.0;
    for (double v : elementEnergy) total += v;
    return total;
  }

  /// Element e's energy, curvature and gradient, added into the request (what the element loop does for it).
  void assemble(const Eigen::VectorXd& x, const EvalRequest& request, const Mode& mode, int e,
                std::vector<double>& elementEnergy) {
    Gradient g;
    Hessian H;
    const int* ids = graph_.elements().element(e);
    const bool wantG = request.gradient != nullptr;
    elementEnergy[static_cast<std::size_t>(e)] = element(x, e, ids, mode, PsdProjection::None, wantG, true, g, H);
    addElementResult<K>(request, e, ids, g.data(), H.data());
  }

  Graph& graph_;
  ElementProjector projector_;  // optional (setElementProjector)
  typename Tuples<Seq>::Shared shared_;
  typename Tuples<Seq>::Sent sent_;  // per Local layer: per element, Jᵀw over its From-Shared groups (keepSentAdjoint)
  std::vector<double> elementGradient_;  // gradientInWindows: per element, its leaf adjoints (D) until assembled
};

}  // namespace jetshell
