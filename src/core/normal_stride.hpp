// Internal to the core: loops that index the normals' blocks by the stride.
#pragma once

#include "risas/params.hpp"

#include <type_traits>

namespace risas {

// Calls f(stride), with the default normal stride as a compile-time constant
// (std::integral_constant) and any other as an int. A loop that divides by
// the stride or steps by it then compiles to shifts and fixed-step loads for
// the default, instead of a division per pixel.
template <class F>
decltype(auto) withNormalStride(int stride, F&& f) {
  constexpr int kDefault = GeometryParams::kDefaultNormalStride;
  if (stride == kDefault) return f(std::integral_constant<int, kDefault>());
  return f(stride);
}

}  // namespace risas
