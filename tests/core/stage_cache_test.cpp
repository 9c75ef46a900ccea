#include "core/stage_cache.h"

#include <catch2/catch.hpp>

#include <stdexcept>

using namespace jetshell;

namespace {

struct Counted {
  static constexpr int kInputs = 1, kOutputs = 1;
  int* calls = nullptr;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    y[0] = z[0] * z[0];
    if constexpr (std::is_same_v<T, double>) ++*calls;
  }
};

}  // namespace

TEST_CASE("stage cache: an entity is computed once per evaluation and must keep its inputs", "[stages]") {
  int calls = 0;
  StageCache<Counted> cache(Counted{&calls}, 3);
  StageContext ctx;
  ctx.epoch = 1;
  const double z = 2.0, other = 3.0;
  CHECK(cache.get(1, &z, ctx).value[0] == 4.0);
  CHECK(cache.get(1, &z, ctx).value[0] == 4.0);
  CHECK(calls == 1);
  CHECK_THROWS_AS(cache.get(1, &other, ctx), std::logic_error);
  ctx.epoch = 2;  // a new evaluation recomputes
  CHECK(cache.get(1, &other, ctx).value[0] == 9.0);
  CHECK(calls == 2);
}
