// An energy term built from stages (core/stage.h): the user writes small templated stage functions and, per
// stencil, how they connect; the framework evaluates every stage with Jets (or its checked analytic twin),
// shares per-entity results through StageCaches and chains them (core/stage_chain.h). No derivative is
// written by hand.
//
// The definition:
//   struct MyStagedEnergy {
//     static constexpr int kVertices = K;                      // stencil width
//     StageCache<FaceNormal> normals;                          // results shared between stencils, if any
//     void operator()(StageChain<K>& chain, int element);     // builds the element's chain, ends with
//   };                                                         // chain.energy(...)
// Input:  positions x (3N), the stencil table (K ids per element; -1 = absent, read as 0), the request.
// Output: energy; gradient and Hessian blocks added as requested, through the parallel coloured element loop
//         (core/element_loop.h), which also makes the caches race-free. One chain per thread, allocated once;
//         the element loop does not allocate.
// EvalOptions::bendingHessian == GaussNewton keeps only the energy stage's curvature: H = J_sᵀ W'' J_s.
// EvalOptions::path picks the stages' analytic twins where they exist (AutoDiff: Jets everywhere).
#pragma once

#include "core/element_loop.h"
#include "core/fixed_stencil_term.h"
#include "core/stage_chain.h"
#include "core/term.h"

#include <omp.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace jetshell {

/// The stencil's coordinates xe (3K) from x; absent vertices (id −1) read as 0.
template <int K>
void gatherStencil(const int* ids, const Eigen::VectorXd& x, double* xe) {
  for (int k = 0; k < K; ++k)
    for (int c = 0; c < 3; ++c) xe[3 * k + c] = ids[k] >= 0 ? x[3 * ids[k] + c] : 0.0;
}

/// The evaluation machinery of a staged term, for terms that keep their own class (the shell terms): one chain
/// per thread and the evaluation epoch. evaluate() runs build(chain, element) for every element through the
/// coloured element loop; build connects the element's stages and ends with chain.energy(...).
template <int K>
class StagedElements {
 public:
  static constexpr int M = 3 * K;

  /// The context of an evaluation for `request` and `options` (a new epoch each call).
  StageContext newContext(const EvalRequest& request, const EvalOptions& options) {
    const bool wantG = request.gradient != nullptr, wantH = request.hessian != nullptr;
    StageContext context;
    context.epoch = ++epoch_;
    context.path = options.path;
    context.energyOrder = wantH ? 2 : wantG ? 1 : 0;
    context.order = wantH && options.bendingHessian == BendingHessian::GaussNewton ? 1 : context.energyOrder;
    return context;
  }

  /// A chain for the calling thread (created on first use; the element loop never allocates).
  StageChain<K>& chain() { return *chains_[static_cast<std::size_t>(omp_get_thread_num())]; }

  template <typename Build>
  double evaluate(const StencilTable& table, const ElementSchedule& schedule, const Eigen::VectorXd& x,
                  const EvalRequest& request, const EvalOptions& options, std::vector<double>& elementEnergy,
                  Build&& build) {
    const StageContext context = newContext(request, options);
    reserveChains();
    return runElementLoop<K>(
        table, schedule, x, request, options.projection, elementEnergy,
        [&](int e, const int* ids, bool g_, bool h_, Eigen::Matrix<double, M, 1>& g, Eigen::Matrix<double, M, M>& H) {
          double xe[M];
          gatherStencil<K>(ids, x, xe);
          StageChain<K>& c = chain();
          c.begin(xe, context);
          build(c, e);
          return c.finish(g_, h_, g, H);
        },
        /*colouredValues=*/true);
  }

  /// The value of one node at every element of x, serially and without derivatives, from the very stages
  /// evaluate() runs (so an origin taken this way cancels to the bit there): node(chain, e) connects element e's
  /// stages and returns the node; store(e, chain, node) reads its outputs with chain.value(node, k).
  template <typename Node, typename Store>
  void nodeValues(const StencilTable& table, const Eigen::VectorXd& x, Node&& node, Store&& store) {
    const StageContext context = newContext(EvalRequest{}, EvalOptions{});
    reserveChains();
    StageChain<K>& c = chain();
    for (int e = 0; e < table.size(); ++e) {
      double xe[M];
      gatherStencil<K>(table.element(e), x, xe);
      c.begin(xe, context);
      store(e, c, node(c, e));
    }
  }

  /// Makes sure every thread of the next parallel region has its chain.
  void reserveChains() {
    const int threads = omp_get_max_threads();
    while (static_cast<int>(chains_.size()) < threads) chains_.push_back(std::make_unique<StageChain<K>>());
  }

 private:
  std::uint64_t epoch_ = 0;
  std::vector<std::unique_ptr<StageChain<K>>> chains_;  // one per thread, reused
};

template <typename Definition>
class StagedEnergyTerm : public FixedStencilTerm {
 public:
  static constexpr int K = Definition::kVertices;
  static constexpr int M = 3 * K;

  StagedEnergyTerm(std::string name, StencilTable stencils, int numVertices, Definition definition,
                   bool zeroAtRest = true, bool rigidInvariant = true)
      : FixedStencilTerm(std::move(name), std::move(stencils), numVertices, zeroAtRest, rigidInvariant),
        definition_(std::move(definition)) {}

  Definition& definition() { return definition_; }
  const Definition& definition() const { return definition_; }

  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override {
    return elements_.evaluate(table_, schedule_, x, request, options, elementEnergy_,
                              [&](StageChain<K>& chain, int e) { definition_(chain, e); });
  }

 private:
  Definition definition_;
  StagedElements<K> elements_;
};

}  // namespace jetshell
