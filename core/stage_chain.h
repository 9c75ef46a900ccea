// The chain rule between stages, for one stencil of K vertices (D = 3K coordinates). Written once here, so no
// term differentiates through its stages by hand.
//
// Data flow for one stencil (a term's build function calls these in order):
//   begin(xe, context)             the stencil's coordinates xe (3K) and what to compute
//   vertex(k), difference(i, j)    leaves: x_k and x_j − x_i (linear: their Jacobian is ±I, no curvature)
//   stage(s | cache, entity, {inputs...})
//                                  a stage node: its input z is the concatenated values of the input nodes. Local
//                                  derivatives (value y, ∂y/∂z, ∇²y_k) from the stage (core/stage.h) or from a
//                                  StageCache entry shared with other stencils (core/stage_cache.h). Forward: the
//                                  node's total Jacobian over the stencil, J = (∂y/∂z) Z, Z the inputs' stacked
//                                  total Jacobians, kept on the vertices the node depends on (its support).
//   energy(s, entity, {inputs...}) the root: a one-output stage (the energy density), always at order 2 when a
//                                  Hessian is asked.
//   finish(wantG, wantH, g, H)     g = J_rootᵀ. H by a reverse sweep: adjoint w̄ = 1 at the root, and per stage node
//                                  H += Zᵀ (Σ_k w̄_k ∇²y_k) Z, then w̄_inputs += (∂y/∂z)ᵀ w̄. That is
//                                  H = J_sᵀ W'' J_s + Σ_k w_k ∇²s_k, recursively. Gauss–Newton (context.order < 2
//                                  with a Hessian asked) keeps the root's term only: H = J_sᵀ W'' J_s.
// Every buffer is a fixed-size member (kMaxNodes nodes, stage sizes bounded by core/stage.h): a chain is built
// once per thread and reused; building and finishing a stencil never allocates.
#pragma once

#include "core/stage.h"
#include "core/stage_cache.h"

#include <Eigen/Core>

#include <cstdint>
#include <initializer_list>
#include <new>
#include <stdexcept>

namespace jetshell {

template <int K>
class StageChain {
 public:
  static constexpr int D = 3 * K;
  static constexpr int kMaxNodes = 32;
  using Gradient = Eigen::Matrix<double, D, 1>;
  using Hessian = Eigen::Matrix<double, D, D>;

  void begin(const double* xe, const StageContext& context) {
    xe_ = xe;
    context_ = context;
    numNodes_ = 0;
    arenaUsed_ = 0;
    root_ = -1;
  }
  const StageContext& context() const { return context_; }

  /// Leaf: the position of stencil vertex k.
  int vertex(int k) { return leaf(k, -1); }
  /// Leaf: x_j − x_i.
  int difference(int i, int j) { return leaf(j, i); }

  /// A stage node evaluated for this stencil only.
  template <typename S>
  int stage(const S& s, int entity, std::initializer_list<int> inputs) {
    return addStage<S>(inputs, context_.order, [&](const double* z, int order) -> const StageDerivativesOf<S>& {
      auto* d = new (allocate(sizeof(StageDerivativesOf<S>))) StageDerivativesOf<S>;
      evaluateStage(s, z, entity, order, context_.path, *d);
      return *d;
    });
  }
  /// A stage node whose result is shared through a cache (computed by the first stencil that asks).
  template <typename S>
  int stage(StageCache<S>& cache, int entity, std::initializer_list<int> inputs) {
    return addStage<S>(inputs, context_.order, [&](const double* z, int) -> const StageDerivativesOf<S>& {
      return cache.get(entity, z, context_);
    });
  }
  /// The root: a one-output stage, the stencil's energy.
  template <typename S>
  int energy(const S& s, int entity, std::initializer_list<int> inputs) {
    static_assert(S::kOutputs == 1, "the energy stage has one output");
    root_ = addStage<S>(inputs, context_.energyOrder, [&](const double* z, int order) -> const StageDerivativesOf<S>& {
      auto* d = new (allocate(sizeof(StageDerivativesOf<S>))) StageDerivativesOf<S>;
      evaluateStage(s, z, entity, order, context_.path, *d);
      return *d;
    });
    return root_;
  }

  /// Output k of a node.
  double value(int node, int k = 0) const { return nodes_[node].value[k]; }

  /// The energy; g (and H) over the stencil's D coordinates when asked.
  double finish(bool wantG, bool wantH, Gradient& g, Hessian& H) {
    if (root_ < 0) throw std::logic_error("stage chain: no energy stage");
    const Node& r = nodes_[root_];
    if (wantG || wantH) {
      g.setZero();
      for (int v = 0; v < K; ++v)
        if (r.support >> v & 1u)
          for (int c = 0; c < 3; ++c) g[3 * v + c] = r.J[3 * v + c];
    }
    if (wantH) {
      H.setZero();
      for (int n = 0; n <= root_; ++n)
        for (int k = 0; k < kMaxStageOutputs; ++k) nodes_[n].adjoint[k] = 0.0;
      nodes_[root_].adjoint[0] = 1.0;
      const bool exact = context_.order >= 2;
      for (int n = root_; n >= 0; --n) {
        Node& node = nodes_[n];
        if (node.numInputs == 0) continue;  // a leaf
        if (n != root_ && !exact) break;
        node.curvature(*this, node, H);
        if (exact) {
          for (int i = 0; i < node.numInputs; ++i) {
            double s = 0.0;
            for (int k = 0; k < node.outputs; ++k) s += node.jacobian[k + node.outputs * i] * node.adjoint[k];
            nodes_[node.inputNode[i]].adjoint[node.inputComponent[i]] += s;
          }
        }
      }
    }
    return r.value[0];
  }

 private:
  struct Node {
    int outputs = 0;
    int numInputs = 0;                     // 0: a leaf
    int inputNode[kMaxStageInputs];        // per input i: the node and component it reads
    int inputComponent[kMaxStageInputs];
    const double* value = nullptr;         // outputs
    const double* jacobian = nullptr;      // ∂y/∂z, column-major outputs × numInputs
    const double* hessian[kMaxStageOutputs] = {};  // ∇²y_k, column-major numInputs²; null below order 2
    double leafValue[3];
    std::uint32_t support = 0;             // bit v: depends on stencil vertex v
    double J[kMaxStageOutputs * D];        // total Jacobian, row k at J + k·D
    double adjoint[kMaxStageOutputs];
    void (*curvature)(const StageChain&, const Node&, Hessian&) = nullptr;  // curvatureOf<numInputs>
  };

  void* allocate(std::size_t bytes) {
    bytes = (bytes + 63) / 64 * 64;
    if (arenaUsed_ + bytes > sizeof(arena_)) throw std::length_error("stage chain: stage results exceed the arena");
    void* p = arena_ + arenaUsed_;
    arenaUsed_ += bytes;
    return p;
  }

  Node& newNode() {
    if (numNodes_ == kMaxNodes) throw std::length_error("stage chain: too many nodes in one stencil");
    return nodes_[numNodes_++];
  }

  int leaf(int j, int i) {
    Node& n = newNode();
    n.outputs = 3;
    n.numInputs = 0;
    for (int c = 0; c < 3; ++c) n.leafValue[c] = xe_[3 * j + c] - (i >= 0 ? xe_[3 * i + c] : 0.0);
    n.value = n.leafValue;
    n.support = 1u << j | (i >= 0 ? 1u << i : 0u);
    if (context_.energyOrder > 0) {
      for (int c = 0; c < 3 * D; ++c) n.J[c] = 0.0;
      for (int c = 0; c < 3; ++c) {
        n.J[c * D + 3 * j + c] = 1.0;
        if (i >= 0) n.J[c * D + 3 * i + c] = -1.0;
      }
    }
    return numNodes_ - 1;
  }

  template <typename S, typename Evaluate>
  int addStage(std::initializer_list<int> inputs, int order, Evaluate&& evaluate) {
    constexpr int N = S::kInputs, M = S::kOutputs;
    double z[N];
    int inputNode[N], inputComponent[N];
    int i = 0;
    std::uint32_t support = 0;
    for (int p : inputs) {
      if (p < 0 || p >= numNodes_) throw std::logic_error("stage chain: an input is not an earlier node");
      const Node& in = nodes_[p];
      support |= in.support;
      for (int c = 0; c < in.outputs; ++c, ++i) {
        if (i >= N) throw std::logic_error("stage chain: inputs larger than the stage's kInputs");
        z[i] = in.value[c];
        inputNode[i] = p;
        inputComponent[i] = c;
      }
    }
    if (i != N) throw std::logic_error("stage chain: inputs smaller than the stage's kInputs");
    const StageDerivativesOf<S>& d = evaluate(z, order);
    Node& n = newNode();
    n.outputs = M;
    n.numInputs = N;
    for (int k = 0; k < N; ++k) {
      n.inputNode[k] = inputNode[k];
      n.inputComponent[k] = inputComponent[k];
    }
    n.value = d.value.data();
    n.jacobian = d.jacobian.data();
    for (int k = 0; k < M; ++k) n.hessian[k] = order >= 2 ? d.hessians[k].data() : nullptr;
    n.support = support;
    n.curvature = &curvatureOf<N>;
    if (context_.energyOrder > 0) {
      // J_k = Σ_i (∂y_k/∂z_i) J_input(i), on the support's columns only.
      for (int k = 0; k < M; ++k)
        for (int c = 0; c < D; ++c) n.J[k * D + c] = 0.0;
      for (int q = 0; q < N; ++q) {
        const double* Jin = nodes_[inputNode[q]].J + inputComponent[q] * D;
        const std::uint32_t s = nodes_[inputNode[q]].support;
        for (int v = 0; v < K; ++v) {
          if (!(s >> v & 1u)) continue;
          for (int k = 0; k < M; ++k) {
            const double a = d.jacobian(k, q);
            for (int c = 3 * v; c < 3 * v + 3; ++c) n.J[k * D + c] += a * Jin[c];
          }
        }
      }
    }
    return numNodes_ - 1;
  }

  /// H += Zᵀ (Σ_k w̄_k ∇²y_k) Z for a node of N inputs, with fixed sizes (N × D) so that the products vectorize;
  /// Z's rows are the inputs' total Jacobians, zero off their supports.
  template <int N>
  static void curvatureOf(const StageChain& chain, const Node& node, Hessian& H) {
    Eigen::Matrix<double, N, N> C = Eigen::Matrix<double, N, N>::Zero();
    bool any = false;
    for (int k = 0; k < node.outputs; ++k) {
      if (node.adjoint[k] == 0.0 || node.hessian[k] == nullptr) continue;
      C.noalias() += node.adjoint[k] * Eigen::Map<const Eigen::Matrix<double, N, N>>(node.hessian[k]);
      any = true;
    }
    if (!any) return;
    Eigen::Matrix<double, N, D> Z;
    for (int q = 0; q < N; ++q)
      Z.row(q) = Eigen::Map<const Eigen::Matrix<double, 1, D>>(chain.nodes_[node.inputNode[q]].J +
                                                               node.inputComponent[q] * D);
    const Eigen::Matrix<double, N, D> CZ = C.lazyProduct(Z);
    H.noalias() += Z.transpose().lazyProduct(CZ);
  }

  const double* xe_ = nullptr;
  StageContext context_;
  int numNodes_ = 0;
  int root_ = -1;
  Node nodes_[kMaxNodes];
  alignas(64) unsigned char arena_[1 << 16];
  std::size_t arenaUsed_ = 0;
};

}  // namespace jetshell
