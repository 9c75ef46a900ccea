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
//                                  total Jacobians.
//   energy(s, entity, {inputs...}) the root: a one-output stage (the energy density), always at order 2 when a
//                                  Hessian is asked.
//   finish(wantG, wantH, g, H)     g = J_rootᵀ (with a Hessian, from the forward rows; alone, by one reverse
//                                  sweep of adjoints over the local Jacobians: no rows formed). H by a reverse sweep: adjoint w̄ = 1 at the root, and per stage node
//                                  H += Zᵀ (Σ_k w̄_k ∇²y_k) Z, then w̄_inputs += (∂y/∂z)ᵀ w̄. That is
//                                  H = J_sᵀ W'' J_s + Σ_k w_k ∇²s_k, recursively. Gauss–Newton (context.order < 2
//                                  with a Hessian asked) keeps the root's term only: H = J_sᵀ W'' J_s.
// Cost: total Jacobians are full-width rows (D), so that each update is one fixed-length vector operation; a
// leaf stores no rows: its ±I selector is applied directly (two scalar updates instead of a row update). The
// curvature Zᵀ C Z is formed per input node, skipping the zero entries of C (a bilinear stage couples only some
// of its inputs; a stage with constant zero Hessians, core/stage.h, has none) and, in Zᵀ, the columns off the
// input's support (the stencil vertices it depends on, e.g. three for a face normal). Only the blocks C_ab with
// b ≥ a are formed, the diagonal one halved, into P; the Hessian is P + Pᵀ (symmetric pairs of blocks once).
// A value-only evaluation (no gradient, no Hessian: a line search's trial point) records each node's value and
// nothing of the graph (no input map, groups or support), since nothing will be chained; a gradient alone records
// the input map its reverse sweep reads, and no groups or supports.
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
    return addStage<S>(inputs, context_.order, [&](const double* z, int order) {
      auto* d = new (allocate(sizeof(StageDerivativesOf<S>))) StageDerivativesOf<S>;
      return evaluateStageView(s, z, entity, order, context_.path, *d);
    });
  }
  /// A stage node whose result is shared through a cache (computed by the first stencil that asks).
  template <typename S>
  int stage(StageCache<S>& cache, int entity, std::initializer_list<int> inputs) {
    return addStage<S>(inputs, context_.order, [&](const double* z, int) { return cache.get(entity, z, context_); });
  }
  /// The root: a one-output stage, the stencil's energy.
  template <typename S>
  int energy(const S& s, int entity, std::initializer_list<int> inputs) {
    static_assert(S::kOutputs == 1, "the energy stage has one output");
    root_ = addStage<S>(inputs, context_.energyOrder, [&](const double* z, int order) {
      auto* d = new (allocate(sizeof(StageDerivativesOf<S>))) StageDerivativesOf<S>;
      return evaluateStageView(s, z, entity, order, context_.path, *d);
    });
    return root_;
  }

  /// Output k of a node.
  double value(int node, int k = 0) const { return nodes_[node].value[k]; }

  /// The energy; g (and H) over the stencil's D coordinates when asked.
  double finish(bool wantG, bool wantH, Gradient& g, Hessian& H) {
    if (root_ < 0) throw std::logic_error("stage chain: no energy stage");
    const Node& r = nodes_[root_];
    if (wantG && !forwardRows()) reverseGradient(g);
    if ((wantG || wantH) && forwardRows()) g = row(r, 0).transpose();
    if (wantH) {
      for (int i = 0; i < D * D; ++i) Hrow_[i] = 0.0;
      for (int n = 0; n <= root_; ++n)
        for (int k = 0; k < kMaxStageOutputs; ++k) nodes_[n].adjoint[k] = 0.0;
      nodes_[root_].adjoint[0] = 1.0;
      const bool exact = context_.order >= 2;
      for (int n = root_; n >= 0; --n) {
        Node& node = nodes_[n];
        if (node.numInputs == 0) continue;  // a leaf
        if (n != root_ && !exact) break;
        addCurvature(node);
        if (exact) {
          for (int i = 0; i < node.numInputs; ++i) {
            double s = 0.0;
            for (int k = 0; k < node.outputs; ++k) s += node.view.jacobian[k + node.outputs * i] * node.adjoint[k];
            nodes_[node.inputNode[i]].adjoint[node.inputComponent[i]] += s;
          }
        }
      }
      const Eigen::Map<const Eigen::Matrix<double, D, D, Eigen::RowMajor>> P(Hrow_);
      H = P + P.transpose();
    }
    return r.value[0];
  }

 private:
  /// Total Jacobians are formed forward only when a Hessian is asked (its curvature terms need them); a gradient
  /// alone comes from one reverse sweep over the local Jacobians.
  bool forwardRows() const { return context_.energyOrder >= 2; }

  /// g = J_rootᵀ by adjoints: w̄ = 1 at the root, w̄_inputs += (∂y/∂z)ᵀ w̄ per stage node, a leaf's w̄ added to
  /// its vertex's coordinates (subtracted at its second vertex).
  void reverseGradient(Gradient& g) {
    g.setZero();
    for (int n = 0; n <= root_; ++n)
      for (int k = 0; k < kMaxStageOutputs; ++k) nodes_[n].adjoint[k] = 0.0;
    nodes_[root_].adjoint[0] = 1.0;
    for (int n = root_; n >= 0; --n) {
      Node& node = nodes_[n];
      if (node.numInputs == 0) {
        for (int c = 0; c < 3; ++c) {
          g[3 * node.leafPlus + c] += node.adjoint[c];
          if (node.leafMinus >= 0) g[3 * node.leafMinus + c] -= node.adjoint[c];
        }
        continue;
      }
      for (int i = 0; i < node.numInputs; ++i) {
        double s = 0.0;
        for (int k = 0; k < node.outputs; ++k) s += node.view.jacobian[k + node.outputs * i] * node.adjoint[k];
        nodes_[node.inputNode[i]].adjoint[node.inputComponent[i]] += s;
      }
    }
  }

  struct Node {
    int outputs = 0;
    int numInputs = 0;                       // 0: a leaf
    int inputNode[kMaxStageInputs];          // per input i: the node and component it reads
    int inputComponent[kMaxStageInputs];
    int numGroups = 0;                       // input nodes in order; group g is inputs groupStart[g] ..
    int groupNode[kMaxStageInputs];
    int groupStart[kMaxStageInputs + 1];
    const double* value = nullptr;           // outputs
    StageView view;                          // local derivatives (stage nodes)
    double leafValue[3];
    int leafPlus = -1, leafMinus = -1;       // a leaf's Jacobian: +I at vertex leafPlus, −I at leafMinus (or none)
    int numSupport = 0;                      // the stencil vertices the node depends on, ascending
    int support[K];
    std::uint32_t mask = 0;                  // the same as bits
    alignas(64) double J[kMaxStageOutputs * D];  // total Jacobian ∂y_k/∂xe: row k at J + k·D, zero off the
                                                 // support; unused for a leaf
    double adjoint[kMaxStageOutputs];
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

  static void setSupport(Node& n, std::uint32_t mask) {
    n.mask = mask;
    n.numSupport = 0;
    for (int v = 0; v < K; ++v)
      if (mask >> v & 1u) n.support[n.numSupport++] = v;
  }

  int leaf(int j, int i) {
    Node& n = newNode();
    n.outputs = 3;
    n.numInputs = 0;
    for (int c = 0; c < 3; ++c) n.leafValue[c] = xe_[3 * j + c] - (i >= 0 ? xe_[3 * i + c] : 0.0);
    n.value = n.leafValue;
    if (forwardRows()) setSupport(n, 1u << j | (i >= 0 ? 1u << i : 0u));  // read by forward rows only
    n.leafPlus = j;
    n.leafMinus = i;  // no rows stored: the chain applies a leaf's ±I selector directly
    return numNodes_ - 1;
  }

  template <typename S, typename Evaluate>
  int addStage(std::initializer_list<int> inputs, int order, Evaluate&& evaluate) {
    constexpr int N = S::kInputs, M = S::kOutputs;
    double z[N];
    Node& n = newNode();
    const int self = numNodes_ - 1;
    if (context_.energyOrder == 0) {
      // Values only (a line search's trial point): no derivative will be chained, so the node keeps its value
      // and nothing of the graph (input map, groups, support).
      int i = 0;
      for (int p : inputs) {
        if (p < 0 || p >= self) throw std::logic_error("stage chain: an input is not an earlier node");
        const Node& in = nodes_[p];
        if (i + in.outputs > N) throw std::logic_error("stage chain: inputs larger than the stage's kInputs");
        for (int c = 0; c < in.outputs; ++c) z[i++] = in.value[c];
      }
      if (i != N) throw std::logic_error("stage chain: inputs smaller than the stage's kInputs");
      n.view = evaluate(z, 0);
      n.outputs = M;
      n.numInputs = N;
      n.value = n.view.value;
      return self;
    }
    int i = 0;
    std::uint32_t mask = 0;
    n.numGroups = 0;
    const bool rows = forwardRows();  // a gradient alone needs the input map only, not the groups or support
    for (int p : inputs) {
      if (p < 0 || p >= self) throw std::logic_error("stage chain: an input is not an earlier node");
      const Node& in = nodes_[p];
      if (rows) {
        mask |= in.mask;
        n.groupNode[n.numGroups] = p;
        n.groupStart[n.numGroups++] = i;
      }
      for (int c = 0; c < in.outputs; ++c, ++i) {
        if (i >= N) throw std::logic_error("stage chain: inputs larger than the stage's kInputs");
        z[i] = in.value[c];
        n.inputNode[i] = p;
        n.inputComponent[i] = c;
      }
    }
    if (i != N) throw std::logic_error("stage chain: inputs smaller than the stage's kInputs");
    n.view = evaluate(z, order);
    n.outputs = M;
    n.numInputs = N;
    n.value = n.view.value;
    if (rows) {
      n.groupStart[n.numGroups] = N;
      setSupport(n, mask);
      // J_k = Σ_q (∂y_k/∂z_q) J_input(q): full-width rows (zero off the support), so that every update is a
      // fixed-length vector operation.
      // A leaf input adds ±(∂y_k/∂z_q) at its two columns instead of a row.
      const double* a = n.view.jacobian;
      for (int k = 0; k < M; ++k) row(n, k).setZero();
      for (int q = 0; q < N; ++q) {
        const Node& from = nodes_[n.inputNode[q]];
        if (from.numInputs == 0) {
          const int plus = 3 * from.leafPlus + n.inputComponent[q];
          const int minus = from.leafMinus >= 0 ? 3 * from.leafMinus + n.inputComponent[q] : -1;
          for (int k = 0; k < M; ++k) {
            const double akq = a[k + M * q];
            n.J[k * D + plus] += akq;
            if (minus >= 0) n.J[k * D + minus] -= akq;
          }
          continue;
        }
        const auto in = row(from, n.inputComponent[q]);
        for (int k = 0; k < M; ++k) {
          const double akq = a[k + M * q];
          if (akq != 0.0) row(n, k).noalias() += akq * in;
        }
      }
    }
    return self;
  }

  using Row = Eigen::Map<Eigen::Matrix<double, 1, D>>;
  static Row row(Node& n, int k) { return Row(n.J + k * D); }
  static Eigen::Map<const Eigen::Matrix<double, 1, D>> row(const Node& n, int k) {
    return Eigen::Map<const Eigen::Matrix<double, 1, D>>(n.J + k * D);
  }

  /// Adds Zᵀ C Z (C = Σ_k w̄_k ∇²y_k) to P, half of H (H = P + Pᵀ at the end): per input group a, only the
  /// blocks C_ab with b ≥ a (the diagonal block halved), so a symmetric pair of blocks is formed once. Per group
  /// a: Y = Σ_{b≥a} C_ab Z_b (full-width rows, zero entries of C skipped, a leaf's ±1 columns written directly),
  /// then for each column r of Z_a on a's support, P's row r += Z_a(·, r)ᵀ Y.
  void addCurvature(const Node& node) {
    const int N = node.numInputs;
    double C[kMaxStageInputs * kMaxStageInputs];
    bool any = false;
    for (int k = 0; k < node.outputs; ++k) {
      const double w = node.adjoint[k];
      const double* h = node.view.hessian[k];
      if (w == 0.0 || h == nullptr) continue;
      if (!any) {
        for (int i = 0; i < N * N; ++i) C[i] = w * h[i];
      } else {
        for (int i = 0; i < N * N; ++i) C[i] += w * h[i];
      }
      any = true;
    }
    if (!any) return;
    alignas(64) double Y[kMaxStageOutputs * D];
    for (int a = 0; a < node.numGroups; ++a) {
      const Node& A = nodes_[node.groupNode[a]];
      const int sa = node.groupStart[a], ea = node.groupStart[a + 1], na = A.outputs;
      bool nonzero = false;
      for (int r = 0; r < na; ++r) Row(Y + r * D).setZero();
      for (int q = sa; q < N; ++q) {
        const Node& B = nodes_[node.inputNode[q]];
        const int comp = node.inputComponent[q];
        const double half = q < ea ? 0.5 : 1.0;
        for (int r = 0; r < na; ++r) {
          const double crq = C[(sa + r) + N * q];
          if (crq == 0.0) continue;
          nonzero = true;
          if (B.numInputs == 0) {
            Y[r * D + 3 * B.leafPlus + comp] += half * crq;
            if (B.leafMinus >= 0) Y[r * D + 3 * B.leafMinus + comp] -= half * crq;
          } else {
            Row(Y + r * D).noalias() += (half * crq) * row(B, comp);
          }
        }
      }
      if (!nonzero) continue;
      if (A.numInputs == 0) {  // a leaf: column 3v + r of Z_a is ±e_r
        for (int r = 0; r < na; ++r) {
          const auto y = Eigen::Map<const Eigen::Matrix<double, 1, D>>(Y + r * D);
          Row(Hrow_ + (3 * A.leafPlus + r) * D).noalias() += y;
          if (A.leafMinus >= 0) Row(Hrow_ + (3 * A.leafMinus + r) * D).noalias() -= y;
        }
        continue;
      }
      // P's row of each column of Z_a on a's support += Z_a(·, column)ᵀ Y.
      for (int t = 0; t < A.numSupport; ++t) {
        for (int cc = 0; cc < 3; ++cc) {
          const int hr = 3 * A.support[t] + cc;
          Row h(Hrow_ + hr * D);
          for (int r = 0; r < na; ++r) {
            const double z = A.J[r * D + hr];
            if (z != 0.0) h.noalias() += z * Eigen::Map<const Eigen::Matrix<double, 1, D>>(Y + r * D);
          }
        }
      }
    }
  }

  const double* xe_ = nullptr;
  StageContext context_;
  int numNodes_ = 0;
  int root_ = -1;
  Node nodes_[kMaxNodes];
  alignas(64) double Hrow_[D * D];  // P, half of the Hessian being accumulated (H = P + Pᵀ), row-major
  alignas(64) unsigned char arena_[1 << 16];
  std::size_t arenaUsed_ = 0;
};

}  // namespace jetshell
