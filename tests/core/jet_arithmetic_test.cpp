// Energies written as plain math (core/jet_arithmetic.h): every listed operation compiles for double,
// ceres::Jet<double,N>, SecondOrderJet<N> and the parameter path's SecondOrderJet<N,P>, and its value, gradient
// and Hessian equal hand-derived ones. Inputs: x = (a, b), two 3-vectors.
#include "core/jet_arithmetic.h"

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

namespace {

constexpr int kN = 6;
using J1 = ceres::Jet<double, kN>;
using J2 = SecondOrderJet<kN>;
using JP = SecondOrderJet<kN, 2>;  // the shape of the parameter and origin derivatives (inner duals unseeded)
using Vec6 = Eigen::Matrix<double, kN, 1>;
using Mat6 = Eigen::Matrix<double, kN, kN>;
using Eigen::Matrix3d;
using Eigen::Vector3d;

template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

template <typename T>
Vec3<T> vecA(const T* x) {
  return Vec3<T>(x[0], x[1], x[2]);
}
template <typename T>
Vec3<T> vecB(const T* x) {
  return Vec3<T>(x[3], x[4], x[5]);
}

const double kX[kN] = {0.4, 0.9, -0.5, 0.7, -0.2, 1.3};
Vector3d handA() { return Vector3d(kX[0], kX[1], kX[2]); }
Vector3d handB() { return Vector3d(kX[3], kX[4], kX[5]); }

/// Value, gradient and Hessian derived by hand.
struct Expected {
  double value = 0.0;
  Vec6 gradient = Vec6::Zero();
  Mat6 hessian = Mat6::Zero();
};

Matrix3d skew(const Vector3d& w) {  // skew(w) u = w × u
  Matrix3d s;
  s << 0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0;
  return s;
}

bool close(double got, double want) { return std::abs(got - want) <= 1e-12 * (1.0 + std::abs(want)); }

/// f evaluated with every scalar type against the hand values.
template <typename F>
void checkEveryScalar(const F& f, const Expected& e) {
  CHECK(close(f(kX), e.value));

  J1 y[kN];
  for (int i = 0; i < kN; ++i) y[i] = J1(kX[i], i);
  const J1 r1 = f(static_cast<const J1*>(y));
  CHECK(close(r1.a, e.value));
  for (int i = 0; i < kN; ++i) CHECK(close(r1.v[i], e.gradient[i]));

  J2 z[kN];
  for (int i = 0; i < kN; ++i) z[i] = secondOrderVariable<kN>(kX[i], i);
  const J2 r2 = f(static_cast<const J2*>(z));
  CHECK(close(r2.a.a, e.value));
  for (int i = 0; i < kN; ++i) {
    CHECK(close(r2.a.v[i], e.gradient[i]));
    CHECK(close(r2.v[i].a, e.gradient[i]));
    for (int j = 0; j < kN; ++j) {
      INFO("Hessian (" << i << ", " << j << ")");
      CHECK(close(r2.v[i].v[j], e.hessian(i, j)));
    }
  }

  JP p[kN];  // outer duals on x, inner ones (parameters) unseeded: ∂²/∂x∂p = 0
  for (int i = 0; i < kN; ++i) {
    p[i] = JP(InnerJet<2>(kX[i]));
    p[i].v[i] = InnerJet<2>(1.0);
  }
  const JP rp = f(static_cast<const JP*>(p));
  CHECK(close(rp.a.a, e.value));
  for (int i = 0; i < kN; ++i) {
    CHECK(close(rp.v[i].a, e.gradient[i]));
    CHECK(rp.v[i].v.cwiseAbs().maxCoeff() == 0.0);
  }
}

}  // namespace

TEST_CASE("jet arithmetic: plain constants mix with every scalar type", "[jet_arithmetic]") {
  // f = 2.0·x0 + x1/3 + (x2 + 1.0) − (1 − x3) + 3·x4·x5 − 2/x5 + 0.5·x0²; compound assignments apply the same.
  const auto f = [](const auto* x) {
    using T = std::decay_t<decltype(*x)>;
    T s = 2.0 * x[0] + x[1] / 3 + (x[2] + 1.0) - (1 - x[3]) + 3 * x[4] * x[5] - 2 / x[5];
    T q = x[0] * x[0];
    q *= 0.5;
    q /= 2;
    q *= 2.0;
    q += 1;
    q -= 1.0;
    return s + q;
  };
  Expected e;
  const double* x = kX;
  e.value = 2 * x[0] + x[1] / 3 + x[2] + 1 - 1 + x[3] + 3 * x[4] * x[5] - 2 / x[5] + 0.5 * x[0] * x[0];
  e.gradient << 2 + x[0], 1.0 / 3, 1, 1, 3 * x[5], 3 * x[4] + 2 / (x[5] * x[5]);
  e.hessian(0, 0) = 1;
  e.hessian(4, 5) = e.hessian(5, 4) = 3;
  e.hessian(5, 5) = -4 / (x[5] * x[5] * x[5]);
  checkEveryScalar(f, e);
}

TEST_CASE("jet arithmetic: comparisons with plain numbers see the value", "[jet_arithmetic]") {
  J2 z[kN];
  for (int i = 0; i < kN; ++i) z[i] = secondOrderVariable<kN>(kX[i], i);
  const J1 y(0.4, 0);
  CHECK(z[0] < 0.5);
  CHECK(z[0] > 0);
  CHECK(0.3 < z[0]);
  CHECK(z[2] <= -0.5);
  CHECK(!(z[2] < -0.5));
  CHECK(z[0] == 0.4);
  CHECK(z[0] != 1);
  CHECK(z[1] >= z[0]);
  CHECK(y < 1);
  CHECK(y >= 0.4);
  CHECK((z[3] < 0.5 ? 0 : 1) == 1);
}

TEST_CASE("jet arithmetic: dot, norm and squaredNorm", "[jet_arithmetic]") {
  const Vector3d a = handA(), b = handB();
  SECTION("a.dot(b)") {
    Expected e;
    e.value = a.dot(b);
    e.gradient << b, a;
    e.hessian.topRightCorner<3, 3>() = e.hessian.bottomLeftCorner<3, 3>() = Matrix3d::Identity();
    checkEveryScalar([](const auto* x) { return vecA(x).dot(vecB(x)); }, e);
  }
  SECTION("a.norm()") {
    Expected e;
    const double r = a.norm();
    e.value = r;
    e.gradient.head<3>() = a / r;
    e.hessian.topLeftCorner<3, 3>() = (Matrix3d::Identity() - a * a.transpose() / (r * r)) / r;
    checkEveryScalar([](const auto* x) { return vecA(x).norm(); }, e);
  }
  SECTION("b.squaredNorm()") {
    Expected e;
    e.value = b.squaredNorm();
    e.gradient.tail<3>() = 2 * b;
    e.hessian.bottomRightCorner<3, 3>() = 2 * Matrix3d::Identity();
    checkEveryScalar([](const auto* x) { return vecB(x).squaredNorm(); }, e);
  }
}

TEST_CASE("jet arithmetic: cross, sum, scaling of vectors", "[jet_arithmetic]") {
  const Vector3d a = handA(), b = handB();
  for (int k = 0; k < 3; ++k) {
    // (a × b)_k = Σ ε_kij a_i b_j: ∂/∂a = −skew(b) row k, ∂/∂b = skew(a) row k, ∂²/∂a_i∂b_j = ε_kij.
    Expected e;
    e.value = a.cross(b)[k];
    e.gradient.head<3>() = -skew(b).row(k).transpose();
    e.gradient.tail<3>() = skew(a).row(k).transpose();
    const Matrix3d eps = -skew(Vector3d::Unit(k));  // eps(i, j) = ε_kij
    e.hessian.topRightCorner<3, 3>() = eps;
    e.hessian.bottomLeftCorner<3, 3>() = eps.transpose();
    checkEveryScalar([k](const auto* x) { return vecA(x).cross(vecB(x))[k]; }, e);
  }
  // (2.0·a − b/3.0 + a/2 − 1.0·b·2).sum() is linear: gradient (2.5, 2.5, 2.5, −7/3, −7/3, −7/3).
  Expected e;
  e.value = (2.5 * a - 7.0 / 3.0 * b).sum();
  e.gradient << 2.5, 2.5, 2.5, -7.0 / 3.0, -7.0 / 3.0, -7.0 / 3.0;
  checkEveryScalar([](const auto* x) { return (2.0 * vecA(x) - vecB(x) / 3.0 + vecA(x) / 2 - 1.0 * vecB(x) * 2).sum(); },
                   e);
}

TEST_CASE("jet arithmetic: normalized difference", "[jet_arithmetic]") {
  const Vector3d d = handA() - handB();
  const double r = d.norm();
  const Vector3d n = d / r;
  for (int k = 0; k < 3; ++k) {
    // n_k(d): ∂n_k/∂d_i = (δ_ki − n_k n_i)/r; ∂²n_k/∂d_i∂d_j = −(δ_ki n_j + δ_kj n_i + δ_ij n_k − 3 n_k n_i n_j)/r².
    // d = a − b: the b blocks change sign once per derivative.
    Vector3d g;
    Matrix3d h;
    for (int i = 0; i < 3; ++i) {
      g[i] = ((i == k) - n[k] * n[i]) / r;
      for (int j = 0; j < 3; ++j)
        h(i, j) = -((i == k) * n[j] + (j == k) * n[i] + (i == j) * n[k] - 3 * n[k] * n[i] * n[j]) / (r * r);
    }
    Expected e;
    e.value = n[k];
    e.gradient << g, -g;
    e.hessian << h, -h, -h, h;
    checkEveryScalar([k](const auto* x) { return (vecA(x) - vecB(x)).normalized()[k]; }, e);
  }
}

TEST_CASE("jet arithmetic: 3×3 products, trace and determinants", "[jet_arithmetic]") {
  const Vector3d a = handA(), b = handB(), c(0.3, -1.1, 0.6);
  SECTION("trace(M Mᵀ) with M = [a b c]: |a|² + |b|² + |c|²") {
    Expected e;
    e.value = a.squaredNorm() + b.squaredNorm() + c.squaredNorm();
    e.gradient << 2 * a, 2 * b;
    e.hessian = 2 * Mat6::Identity();
    checkEveryScalar(
        [c](const auto* x) {
          using T = std::decay_t<decltype(*x)>;
          Eigen::Matrix<T, 3, 3> m;
          m << vecA(x), vecB(x), c.cast<T>();
          const Eigen::Matrix<T, 3, 3> p = m * m.transpose();
          return p.trace();
        },
        e);
  }
  SECTION("(M G)(1, 2) with a constant G: linear in a and b") {
    Matrix3d g;
    g << 1, 2, 3, -1, 0.5, 4, 2, -2, 1;
    Matrix3d m;
    m << a, b, c;
    Expected e;
    e.value = (m * g)(1, 2);
    e.gradient << g(0, 2) * Vector3d::Unit(1), g(1, 2) * Vector3d::Unit(1);  // ∂/∂a_1 = G(0,2), ∂/∂b_1 = G(1,2)
    checkEveryScalar(
        [c, g](const auto* x) {
          using T = std::decay_t<decltype(*x)>;
          Eigen::Matrix<T, 3, 3> mt;
          mt << vecA(x), vecB(x), c.cast<T>();
          const Eigen::Matrix<T, 3, 3> p = mt * g.cast<T>();
          return p(1, 2);
        },
        e);
  }
  SECTION("det [a b c] = c · (a × b)") {
    Expected e;
    e.value = c.dot(a.cross(b));
    e.gradient << b.cross(c), c.cross(a);
    const Matrix3d eps = -skew(c);  // ∂²/∂a_i∂b_j = Σ_k ε_kij c_k = −skew(c)(i, j)
    e.hessian.topRightCorner<3, 3>() = eps;
    e.hessian.bottomLeftCorner<3, 3>() = eps.transpose();
    checkEveryScalar(
        [c](const auto* x) {
          using T = std::decay_t<decltype(*x)>;
          Eigen::Matrix<T, 3, 3> m;
          m << vecA(x), vecB(x), c.cast<T>();
          return m.determinant();
        },
        e);
  }
  SECTION("det [[a0 b0] [a1 b1]] = a0 b1 − a1 b0") {
    Expected e;
    e.value = a[0] * b[1] - a[1] * b[0];
    e.gradient << b[1], -b[0], 0, -a[1], a[0], 0;
    e.hessian(0, 4) = e.hessian(4, 0) = 1;
    e.hessian(1, 3) = e.hessian(3, 1) = -1;
    checkEveryScalar(
        [](const auto* x) {
          using T = std::decay_t<decltype(*x)>;
          Eigen::Matrix<T, 2, 2> m;
          m << x[0], x[3], x[1], x[4];
          return m.determinant();
        },
        e);
  }
}

TEST_CASE("jet arithmetic: math functions with one plain number", "[jet_arithmetic]") {
  // f = atan2(x0, 2) + 2^x1 + fmax(x2, −1) + hypot(x3, 1) + fmin(x4, 0.5) + √x5 (here x2 > −1 and x4 < 0.5).
  const auto f = [](const auto* x) {
    using std::atan2, std::pow, std::fmax, std::fmin, std::hypot, std::sqrt;
    return atan2(x[0], 2.0) + pow(2.0, x[1]) + fmax(x[2], -1.0) + hypot(x[3], 1.0) + fmin(x[4], 0.5) + sqrt(x[5]);
  };
  const double* x = kX;
  const double q = x[0] * x[0] + 4, h = std::hypot(x[3], 1.0), p = std::pow(2.0, x[1]), l = std::log(2.0);
  Expected e;
  e.value = std::atan2(x[0], 2.0) + p + x[2] + h + x[4] + std::sqrt(x[5]);
  e.gradient << 2 / q, l * p, 1, x[3] / h, 1, 0.5 / std::sqrt(x[5]);
  e.hessian.diagonal() << -4 * x[0] / (q * q), l * l * p, 0, 1 / (h * h * h), 0, -0.25 / (x[5] * std::sqrt(x[5]));
  checkEveryScalar(f, e);
}
