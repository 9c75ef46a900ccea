// A stage-graph element's Hessian formed as a whole (core/stage_graph_evaluator.h, elementWhole: the contracted
// exact or Gauss–Newton Hessian of a translation-invariant graph). Every node's total Jacobian is stored by
// coordinate, T (Rw × M: one row per working coordinate, padded to whole vectors), and each node's curvature
// C = Σ_k w_k ∇²y_k (core/stage_contraction.h) is added to one full Rw × Rw block as products of its input groups'
// totals; the element's upper triangle is then expanded from that block, its base slot's row and column from the
// others' (the energy depends on differences x_k − x_0 only). S is a node's layer's shape (StageGraph::Shape<I>).
#pragma once

#include "core/flatten.h"
#include "core/for_each_index.h"
#include "core/psd_projection.h"
#include "core/stage_contraction.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>

namespace jetshell {

/// T += sign · Jᵀ in the rows of working slot w (a leaf's part of a total stored by coordinate).
template <typename JBlock, typename Total>
JETSHELL_INLINE void addLeafRows(int w, double sign, const JBlock& J, Total& T) {
  if (w < 0) return;
  for (int c = 0; c < Total::ColsAtCompileTime; ++c)
    for (int r = 0; r < 3; ++r) T(3 * w + r, c) += sign * J(c, r);
}

/// T += J_gᵀ of leaf group g of a node of shape S in its slots' rows (a Difference: + at its second vertex's, −
/// at its first's). J: the node's Jacobian, or a reader's composed with it (any row count).
template <typename S, int g, typename Jac, typename Slots, typename Total>
JETSHELL_INLINE void addLeafGroup(const Jac& J, const Slots& slot, Total& T) {
  const auto Jg = J.template middleCols<3>(S::offset(g));
  if constexpr (S::Groups::isDifference[g]) {
    addLeafRows(slot[1], 1.0, Jg, T);
    addLeafRows(slot[0], -1.0, Jg, T);
  } else {
    addLeafRows(slot[0], 1.0, Jg, T);
  }
}

/// H += Σ over the group pairs of C = Σ_k w_k ∇²y_k of a node of shape S, its groups' totals by coordinate given
/// by total(group) (From groups) and its leaves' working slots by slot: From–From pairs as products of totals,
/// each leaf's pairs with the From groups as one strip R = Σ_b T_b C_(b, leaf) added to the leaf's columns and,
/// transposed, rows, leaf–leaf pairs as 3×3 blocks. Full and symmetric. Only the blocks C_ab with a ≤ b are read
/// (contractCurvature forms no others). H: the element's whole block, Rw × Rw.
template <typename S, typename Slots, typename Totals, typename WholeBlock>
JETSHELL_INLINE void addWholeCurvature(const Eigen::Matrix<double, S::N, S::N>& C, const std::array<Slots, S::G>& slot,
                                       Totals&& total, WholeBlock& H) {
  constexpr int Rw = WholeBlock::RowsAtCompileTime;
  const auto& kinds = blockKinds<S>();
  forEachIndex<S::G>([&](auto groupA) {
    constexpr int a = decltype(groupA)::value;
    constexpr int na = S::Groups::size[a], oa = S::offset(a);
    constexpr bool leafA = S::Groups::layer[a] < 0;
    if constexpr (leafA) {
      // The leaf's strip over every From group b (C_(b, a) = C_abᵀ read from the block with the smaller index).
      Eigen::Matrix<double, Rw, 3> R;
      bool any = false;
      forEachIndex<S::G>([&](auto groupB) {
        constexpr int b = decltype(groupB)::value;
        if constexpr (S::Groups::layer[b] >= 0) {
          constexpr int lo = a < b ? a : b, hi = a < b ? b : a;
          const BlockKind kind = kinds[static_cast<std::size_t>(lo * S::G + hi)];
          if (kind == BlockKind::Zero) return;
          constexpr int nb = S::Groups::size[b];
          const auto Cba = [&] {
            if constexpr (b < a) {
              return C.template block<nb, 3>(S::offset(b), oa);
            } else {
              return C.template block<3, nb>(oa, S::offset(b)).transpose();
            }
          }();
          if (!any) R.setZero();
          any = true;
          if constexpr (nb == 3) {
            if (kind == BlockKind::Diagonal) {
              for (int j = 0; j < 3; ++j) R.col(j) += Cba(j, j) * total(groupB).col(j);
              return;
            }
          }
          R.noalias() += total(groupB).lazyProduct(Cba);
        }
      });
      if (any) {
        constexpr int rows = S::Groups::isDifference[a] ? 2 : 1;
        for (int t = 0; t < rows; ++t) {
          const int w = slot[a][static_cast<std::size_t>(t)];
          if (w < 0) continue;
          const double sign = S::Groups::isDifference[a] && t == 0 ? -1.0 : 1.0;
          H.template middleCols<3>(3 * w) += sign * R;
          H.template middleRows<3>(3 * w) += sign * R.transpose();
        }
      }
    }
    forEachIndex<S::G>([&](auto groupB) {
      constexpr int b = decltype(groupB)::value;
      constexpr bool leafB = S::Groups::layer[b] < 0;
      if constexpr (b >= a && leafA == leafB) {
        const BlockKind kind = kinds[static_cast<std::size_t>(a * S::G + b)];
        if (kind == BlockKind::Zero) return;
        constexpr int nb = S::Groups::size[b], ob = S::offset(b);
        const auto Cab = C.template block<na, nb>(oa, ob);
        if constexpr (!leafA) {
          // Z_aᵀ C_ab Z_b with Z_g = T_gᵀ: (T_a C_ab) T_bᵀ, and its transpose for a ≠ b.
          Eigen::Matrix<double, Rw, nb> P;
          if (kind == BlockKind::Diagonal) {
            for (int j = 0; j < nb; ++j) P.col(j) = Cab(j, j) * total(groupA).col(j);
          } else {
            P.noalias() = total(groupA).lazyProduct(Cab);
          }
          if constexpr (a == b) {
            H.noalias() += P.lazyProduct(total(groupB).transpose());
          } else {
            const WholeBlock X = P.lazyProduct(total(groupB).transpose());
            H += X + X.transpose();
          }
        } else {
          // Two leaves: ±C_ab at each pair of their slots (and its transpose for a ≠ b).
          constexpr int ra = S::Groups::isDifference[a] ? 2 : 1, rb = S::Groups::isDifference[b] ? 2 : 1;
          const Eigen::Matrix3d M = Cab;
          for (int i = 0; i < ra; ++i) {
            const int wa = slot[a][static_cast<std::size_t>(i)];
            if (wa < 0) continue;
            const double sa = S::Groups::isDifference[a] && i == 0 ? -1.0 : 1.0;
            for (int j = 0; j < rb; ++j) {
              const int wb = slot[b][static_cast<std::size_t>(j)];
              if (wb < 0) continue;
              const double sb = S::Groups::isDifference[b] && j == 0 ? -1.0 : 1.0;
              H.template block<3, 3>(3 * wa, 3 * wb) += (sa * sb) * M;
              if constexpr (a != b) H.template block<3, 3>(3 * wb, 3 * wa) += (sa * sb) * M.transpose();
            }
          }
        }
      }
    });
  });
}

/// The element block's upper triangle from the whole block H over its Kw working slots 1 … K−1: those slots' blocks on and
/// above the diagonal as they are, the base's row and own block from H (completeTranslationInvariantRow,
/// core/psd_projection.h). The lower triangle is not written: the assembly reads the upper one, and a
/// projection, which reads the whole block, never takes this path (a contracted Hessian has none).
template <int Kw, typename WholeBlock, typename Hessian>
JETSHELL_INLINE void expandWholeUpper(const WholeBlock& H, Hessian& hessian) {
  for (int c = 0; c < Kw; ++c)
    for (int r = 0; r <= c; ++r) hessian.template block<3, 3>(3 + 3 * r, 3 + 3 * c) = H.template block<3, 3>(3 * r, 3 * c);
  completeTranslationInvariantRow(H, hessian);
}

}  // namespace jetshell
