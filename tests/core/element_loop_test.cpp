#include "core/element_loop.h"
#include "energies/element_energy_term.h"

#include <catch2/catch.hpp>

#include <omp.h>

#include <cmath>

#include <atomic>
#include <cstring>
#include <stdexcept>

using namespace jetshell;

namespace {

/// A 1-vertex energy that throws on some elements (as a user functor might on bad input).
struct Throwing {
  static constexpr int kVertices = 1;
  int bad = -1;
  template <typename T>
  T operator()(const T* x, int e) const {
    if (e >= bad) throw std::runtime_error("element " + std::to_string(e) + " refused");
    return x[0] * x[0];
  }
};

/// A 5-vertex (15-dof) energy whose nested-Jet Hessian is a costly element; records the largest team it ran in.
struct Chain5 {
  static constexpr int kVertices = 5;
  std::atomic<int>* team = nullptr;
  template <typename T>
  T operator()(const T* x, int) const {
    int seen = team->load();
    const int now = omp_get_num_threads();
    while (now > seen && !team->compare_exchange_weak(seen, now)) {
    }
    T s = x[0] * x[14];
    for (int i = 0; i + 1 < 15; ++i) s = s + x[i] * x[i + 1] * x[(i + 7) % 15];
    return s * s;
  }
};

}  // namespace

TEST_CASE("element loop: a few dozen costly elements (nested-Jet Hessians) run in parallel with the same bits") {
  const int ne = 96, n = ne + 4;  // fewer than kParallelMinElements, at least kParallelMinCostlyElements
  REQUIRE(ne < kParallelMinElements);
  REQUIRE(ne >= kParallelMinCostlyElements);
  StencilTable t{5, {}};
  for (int e = 0; e < ne; ++e)
    for (int k = 0; k < 5; ++k) t.ids.push_back(e + k);  // neighbours share four vertices
  std::atomic<int> team{0};
  ElementEnergyTerm<Chain5> term("chain5", t, n, Chain5{&team});
  Eigen::VectorXd x(3 * n);
  for (int i = 0; i < x.size(); ++i) x[i] = std::sin(0.37 * i);
  HessianAssembler A;
  const int slot = A.addStencils(term.stencils());
  A.finalize(n);
  Eigen::VectorXd g[2];
  Eigen::SparseMatrix<double> H[2];
  double E[2];
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    team = 0;
    A.setZero();
    g[threads - 1] = Eigen::VectorXd::Zero(3 * n);
    E[threads - 1] = term.evaluate(x, EvalRequest{&g[threads - 1], &A, slot}, EvalOptions{});
    H[threads - 1] = A.matrix();
    CHECK(team.load() == threads);
  }
  omp_set_num_threads(saved);
  CHECK(E[0] == E[1]);
  CHECK(std::memcmp(g[0].data(), g[1].data(), sizeof(double) * static_cast<std::size_t>(g[0].size())) == 0);
  REQUIRE(H[0].nonZeros() == H[1].nonZeros());
  CHECK(std::memcmp(H[0].valuePtr(), H[1].valuePtr(), sizeof(double) * static_cast<std::size_t>(H[0].nonZeros())) == 0);
  // A gradient alone is cheap per element: it stays serial below kParallelMinElements.
  omp_set_num_threads(2);
  team = 0;
  term.evaluate(x, EvalRequest{&g[0], nullptr, -1}, EvalOptions{});
  CHECK(team.load() == 1);
  omp_set_num_threads(saved);
}

TEST_CASE("element loop: an exception thrown by an element inside the parallel loop reaches the caller") {
  const int n = 2000;  // above the serial threshold: the loop runs in an OpenMP region
  StencilTable t{1, {}};
  for (int v = 0; v < n; ++v) t.ids.push_back(v);
  ElementEnergyTerm<Throwing> term("throwing", t, n, Throwing{n / 2});
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(3 * n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * n);
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    CHECK_THROWS_WITH(term.evaluate(x, EvalRequest{}, EvalOptions{}), Catch::Contains("refused"));
    CHECK_THROWS_WITH(term.evaluate(x, EvalRequest{&g, nullptr, -1}, EvalOptions{}), Catch::Contains("refused"));
  }
  ElementEnergyTerm<Throwing> fine("fine", t, n, Throwing{n});
  CHECK(fine.evaluate(x, EvalRequest{}, EvalOptions{}) == Approx(n));
}
