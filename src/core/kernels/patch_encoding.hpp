// The fast kernel of the descriptor's histogram: PatchEncoder::encode
// (encoding.hpp, encoding.cpp) computed in passes over arrays of the disc's
// samples (placement, look-ups, labels, counting-sort ranks). Held equal to
// the readable encoding by Descriptor.EncodingIsThePapersHistogramOnEveryPath.
#pragma once

#include "risas/encoding.hpp"
#include "risas/geometry.hpp"
#include "risas/neighbourhood.hpp"
#include "risas/params.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace risas {

// The disc's samples: offsets in units of the radius, and spatial labels.
struct DiscLayout {
  const std::vector<float>& i;
  const std::vector<float>& j;
  const std::vector<uint16_t>& sector;
};

// PatchEncoder::encode's result for the same inputs (lambda: the patch's
// sampleLevel), bit for bit.
bool encodePatchKernel(const GreyPyramid& grey, float lambda, const FrameGeometry& geometry,
                       const Neighbourhood& neighbourhood, float radius_px, double theta, const DiscLayout& disc,
                       const DescriptorParams& params, float* out);

}  // namespace risas
