// Stage results shared by several stencils: one entry per entity (vertex, edge or face), computed once per
// evaluation and reused by every stencil that asks for it (a face normal serves every stencil around the face).
//
// Input:  the stage (core/stage.h), the number of entities, and at each request the entity, its input z and the
//         evaluation's StageContext (epoch, derivative order, path).
// Output: a StageView of the entity's results (core/stage.h), valid until the next evaluation.
// An entry is computed on its first request of an evaluation (its stamp differs from the context's epoch) and
// returned as stored afterwards; a later request must give the same input z (checked: a cached stage's inputs
// are the entity's, in the entity's own order, e.g. a face's edge vectors from its first vertex), otherwise
// std::logic_error. Race-free without locks under the element loop's colouring
// (core/element_loop.h): an entity's vertices belong to every stencil that uses it, so two stencils sharing an
// entity share a vertex and never run at the same time. Storage is sized once; requests never allocate.
#pragma once

#include "core/stage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace jetshell {

/// What one evaluation asks of its stages.
struct StageContext {
  std::uint64_t epoch = 0;  // changes every evaluation: cached entries of older epochs are stale
  int order = 0;            // intermediate stages: 0 value, 1 + Jacobian, 2 + Hessians
  int energyOrder = 0;      // the energy stage (the chain's root): 2 whenever a Hessian is asked (Gauss–Newton too)
  DerivativePath path = DerivativePath::AutoDiff;
};

/// The view of one stage result d evaluated at `order` (core/stage.h): Hessians only at order 2, a stage with
/// constant Hessians (kConstantHessian) pointing at them (none when they are all zero).
template <typename S>
StageView stageView(const Eigen::Matrix<double, S::kOutputs, 1>& value,
                    const Eigen::Matrix<double, S::kOutputs, S::kInputs>& jacobian,
                    const std::array<Eigen::Matrix<double, S::kInputs, S::kInputs>, S::kOutputs>* hessians, int order) {
  StageView v;
  v.value = value.data();
  v.jacobian = jacobian.data();
  if (order < 2) return v;
  if constexpr (HasConstantHessian<S>::value) {
    const ConstantStageHessians<S>& c = constantStageHessians<S>();
    if (c.zero) return v;
    hessians = &c.hessians;
  }
  for (int k = 0; k < S::kOutputs; ++k) v.hessian[k] = (*hessians)[k].data();
  return v;
}

/// Evaluates stage s at z up to `order` into d and returns its view; a stage with constant Hessians is
/// evaluated at order 1 only (its view points at the constant Hessians).
template <typename S>
StageView evaluateStageView(const S& s, const double* z, int entity, int order, DerivativePath path,
                            StageDerivativesOf<S>& d) {
  const int own = HasConstantHessian<S>::value ? std::min(order, 1) : order;
  evaluateStage(s, z, entity, own, path, d);
  return stageView<S>(d.value, d.jacobian, &d.hessians, order);
}

template <typename S>
class StageCache {
 public:
  static constexpr int N = S::kInputs, M = S::kOutputs;
  explicit StageCache(S stage = S(), int numEntities = 0) : stage_(std::move(stage)) { resize(numEntities); }
  void resize(int numEntities) {
    const auto n = static_cast<std::size_t>(numEntities);
    first_.resize(n);
    if (!HasConstantHessian<S>::value) hessians_.resize(n);
    stamps_.assign(n, 0);
    inputs_.assign(n * N, 0.0);
  }
  int size() const { return static_cast<int>(first_.size()); }
  const S& stage() const { return stage_; }
  S& stage() { return stage_; }

  /// The stage's results for `entity` at input z in the evaluation `context`, computed on first request at
  /// context.order.
  StageView get(int entity, const double* z, const StageContext& context) {
    const auto i = static_cast<std::size_t>(entity);
    First& r = first_[i];
    std::uint64_t& stamp = stamps_[i];
    double* in = inputs_.data() + i * N;
    if (stamp != context.epoch) {
      StageDerivativesOf<S> d;
      const int own = HasConstantHessian<S>::value ? std::min(context.order, 1) : context.order;
      evaluateStage(stage_, z, entity, own, context.path, d);
      r.value = d.value;
      if (own >= 1) r.jacobian = d.jacobian;
      if (own >= 2) hessians_[i] = d.hessians;
      for (int k = 0; k < N; ++k) in[k] = z[k];
      stamp = context.epoch;
    } else {
      for (int k = 0; k < N; ++k)
        if (!(in[k] == z[k]) && !(std::isnan(in[k]) && std::isnan(z[k])))
          throw std::logic_error("stage cache: entity " + std::to_string(entity) +
                                 " requested with other inputs than its first request (inputs must be the entity's own)");
    }
    return stageView<S>(r.value, r.jacobian, hessians_.empty() ? nullptr : &hessians_[i], context.order);
  }

 private:
  // Values and Jacobians together, Hessians apart (touched by the exact Hessian only; none for a stage with
  // constant Hessians): a pass reads only what it needs.
  struct First {
    Eigen::Matrix<double, M, 1> value;
    Eigen::Matrix<double, M, N> jacobian;
  };
  S stage_;
  std::vector<First> first_;
  std::vector<std::array<Eigen::Matrix<double, N, N>, M>> hessians_;
  std::vector<double> inputs_;          // the input z of each entry
  std::vector<std::uint64_t> stamps_;  // epoch of each entry (0: never computed; epochs start at 1)
};

}  // namespace jetshell
