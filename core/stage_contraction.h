// The curvature of one stage-graph node, C = Σ_k w_k ∇²y_k over its stage's N inputs (w its adjoint, y its M
// outputs), contracted once, and which of C's group blocks C_ab can be nonzero: the part of a Hessian's chain rule
// that both ways of adding a node's curvature to an element share (core/stage_block_curvature.h by 3×3 blocks of
// the element's slots, core/stage_whole_curvature.h into a whole element block). S is the node's layer's shape
// (StageGraph::Shape<I>, core/stage_graph.h): its stage, input groups and their offsets.
#pragma once

#include "core/flatten.h"
#include "core/for_each_index.h"
#include "core/stage.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace jetshell {

/// What each block C_ab of a node's contracted Hessian can be: for a stage declaring constant Hessians, zero
/// (a bilinear stage couples only some of its input groups), diagonal (every entry on the block's diagonal, as
/// for a dot product of two groups: C_ab Z_b is then a row scaling) or dense; for any other stage, dense.
enum class BlockKind : std::int8_t { Zero, Diagonal, Dense };
/// The input group of a node of shape S that holds its stage input i.
template <typename S>
constexpr int groupOfInput(int i) {
  int a = 0;
  while (S::offset(a + 1) <= i) ++a;
  return a;
}
template <typename S>
const std::array<BlockKind, S::G * S::G>& blockKinds() {
  static const std::array<BlockKind, S::G * S::G> kinds = [] {
    std::array<BlockKind, S::G * S::G> m{};
    if constexpr (HasConstantHessian<typename S::Stage>::value) {
      m.fill(BlockKind::Zero);
      const auto& c = constantStageHessians<typename S::Stage>();
      for (int e = 0; e < c.numEntries; ++e) {
        const auto& t = c.entries[static_cast<std::size_t>(e)];
        const int a = groupOfInput<S>(t.i), b = groupOfInput<S>(t.j);
        BlockKind& k = m[static_cast<std::size_t>(a * S::G + b)];
        const bool diagonal = S::Groups::size[static_cast<std::size_t>(a)] == S::Groups::size[static_cast<std::size_t>(b)] &&
                              t.i - S::offset(a) == t.j - S::offset(b);
        if (k == BlockKind::Zero) k = diagonal ? BlockKind::Diagonal : BlockKind::Dense;
        else if (!diagonal) k = BlockKind::Dense;
      }
    } else {
      m.fill(BlockKind::Dense);
    }
    return m;
  }();
  return kinds;
}

/// A constant-Hessian stage's entries in the blocks C_ab with a ≤ b.
template <typename S>
const std::vector<typename ConstantStageHessians<typename S::Stage>::Entry>& upperEntries() {
  static const auto entries = [] {
    std::vector<typename ConstantStageHessians<typename S::Stage>::Entry> r;
    const auto& c = constantStageHessians<typename S::Stage>();
    for (int e = 0; e < c.numEntries; ++e) {
      const auto& t = c.entries[static_cast<std::size_t>(e)];
      if (groupOfInput<S>(t.i) <= groupOfInput<S>(t.j)) r.push_back(t);
    }
    return r;
  }();
  return entries;
}

/// C = Σ_k w_k ∇²y_k of a node of shape S (its layer's StageGraph::Shape) from its stage's Hessians (a stage with
/// constant Hessians: from their nonzero entries); false when there is no curvature (an affine stage, a zero
/// adjoint).
template <typename S>
JETSHELL_INLINE bool contractCurvature(const double* w, const std::array<Eigen::Matrix<double, S::N, S::N>, S::M>* h,
                                       Eigen::Matrix<double, S::N, S::N>& C) {
  using Stage = typename S::Stage;
  bool any = false;
  for (int k = 0; k < S::M; ++k) any = any || w[k] != 0.0;
  if (!any) return false;
  if constexpr (IsAffineStage<Stage>::value) {
    return false;
  } else if constexpr (HasConstantHessian<Stage>::value) {
    // Only the blocks addNodeCurvature and addWholeCurvature read (a ≤ b, possibly nonzero) are formed.
    const auto& entries = upperEntries<S>();
    if (entries.empty()) return false;
    const auto& kinds = blockKinds<S>();
    forEachIndex<S::G>([&](auto groupA) {
      constexpr int a = decltype(groupA)::value;
      forEachIndex<S::G>([&](auto groupB) {
        constexpr int b = decltype(groupB)::value;
        if constexpr (a <= b)
          if (kinds[static_cast<std::size_t>(a * S::G + b)] != BlockKind::Zero)
            C.template block<S::Groups::size[a], S::Groups::size[b]>(S::offset(a), S::offset(b)).setZero();
      });
    });
    for (const auto& t : entries) C(t.i, t.j) += w[t.k] * t.h;
    return true;
  } else {
    if (h == nullptr) return false;
    C.noalias() = w[0] * (*h)[0];
    for (int k = 1; k < S::M; ++k)
      if (w[k] != 0.0) C.noalias() += w[k] * (*h)[static_cast<std::size_t>(k)];
    return true;
  }
}

}  // namespace jetshell
