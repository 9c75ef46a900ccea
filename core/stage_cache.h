// Stage results shared by several stencils: one entry per entity (vertex, edge or face), computed once per
// evaluation and reused by every stencil that asks for it (a face normal serves every stencil around the face).
//
// Input:  the stage (core/stage.h), the number of entities, and at each request the entity, its input z and the
//         evaluation's StageContext (epoch, derivative order, path).
// Output: the entity's StageDerivatives (core/stage.h), valid until the next evaluation.
// An entry is computed on its first request of an evaluation (its stamp differs from the context's epoch) and
// returned as stored afterwards; a later request must give the same input z (checked: a cached stage's inputs
// are the entity's, in the entity's own order, e.g. a face's edge vectors from its first vertex), otherwise
// std::logic_error. Race-free without locks under the element loop's colouring
// (core/element_loop.h): an entity's vertices belong to every stencil that uses it, so two stencils sharing an
// entity share a vertex and never run at the same time. Storage is sized once; requests never allocate.
#pragma once

#include "core/stage.h"

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

template <typename S>
class StageCache {
 public:
  explicit StageCache(S stage = S(), int numEntities = 0) : stage_(std::move(stage)) { resize(numEntities); }
  void resize(int numEntities) {
    results_.resize(static_cast<std::size_t>(numEntities));
    stamps_.assign(static_cast<std::size_t>(numEntities), 0);
    inputs_.assign(static_cast<std::size_t>(numEntities) * S::kInputs, 0.0);
  }
  int size() const { return static_cast<int>(results_.size()); }
  const S& stage() const { return stage_; }
  S& stage() { return stage_; }

  /// The stage's derivatives for `entity` at input z in the evaluation `context` (computed on first request).
  const StageDerivativesOf<S>& get(int entity, const double* z, const StageContext& context) {
    StageDerivativesOf<S>& r = results_[static_cast<std::size_t>(entity)];
    std::uint64_t& stamp = stamps_[static_cast<std::size_t>(entity)];
    double* in = inputs_.data() + static_cast<std::size_t>(entity) * S::kInputs;
    if (stamp != context.epoch) {
      evaluateStage(stage_, z, entity, context.order, context.path, r);
      for (int i = 0; i < S::kInputs; ++i) in[i] = z[i];
      stamp = context.epoch;
    } else {
      for (int i = 0; i < S::kInputs; ++i)
        if (!(in[i] == z[i]) && !(std::isnan(in[i]) && std::isnan(z[i])))
          throw std::logic_error("stage cache: entity " + std::to_string(entity) +
                                 " requested with other inputs than its first request (inputs must be the entity's own)");
    }
    return r;
  }

 private:
  S stage_;
  std::vector<StageDerivativesOf<S>> results_;
  std::vector<double> inputs_;          // the input z of each entry
  std::vector<std::uint64_t> stamps_;  // epoch of each entry (0: never computed; epochs start at 1)
};

}  // namespace jetshell
