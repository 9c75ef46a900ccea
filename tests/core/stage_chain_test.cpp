#include "core/stage_chain.h"

#include <catch2/catch.hpp>
#include <algorithm>
#include <ceres/jet.h>

using namespace jetshell;

namespace {

/// n = (u × v)/‖u × v‖ (6 → 3).
struct Normal {
  static constexpr int kInputs = 6, kOutputs = 3;
  template <typename T>
  void operator()(const T* z, T* n, int) const {
    const V3<T> c = cross(load3(z), load3(z + 3));
    const T inv = constant<T>(1.0) / norm(c);
    for (int k = 0; k < 3; ++k) n[k] = inv * c[k];
  }
};
/// y = s·z (3 → 3), linear.
struct Scale {
  static constexpr int kInputs = 3, kOutputs = 3;
  double s = 2.0;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    for (int k = 0; k < 3; ++k) y[k] = constant<T>(s) * z[k];
  }
};
/// E = (n·p − 0.3)² + ‖p‖⁴ (6 → 1).
struct Energy {
  static constexpr int kInputs = 6, kOutputs = 1;
  template <typename T>
  void operator()(const T* z, T* e, int) const {
    const T d = dot(load3(z), load3(z + 3)) - constant<T>(0.3);
    const T q = squaredNorm(load3(z + 3));
    e[0] = d * d + q * q;
  }
};

/// The three stages composed as one function of the 9 coordinates.
template <typename T>
T composed(const T* x, bool linearNormal) {
  const V3<T> x0 = load3(x), u = load3(x + 3) - x0, v = load3(x + 6) - x0;
  T z[6] = {u[0], u[1], u[2], v[0], v[1], v[2]}, n[3], e[1];
  if (linearNormal) {
    Scale()(z, n, 0);
  } else {
    Normal()(z, n, 0);
  }
  const T in[6] = {n[0], n[1], n[2], x[6], x[7], x[8]};
  Energy()(in, e, 0);
  return e[0];
}

/// The chain's energy, gradient and Hessian.
/// order 1 or 2 with a Hessian; order 0: the gradient alone (energy stage at order 1, H untouched).
double chained(const double* x, int order, bool linearNormal, Eigen::Matrix<double, 9, 1>& g,
               Eigen::Matrix<double, 9, 9>& H) {
  static StageChain<3> chain;
  StageContext ctx;
  ctx.order = std::max(order, 1);
  ctx.energyOrder = order == 0 ? 1 : 2;
  chain.begin(x, ctx);
  const int n = linearNormal ? chain.stage(Scale(), 0, {chain.difference(0, 1)})
                             : chain.stage(Normal(), 0, {chain.difference(0, 1), chain.difference(0, 2)});
  chain.energy(Energy(), 0, {n, chain.vertex(2)});
  return chain.finish(true, order > 0, g, H);
}

}  // namespace

TEST_CASE("stage chain: gradient and Hessian through stages equal those of the composed function", "[stages]") {
  const double x[9] = {0.1, -0.2, 0.05, 1.1, 0.1, 0.2, 0.2, 0.9, -0.3};
  using J1 = ceres::Jet<double, 9>;
  using J2 = ceres::Jet<J1, 9>;
  J2 xj[9];
  for (int i = 0; i < 9; ++i) {
    xj[i] = J2(J1(x[i], i));
    xj[i].v[i] = J1(1.0);
  }
  const J2 ref = composed(static_cast<const J2*>(xj), false);
  Eigen::Matrix<double, 9, 1> g;
  Eigen::Matrix<double, 9, 9> H;
  CHECK(chained(x, 2, false, g, H) == Approx(ref.a.a).epsilon(1e-14));
  for (int i = 0; i < 9; ++i) {
    CHECK(g[i] == Approx(ref.a.v[i]).margin(1e-13));
    for (int j = 0; j < 9; ++j) CHECK(H(i, j) == Approx(ref.v[i].v[j]).margin(1e-12));
  }
  // The gradient alone (reverse sweep, no forward rows) is the same gradient.
  Eigen::Matrix<double, 9, 1> gAlone;
  CHECK(chained(x, 0, false, gAlone, H) == Approx(ref.a.a).epsilon(1e-14));
  for (int i = 0; i < 9; ++i) CHECK(gAlone[i] == Approx(ref.a.v[i]).margin(1e-13));
}

TEST_CASE("stage chain: Gauss-Newton drops the curvature of intermediate stages only", "[stages]") {
  const double x[9] = {0.1, -0.2, 0.05, 1.1, 0.1, 0.2, 0.2, 0.9, -0.3};
  Eigen::Matrix<double, 9, 1> g, gGN;
  Eigen::Matrix<double, 9, 9> H, HGN;
  // Linear intermediate stage: nothing to drop, Gauss-Newton is exact.
  chained(x, 2, true, g, H);
  chained(x, 1, true, gGN, HGN);
  CHECK((HGN - H).norm() <= 1e-14 * H.norm());
  // Nonlinear one: the model differs, the gradient does not.
  chained(x, 2, false, g, H);
  chained(x, 1, false, gGN, HGN);
  CHECK((gGN - g).norm() <= 1e-15 * g.norm());
  CHECK((HGN - H).norm() >= 1e-3 * H.norm());
}
