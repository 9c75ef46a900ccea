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
    const bool wantG = request.gradient != nullptr, wantH = request.hessian != nullptr;
    StageContext context;
    context.epoch = ++epoch_;
    context.path = options.path;
    context.energyOrder = wantH ? 2 : wantG ? 1 : 0;
    context.order = wantH && options.bendingHessian == BendingHessian::GaussNewton ? 1 : context.energyOrder;
    const int threads = omp_get_max_threads();
    while (static_cast<int>(chains_.size()) < threads) chains_.push_back(std::make_unique<StageChain<K>>());
    return runElementLoop<K>(
        table_, schedule_, x, request, options.projection, elementEnergy_,
        [&](int e, const int* ids, bool g_, bool h_, Eigen::Matrix<double, M, 1>& g, Eigen::Matrix<double, M, M>& H) {
          double xe[M];
          for (int k = 0; k < K; ++k)
            for (int c = 0; c < 3; ++c) xe[3 * k + c] = ids[k] >= 0 ? x[3 * ids[k] + c] : 0.0;
          StageChain<K>& chain = *chains_[static_cast<std::size_t>(omp_get_thread_num())];
          chain.begin(xe, context);
          definition_(chain, e);
          return chain.finish(g_, h_, g, H);
        },
        /*colouredValues=*/true);
  }

 private:
  Definition definition_;
  std::uint64_t epoch_ = 0;
  std::vector<std::unique_ptr<StageChain<K>>> chains_;  // one per thread, reused
};

}  // namespace jetshell
