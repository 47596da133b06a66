// The fast kernel of gradientOrientation (orientation.hpp, orientation.cpp):
// the same grid, the same votes and the same histogram (its sums taken in
// another order), read through raw pointers, with each grid column's and
// row's place in the image and on the pyramid's levels found once. Held
// equal to the readable function by
// Orientation.GradientOrientationKernelEqualsTheReadableRule.
#pragma once

#include "risas/encoding.hpp"
#include "risas/geometry.hpp"
#include "risas/neighbourhood.hpp"
#include "risas/params.hpp"

namespace risas {

// Whether the kernel takes discs of params.patch_radius: up to 27 samples
// (a grid row's bits fit one 64-bit word; the default is 14, the
// reference's 20). Wider discs take the readable rule.
bool gradientOrientationKernelFits(const DescriptorParams& params);

// gradientOrientation's theta for the same inputs, within float rounding.
// Requires gradientOrientationKernelFits(params).
double gradientOrientationKernel(const GreyPyramid& grey, const FrameGeometry& geometry,
                                 const Neighbourhood& neighbourhood, float radius_px, const DescriptorParams& params);

}  // namespace risas
