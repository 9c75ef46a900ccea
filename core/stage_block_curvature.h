// A stage-graph node's curvature Zᵀ C Z added to an element's Hessian by 3×3 blocks of the element's working
// slots (core/stage_graph_evaluator.h: the per-element exact Hessian, a projected one, the contracted Hessian of a
// graph that is not translation-invariant). C = Σ_k w_k ∇²y_k comes from core/stage_contraction.h; Z_g is each input
// group's total Jacobian over its slots (±I for a leaf). S is the node's layer's shape (StageGraph::Shape<I>), Kw
// the element's working slots, H its working block (the upper triangle's blocks only, unless Full).
#pragma once

#include "core/flatten.h"
#include "core/for_each_index.h"
#include "core/stage_contraction.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <type_traits>

namespace jetshell {

/// The slots group g of a node of shape S spans in the working coordinates: a Local group the element's Kw
/// working slots, a leaf or Shared group its support.
template <typename S, int Kw>
constexpr int groupWidth(int g) {
  const auto k = static_cast<std::size_t>(g);
  return S::Groups::layer[k] >= 0 && !S::Groups::fromShared[k] ? Kw : S::Groups::support[k];
}

/// Adds M (3×3, the block of element slots (r, c)) to H: every block when Full, else only the upper
/// triangle's, M going to (c, r) transposed when r > c. `mirror`: the block stands for its transpose at
/// (c, r) too (added as Mᵀ there).
template <bool Full, typename Work>
JETSHELL_INLINE void addBlock(int r, int c, const Eigen::Matrix3d& M, bool mirror, Work& H) {
  if constexpr (Full) {
    H.template block<3, 3>(3 * r, 3 * c) += M;
    if (mirror) H.template block<3, 3>(3 * c, 3 * r) += M.transpose();
  } else {
    if (r < c) {
      H.template block<3, 3>(3 * r, 3 * c) += M;
    } else if (r > c) {
      if (mirror) H.template block<3, 3>(3 * c, 3 * r) += M.transpose();
    } else {
      H.template block<3, 3>(3 * r, 3 * r) += M;
      if (mirror) H.template block<3, 3>(3 * r, 3 * r) += M.transpose();
    }
  }
}

/// Y = C_ab Z_b over b's support slots: a leaf's Z is ±I (its columns are ±C_ab); a From group's T scaled by
/// rows when the block is diagonal.
template <typename S, int a, int b, typename Cab, typename Totals, typename Y>
JETSHELL_INLINE void curvatureColumns(const Cab& C, BlockKind kind, Totals&& total, Y& out) {
  if constexpr (S::Groups::layer[b] < 0) {
    if constexpr (S::Groups::isDifference[b]) {
      out.template middleCols<3>(0) = -C;  // x_j − x_i: −I at i (slot 0), +I at j (slot 1)
      out.template middleCols<3>(3) = C;
    } else {
      out = C;
    }
  } else {
    if constexpr (S::Groups::size[a] == S::Groups::size[b]) {
      if (kind == BlockKind::Diagonal) {
        out.noalias() = C.diagonal().asDiagonal() * total(std::integral_constant<int, b>());
        return;
      }
    }
    out.noalias() = C.lazyProduct(total(std::integral_constant<int, b>()));
  }
}

/// A leaf group a's pairs with the later groups b > a, Σ_b Z_aᵀ C_ab Z_b (and its transpose): Z_a is ±I at
/// a's one or two slots, so the sum is the strip R = Σ_b C_ab Z_b (na × the working columns) in a's rows, added once
/// per row and column block instead of once per pair and support slot (a bilinear stage such as the second
/// fundamental form couples each edge vector with several normals).
template <typename S, int Kw, int a, bool Full, typename Slots, typename Totals, typename Work>
JETSHELL_INLINE void addLeafStrip(const Eigen::Matrix<double, S::N, S::N>& C, const std::array<Slots, S::G>& slot,
                                  Totals&& total, Work& H) {
  constexpr int na = S::Groups::size[a], oa = S::offset(a);
  static_assert(na == 3, "a leaf group is one vertex's three coordinates");
  const auto& kinds = blockKinds<S>();
  Eigen::Matrix<double, 3, 3 * Kw> R;
  std::array<bool, Kw> touched{};
  bool any = false;
  forEachIndex<S::G>([&](auto groupB) {
    constexpr int b = decltype(groupB)::value;
    if constexpr (b > a) {
      const BlockKind kind = kinds[static_cast<std::size_t>(a * S::G + b)];
      if (kind == BlockKind::Zero) return;
      constexpr int nb = S::Groups::size[b], wb = groupWidth<S, Kw>(b);
      Eigen::Matrix<double, 3, 3 * wb> Y;
      curvatureColumns<S, a, b>(C.template block<na, nb>(oa, S::offset(b)), kind, total, Y);
      if (!any) R.setZero();
      any = true;
      for (int sb = 0; sb < wb; ++sb) {
        const int c = slot[b][static_cast<std::size_t>(sb)];
        if (c < 0) continue;
        R.template middleCols<3>(3 * c) += Y.template middleCols<3>(3 * sb);
        touched[static_cast<std::size_t>(c)] = true;
      }
    }
  });
  if (!any) return;
  constexpr int rows = S::Groups::isDifference[a] ? 2 : 1;
  for (int sa = 0; sa < rows; ++sa) {
    const int r = slot[a][static_cast<std::size_t>(sa)];
    if (r < 0) continue;
    const double sign = S::Groups::isDifference[a] && sa == 0 ? -1.0 : 1.0;
    for (int c = 0; c < Kw; ++c) {
      if (!touched[static_cast<std::size_t>(c)]) continue;
      const Eigen::Matrix3d M = sign * R.template middleCols<3>(3 * c);
      addBlock<Full>(r, c, M, true, H);
    }
  }
}

/// H += the node's curvature Zᵀ C Z (C = Σ_k w_k ∇²y_k, N×N) in element coordinates, block by block: per
/// pair of input groups a ≤ b with C_ab possibly nonzero, Y = C_ab Z_b over b's support slots, then per pair
/// of support slots the 3×3 block Z_a(·, slot)ᵀ Y(·, slot') at their element slots; a leaf group a's pairs
/// with the later groups through its strip (addLeafStrip). `slot[g]` maps group g's support slots to the
/// element's (−1: none); `total(group)` gives a From group's T.
template <typename S, int Kw, bool Full, typename Slots, typename Totals, typename Work>
JETSHELL_INLINE void addNodeCurvature(const Eigen::Matrix<double, S::N, S::N>& C, const std::array<Slots, S::G>& slot,
                                      Totals&& total, Work& H) {
  const auto& kinds = blockKinds<S>();
  forEachIndex<S::G>([&](auto groupA) {
    constexpr int a = decltype(groupA)::value;
    constexpr int na = S::Groups::size[a], oa = S::offset(a), la = S::Groups::layer[a], wa = groupWidth<S, Kw>(a);
    if constexpr (la < 0) addLeafStrip<S, Kw, a, Full>(C, slot, total, H);
    forEachIndex<S::G>([&](auto groupB) {
      constexpr int b = decltype(groupB)::value;
      // A leaf's pairs with later groups went into its strip.
      if constexpr (b == a || (b > a && la >= 0)) {
        const BlockKind kind = kinds[static_cast<std::size_t>(a * S::G + b)];
        if (kind == BlockKind::Zero) return;
        constexpr int nb = S::Groups::size[b], ob = S::offset(b);
        constexpr int wb = groupWidth<S, Kw>(b);
        const auto Cab = C.template block<na, nb>(oa, ob);
        Eigen::Matrix<double, na, 3 * wb> Y;
        curvatureColumns<S, a, b>(Cab, kind, total, Y);
        constexpr bool same = a == b;
        // A From group's blocks all at once, Z_aᵀ Y = (Z_aᵀ) Y with Z_aᵀ stored by columns: each column of the
        // product is a combination of Z_aᵀ's columns, which vectorizes (Z_a(·, slot)ᵀ Y(·, slot') per block
        // ran as scalar 3×3×3 products).
        using Product = std::conditional_t<(la >= 0), Eigen::Matrix<double, 3 * wa, 3 * wb>, Eigen::Matrix<double, 1, 1>>;
        Product P;
        if constexpr (la >= 0) {
          const Eigen::Matrix<double, 3 * wa, na> Zt = total(groupA).transpose();
          // A Local group spans the element's stencil in its own order (its slots are 0 … K−1), so Z_aᵀ C_aa Z_a
          // is the element block itself, symmetric: added whole when Full, else by column panels down to the
          // diagonal block (the lower triangle is never read), each panel one fixed-size product.
          if constexpr (same && !S::Groups::fromShared[a]) {
            if constexpr (Full) {
              H.noalias() += Zt.lazyProduct(Y);
            } else {
              forEachIndex<wa>([&](auto column) {
                constexpr int c = decltype(column)::value, rows = 3 * (c + 1);
                H.template block<rows, 3>(0, 3 * c).noalias() +=
                    Zt.template topRows<rows>().lazyProduct(Y.template middleCols<3>(3 * c));
              });
            }
            return;
          }
          P.noalias() = Zt.lazyProduct(Y);
        }
        for (int sa = 0; sa < wa; ++sa) {
          const int r = slot[a][static_cast<std::size_t>(sa)];
          if (r < 0) continue;
          for (int sb = same ? sa : 0; sb < wb; ++sb) {
            const int c = slot[b][static_cast<std::size_t>(sb)];
            if (c < 0) continue;
            Eigen::Matrix3d M;
            if constexpr (la < 0) {
              const double sign = S::Groups::isDifference[a] && sa == 0 ? -1.0 : 1.0;
              M = sign * Y.template block<3, 3>(0, 3 * sb);
            } else {
              M = P.template block<3, 3>(3 * sa, 3 * sb);
            }
            // Within one group the pair (sa, sb), sb > sa, stands for (sb, sa) too: Z_aᵀ C_aa Z_a is symmetric.
            addBlock<Full>(r, c, M, !same || sb != sa, H);
          }
        }
      }
    });
  });
}

}  // namespace jetshell
