// ElementEnergyTerm's difference coordinates: a functor that declares kTranslationInvariant gets the same value,
// gradient and Hessian (exact and projected) as the same energy differentiated in full coordinates, and the
// derivative checks (tools/checks/term_check.h) refuse a false claim.
#include "core/assembly.h"
#include "energies/element_energy_term.h"
#include "tools/checks/term_check.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;

namespace {

/// A 3-vertex energy of the edge vectors a = x1 − x0, b = x2 − x0 alone: a stretched spring, a bent pair and a
/// smooth cutoff (as the point-pair penalty's square root of a squared distance).
struct Triple {
  static constexpr int kVertices = 3;
  template <typename T>
  T operator()(const T* x, int e) const {
    using std::sqrt;
    T a[3], b[3];
    for (int c = 0; c < 3; ++c) {
      a[c] = x[3 + c] - x[c];
      b[c] = x[6 + c] - x[c];
    }
    const T la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const T ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const T stretch = la - constant<T>(0.3 + 0.01 * e);
    return stretch * stretch * constant<T>(40.0) + ab * ab * ab - constant<T>(2.0) * ab * la;
  }
};

/// The same energy, declared translation-invariant: its Jets carry vertices 1 and 2 only.
struct TripleInDifferences : Triple {
  static constexpr bool kTranslationInvariant = true;
};

/// A 2-vertex one (the point pairs' width: the inlined path).
struct Pair {
  static constexpr int kVertices = 2;
  template <typename T>
  T operator()(const T* x, int) const {
    using std::sqrt;
    T d2 = constant<T>(0.0);
    for (int c = 0; c < 3; ++c) d2 = d2 + (x[3 + c] - x[c]) * (x[3 + c] - x[c]);
    const T gap = constant<T>(0.05) - sqrt(d2);
    return gap * gap * gap;
  }
};
struct PairInDifferences : Pair {
  static constexpr bool kTranslationInvariant = true;
};

/// A pair energy that also depends on where the pair is (a height term): not translation-invariant.
struct Anchored : Pair {
  template <typename T>
  T operator()(const T* x, int e) const {
    return Pair::operator()(x, e) + x[1] * x[1] * x[4];
  }
};
/// The same, falsely declared translation-invariant.
struct FalselyInvariant : Anchored {
  static constexpr bool kTranslationInvariant = true;
};

template <typename Full, typename Reduced>
void checkSameDerivatives(const StencilTable& table, int n) {
  static_assert(!ElementEnergyTerm<Full>::kDifferences);
  static_assert(ElementEnergyTerm<Reduced>::kDifferences);
  ElementEnergyTerm<Full> full("full", table, n, Full{}, false);
  ElementEnergyTerm<Reduced> reduced("reduced", table, n, Reduced{}, false);
  Eigen::VectorXd x(3 * n);
  for (int i = 0; i < x.size(); ++i) x[i] = 0.02 * std::sin(1.7 * i + 0.3) + 0.01 * (i % 5);
  for (PsdProjection projection : {PsdProjection::None, PsdProjection::Clamp}) {
    INFO("projection " << static_cast<int>(projection));
    EvalOptions options;
    options.projection = projection;
    Eigen::VectorXd g[2];
    Eigen::SparseMatrix<double> H[2];
    double E[2];
    for (int k = 0; k < 2; ++k) {
      HessianAssembler A;
      const int slot = A.addStencils(table);
      A.finalize(n);
      A.setZero();
      g[k] = Eigen::VectorXd::Zero(3 * n);
      E[k] = (k == 0 ? static_cast<EnergyTerm&>(full) : static_cast<EnergyTerm&>(reduced))
                 .evaluate(x, EvalRequest{&g[k], &A, slot}, options);
      H[k] = A.matrix();
    }
    CHECK(E[1] == Approx(E[0]).epsilon(1e-14));
    const double gScale = g[0].cwiseAbs().maxCoeff(), hScale = Eigen::MatrixXd(H[0]).cwiseAbs().maxCoeff();
    REQUIRE(gScale > 0.0);
    REQUIRE(hScale > 0.0);
    CHECK((g[1] - g[0]).cwiseAbs().maxCoeff() <= 1e-12 * gScale);
    CHECK((Eigen::MatrixXd(H[1]) - Eigen::MatrixXd(H[0])).cwiseAbs().maxCoeff() <= 1e-12 * hScale);
    // A gradient alone takes the first-order Jets.
    Eigen::VectorXd gOnly = Eigen::VectorXd::Zero(3 * n);
    reduced.evaluate(x, EvalRequest{&gOnly, nullptr, -1}, options);
    CHECK((gOnly - g[0]).cwiseAbs().maxCoeff() <= 1e-12 * gScale);
  }
}

}  // namespace

TEST_CASE("element energy term: a translation-invariant energy gives the same derivatives in difference "
          "coordinates as in full ones") {
  SECTION("three vertices") {
    StencilTable t{3, {0, 1, 2, 2, 1, 3, 3, 4, 0}};
    checkSameDerivatives<Triple, TripleInDifferences>(t, 5);
  }
  SECTION("two vertices, the inlined path") {
    StencilTable t{2, {0, 1, 1, 2, 3, 0}};
    checkSameDerivatives<Pair, PairInDifferences>(t, 4);
  }
}

TEST_CASE("element energy term: the derivative checks catch a false translation-invariance claim") {
  const StencilTable t{2, {0, 1, 1, 2}};
  Eigen::VectorXd x(9);
  for (int i = 0; i < x.size(); ++i) x[i] = 0.02 * std::sin(1.3 * i + 0.2) + 0.01 * (i % 4);
  ElementEnergyTerm<Anchored> honest("anchored", t, 3, Anchored{}, false, false);
  ElementEnergyTerm<FalselyInvariant> claimed("falsely_invariant", t, 3, FalselyInvariant{}, false, false);
  CHECK(termCheckFailures(honest, x).empty());
  CHECK_FALSE(termCheckFailures(claimed, x).empty());
}
