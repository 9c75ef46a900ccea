// A node's curvature, C = Σ_k w_k ∇²y_k, contracted (core/stage_contraction.h) and added to an element's Hessian
// by 3×3 blocks of its slots (core/stage_block_curvature.h) or into a whole block (core/stage_whole_curvature.h),
// against Zᵀ C Z formed densely from the stage's Jets, Z being the node's inputs' total Jacobian over the
// element's working coordinates. The layers are taken from a small graph type; no mesh is needed.
#include "core/scalar.h"
#include "core/stage.h"
#include "core/stage_block_curvature.h"
#include "core/stage_graph.h"
#include "core/stage_whole_curvature.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>

// A named namespace: the unity build puts test files into one translation unit, where other files' anonymous
// namespaces already hold stages of the same names.
namespace jetshell::stage_curvature_test {
namespace {

// Layer 0 (Local): p = f(e, v) from a vertex difference e and a vertex v.
struct Pair {
  static constexpr int kInputs = 6, kOutputs = 3;
  template <typename T>
  void operator()(const T* z, T* p, int) const {
    const auto e = vec3(z), v = vec3(z + 3);
    vec3(p) = e.cross(v) + e * v.squaredNorm();
  }
};
// Layer 1, dense curvature: every pair of its groups (a difference e, p, a vertex v) is coupled.
struct Mixer {
  static constexpr int kInputs = 9, kOutputs = 1;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    const auto e = vec3(z), p = vec3(z + 3), v = vec3(z + 6);
    y[0] = sin(p.dot(e)) + p.dot(v) * e.squaredNorm() + v.cross(e).squaredNorm() + 0.5 * p.squaredNorm();
  }
};
// Layer 1, constant Hessians: Σ_i c_i e_i p_i couples e and p on the diagonal only (unequal entries), a cross
// product's component couples p and v densely, e and v not at all.
struct Bilinear {
  static constexpr int kInputs = 9, kOutputs = 1;
  static constexpr bool kConstantHessian = true;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    const auto e = vec3(z), p = vec3(z + 3), v = vec3(z + 6);
    y[0] = e[0] * p[0] + 2.0 * e[1] * p[1] - 3.0 * e[2] * p[2] + 2.0 * p.cross(v)[1];
  }
};

template <typename Root>
using Graph = StageGraph<3, Local<Pair, Difference, Vertex>, Local<Root, Difference, From<0>, Vertex>>;
static_assert(Graph<Mixer>::Shape<0>::N == 6 && Graph<Mixer>::Shape<1>::N == 9 && Graph<Mixer>::Shape<1>::G == 3);

constexpr int K = 3, Kw = 3, Dw = 3 * Kw, Rw = 12;
using Slots = std::array<std::int8_t, K>;

// The root's input groups' working slots: e = x_b − x_a at two slots, p (a Local group: the element's slots in
// order), v at one; −1 marks an absent vertex (a base whose rows are not kept).
const std::array<Slots, 3> kBothSlots = {{{1, 2, -1}, {0, 1, 2}, {0, -1, -1}}};
const std::array<Slots, 3> kAbsentSlot = {{{-1, 0, -1}, {0, 1, 2}, {2, -1, -1}}};

// Z: the root's inputs' total Jacobian over the working coordinates (the From group's from its given total, a
// difference's −I and +I at its two slots, a vertex's +I).
Eigen::Matrix<double, 9, Dw> totalJacobian(const Eigen::Matrix<double, 3, Dw>& pTotal, const std::array<Slots, 3>& slot) {
  Eigen::Matrix<double, 9, Dw> Z = Eigen::Matrix<double, 9, Dw>::Zero();
  if (slot[0][0] >= 0) Z.block<3, 3>(0, 3 * slot[0][0]) = -Eigen::Matrix3d::Identity();
  if (slot[0][1] >= 0) Z.block<3, 3>(0, 3 * slot[0][1]) = Eigen::Matrix3d::Identity();
  Z.middleRows<3>(3) = pTotal;
  if (slot[2][0] >= 0) Z.block<3, 3>(6, 3 * slot[2][0]) = Eigen::Matrix3d::Identity();
  return Z;
}

template <typename Root>
Eigen::Matrix<double, 9, 9> jetCurvature(const double* z, double w) {
  StageDerivativesOf<Root> d;
  stageDerivativesFromJets(Root(), z, 0, 2, d);
  return w * d.hessians[0];
}

const double kZ[9] = {0.3, -0.7, 0.4, 1.1, 0.2, -0.5, -0.6, 0.9, 0.35};

Eigen::Matrix<double, 3, Dw> somePTotal() {
  Eigen::Matrix<double, 3, Dw> T;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < Dw; ++c) T(r, c) = std::sin(1.0 + r + 0.37 * c);
  return T;
}

template <typename Root>
void checkBothWays(const Eigen::Matrix<double, 9, 9>& C, const std::array<Slots, 3>& slot) {
  using S = typename Graph<Root>::template Shape<1>;
  const Eigen::Matrix<double, 3, Dw> pTotal = somePTotal();
  const Eigen::Matrix<double, 9, Dw> Z = totalJacobian(pTotal, slot);
  const Eigen::Matrix<double, Dw, Dw> expected = Z.transpose() * C * Z;
  const double scale = expected.cwiseAbs().maxCoeff();
  REQUIRE(scale > 0.0);

  // By 3×3 blocks: every block (Full), or the upper triangle's (the lower ones stay untouched).
  const auto total = [&](auto) -> const Eigen::Matrix<double, 3, Dw>& { return pTotal; };
  Eigen::Matrix<double, Dw, Dw> full = Eigen::Matrix<double, Dw, Dw>::Zero();
  addNodeCurvature<S, Kw, true>(C, slot, total, full);
  CHECK((full - expected).cwiseAbs().maxCoeff() <= 1e-14 * scale);
  Eigen::Matrix<double, Dw, Dw> upper = Eigen::Matrix<double, Dw, Dw>::Zero();
  addNodeCurvature<S, Kw, false>(C, slot, total, upper);
  for (int r = 0; r < Kw; ++r)
    for (int c = 0; c < Kw; ++c) {
      const Eigen::Matrix3d got = upper.block<3, 3>(3 * r, 3 * c);
      if (r <= c) {
        CHECK((got - expected.block<3, 3>(3 * r, 3 * c)).cwiseAbs().maxCoeff() <= 1e-14 * scale);
      } else {
        CHECK(got.isZero(0.0));
      }
    }

  // Whole: the totals stored by coordinate (Rw × M, padded rows zero), one full symmetric block.
  Eigen::Matrix<double, Rw, 3> pRows = Eigen::Matrix<double, Rw, 3>::Zero();
  pRows.topRows<Dw>() = pTotal.transpose();
  Eigen::Matrix<double, Rw, Rw> whole = Eigen::Matrix<double, Rw, Rw>::Zero();
  addWholeCurvature<S>(C, slot, [&](auto) -> const Eigen::Matrix<double, Rw, 3>& { return pRows; }, whole);
  CHECK((whole.topLeftCorner<Dw, Dw>() - expected).cwiseAbs().maxCoeff() <= 1e-14 * scale);
  CHECK(whole.bottomRows<Rw - Dw>().isZero(0.0));
  CHECK(whole.rightCols<Rw - Dw>().isZero(0.0));
}

}  // namespace

TEST_CASE("stage contraction: which blocks of a constant-Hessian stage's curvature can be nonzero") {
  using S = Graph<Bilinear>::Shape<1>;
  const auto& kinds = blockKinds<S>();
  // Groups e, p, v: e·p on the diagonal, p × v dense, nothing else.
  CHECK(kinds[0 * 3 + 1] == BlockKind::Diagonal);
  CHECK(kinds[1 * 3 + 2] == BlockKind::Dense);
  CHECK(kinds[0 * 3 + 2] == BlockKind::Zero);
  CHECK(kinds[0 * 3 + 0] == BlockKind::Zero);
  CHECK(kinds[1 * 3 + 1] == BlockKind::Zero);
  CHECK(kinds[2 * 3 + 2] == BlockKind::Zero);
  // A stage without constant Hessians: every block may be nonzero.
  for (BlockKind k : blockKinds<Graph<Mixer>::Shape<1>>()) CHECK(k == BlockKind::Dense);
}

TEST_CASE("stage contraction: C = w ∇²y from the stage's Jets, on the blocks the curvature reads") {
  SECTION("constant Hessians, from their nonzero entries") {
    using S = Graph<Bilinear>::Shape<1>;
    const double w = -1.75;
    Eigen::Matrix<double, 9, 9> C;
    C.setConstant(std::nan(""));  // blocks it does not form stay unread
    REQUIRE(contractCurvature<S>(&w, nullptr, C));
    const Eigen::Matrix<double, 9, 9> expected = jetCurvature<Bilinear>(kZ, w);
    const auto& kinds = blockKinds<S>();
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b)
        if (kinds[static_cast<std::size_t>(a * 3 + b)] != BlockKind::Zero)
          CHECK((C.block<3, 3>(3 * a, 3 * b) - expected.block<3, 3>(3 * a, 3 * b)).cwiseAbs().maxCoeff() <= 1e-15);
    const double zero = 0.0;
    CHECK_FALSE(contractCurvature<S>(&zero, nullptr, C));  // a zero adjoint: no curvature
  }
  SECTION("a stage's own Hessians") {
    using S = Graph<Mixer>::Shape<1>;
    StageDerivativesOf<Mixer> d;
    stageDerivativesFromJets(Mixer(), kZ, 0, 2, d);
    const double w = 0.8;
    Eigen::Matrix<double, 9, 9> C;
    REQUIRE(contractCurvature<S>(&w, &d.hessians, C));
    CHECK((C - w * d.hessians[0]).cwiseAbs().maxCoeff() <= 1e-15 * C.cwiseAbs().maxCoeff());
    CHECK_FALSE(contractCurvature<S>(&w, nullptr, C));  // no Hessians kept: nothing to contract
  }
}

TEST_CASE("stage curvature: Zᵀ C Z by 3×3 blocks and as a whole block, against the dense product") {
  SECTION("dense curvature, every block coupled") {
    checkBothWays<Mixer>(jetCurvature<Mixer>(kZ, 1.3), kBothSlots);
    checkBothWays<Mixer>(jetCurvature<Mixer>(kZ, 1.3), kAbsentSlot);
  }
  SECTION("constant Hessians: diagonal, dense and zero blocks") {
    using S = Graph<Bilinear>::Shape<1>;
    const double w = 0.6;
    Eigen::Matrix<double, 9, 9> C = Eigen::Matrix<double, 9, 9>::Zero();
    REQUIRE(contractCurvature<S>(&w, nullptr, C));
    // The curvature reads the blocks a ≤ b only: the reference is their symmetric completion.
    const Eigen::Matrix<double, 9, 9> upper = C.triangularView<Eigen::Upper>();
    const Eigen::Matrix<double, 9, 9> symmetric = upper + upper.transpose() - Eigen::Matrix<double, 9, 9>(upper.diagonal().asDiagonal());
    CHECK((symmetric - jetCurvature<Bilinear>(kZ, w)).cwiseAbs().maxCoeff() <= 1e-15);
    checkBothWays<Bilinear>(symmetric, kBothSlots);
    checkBothWays<Bilinear>(symmetric, kAbsentSlot);
  }
}

TEST_CASE("stage whole curvature: the element's upper triangle from the block over its differences") {
  // E(x) depends on u_k = x_k − x_0 (k = 1, 2) only: H = Lᵀ H_u L, L the 6 × 9 map u = L x.
  constexpr int KwR = 2;
  Eigen::Matrix<double, 8, 8> Hu = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix<double, 6, 6> A;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) A(r, c) = std::cos(0.3 * r + 0.71 * c);
  Hu.topLeftCorner<6, 6>() = A + A.transpose();
  Eigen::Matrix<double, 6, 9> L = Eigen::Matrix<double, 6, 9>::Zero();
  for (int k = 0; k < KwR; ++k) {
    L.block<3, 3>(3 * k, 0) = -Eigen::Matrix3d::Identity();
    L.block<3, 3>(3 * k, 3 * (k + 1)) = Eigen::Matrix3d::Identity();
  }
  const Eigen::Matrix<double, 9, 9> expected = L.transpose() * Hu.topLeftCorner<6, 6>() * L;
  Eigen::Matrix<double, 9, 9> H = Eigen::Matrix<double, 9, 9>::Zero();
  expandWholeUpper<KwR>(Hu, H);
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c)
      CHECK((H.block<3, 3>(3 * r, 3 * c) - expected.block<3, 3>(3 * r, 3 * c)).cwiseAbs().maxCoeff() <=
            1e-14 * expected.cwiseAbs().maxCoeff());
}

}  // namespace jetshell::stage_curvature_test
