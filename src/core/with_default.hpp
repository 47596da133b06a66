// Internal to the core: loops compiled for a parameter's default value.
#pragma once

#include <type_traits>

namespace risas {

// Calls f(value), with value as a compile-time constant
// (std::integral_constant<int, kDefault>) when it is kDefault and as an int
// otherwise. One loop body serves both: for the default the compiler turns
// divisions by the value into shifts, steps of it into fixed-step loads and
// loops over it into straight vector code.
template <int kDefault, class F>
decltype(auto) withDefault(int value, F&& f) {
  if (value == kDefault) return f(std::integral_constant<int, kDefault>());
  return f(value);
}

}  // namespace risas
