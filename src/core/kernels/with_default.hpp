// Internal to the core: loops compiled for a parameter's default value.
#pragma once

#include <type_traits>
#include <utility>

namespace risas {

// Calls f(value), with value as a compile-time constant
// (std::integral_constant<int, k>) when it is one of the defaults k and as an
// int otherwise. f is compiled once per default and once for int: for a
// default the compiler turns divisions by the value into shifts, steps of it
// into fixed-step loads and loops over it into straight vector code. A
// caller whose loop must differ for a run-time value branches on the type
// (std::is_integral_v<decltype(value)>).
template <int kDefault, int... kOthers, class F>
decltype(auto) withDefault(int value, F&& f) {
  if (value == kDefault) return f(std::integral_constant<int, kDefault>());
  if constexpr (sizeof...(kOthers) > 0) {
    return withDefault<kOthers...>(value, std::forward<F>(f));
  } else {
    return f(value);
  }
}

}  // namespace risas
