// gradientOrientation's pieces that its readable form (orientation.cpp) and
// its kernel (kernels/gradient_orientation.cpp) share: the grid's sample
// kinds, the reach of the blur, and the histogram of gradient directions.
#pragma once

#include "risas/encoding.hpp"

#include <array>
#include <cmath>

namespace risas {

// How far, in samples, the pyramid's blur of kOrientationBlur spacings
// carries the background's grey across a silhouette: twice the blur,
// rounded up. A gradient read there points at the background, not along the
// surface's pattern.
constexpr int kBlurReach = static_cast<int>(2.0 * kOrientationBlur + 0.999);

// What a grid sample shows, from the depth at its nearest pixel.
enum class SampleKind : unsigned char {
  Counted,     // a normal, and foreground by eq. 5: as the encoder counts a sample
  Uncounted,   // no depth or no normal: no vote, but its grey is the surface's or a hole's
  Background,  // outside the image, or beyond t of k_i (eq. 5): its grey is not the surface's
};

// 36 bins of 10 degrees, as SIFT's; bin b's centre at (b + 0.5) 10 degrees.
constexpr int kOrientationBins = 36;
using OrientationHistogram = std::array<double, kOrientationBins>;

// weight into the two bins nearest `degrees` (in [0, 360]), shared linearly.
inline void voteDirection(OrientationHistogram& histogram, float degrees, double weight) {
  const double bin = degrees / 360.0 * kOrientationBins - 0.5;
  const int below = static_cast<int>(std::floor(bin));
  const double above_share = bin - below;
  // below in [-1, 35]; the circle wraps -1 to 35 and 36 to 0.
  const int lower = below < 0 ? below + kOrientationBins : below;
  const int upper = below + 1 >= kOrientationBins ? below + 1 - kOrientationBins : below + 1;
  histogram[static_cast<size_t>(lower)] += weight * (1.0 - above_share);
  histogram[static_cast<size_t>(upper)] += weight * above_share;
}

// The histogram smoothed by four passes of [1 2 1] / 4 around the circle, a
// binomial of about 14 degrees (OpenCV's SIFT smooths with two passes,
// VLFeat's with six of a three-bin box: a corner's two edges each make a
// peak, and an unsmoothed histogram's highest bin jumps between them with
// the noise), then its highest bin's angle refined by the vertex of the
// parabola through it and its two neighbours: radians in [0, 2 pi), 0 when
// nothing voted.
double histogramPeak(OrientationHistogram histogram);

}  // namespace risas
