// A loop unrolled at compile time: f(std::integral_constant<int, i>()) for i = 0 … N−1, so that the body can use i
// as a template argument (a stage graph's layers, a stage's input groups).
#pragma once

#include <type_traits>
#include <utility>

namespace jetshell {

template <typename F, int... Is>
void forEachIndexIn(F&& f, std::integer_sequence<int, Is...>) {
  (f(std::integral_constant<int, Is>()), ...);
}

template <int N, typename F>
void forEachIndex(F&& f) {
  forEachIndexIn(f, std::make_integer_sequence<int, N>());
}

}  // namespace jetshell
