#include "core/element_loop.h"
#include "energies/element_energy_term.h"

#include <catch2/catch.hpp>

#include <omp.h>

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

}  // namespace

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
