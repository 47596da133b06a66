#include "risas/orientation_histogram.hpp"

#include <opencv2/core.hpp>

#include <cmath>

namespace risas {
namespace {

// Bin b of the circle, for b in [-kOrientationBins, 2 kOrientationBins).
size_t wrapBin(int b) {
  return static_cast<size_t>(b < 0 ? b + kOrientationBins : b >= kOrientationBins ? b - kOrientationBins : b);
}

}  // namespace

double histogramPeak(OrientationHistogram histogram) {
  for (int pass = 0; pass < 4; ++pass) {
    OrientationHistogram next{};
    for (int b = 0; b < kOrientationBins; ++b) {
      next[wrapBin(b)] = 0.25 * (histogram[wrapBin(b - 1)] + 2.0 * histogram[wrapBin(b)] + histogram[wrapBin(b + 1)]);
    }
    histogram = next;
  }
  int peak = 0;
  for (int b = 1; b < kOrientationBins; ++b) {
    if (histogram[wrapBin(b)] > histogram[wrapBin(peak)]) peak = b;
  }
  const double left = histogram[wrapBin(peak - 1)], centre = histogram[wrapBin(peak)],
               right = histogram[wrapBin(peak + 1)];
  if (!(centre > 0.0)) return 0.0;  // nothing voted: a flat patch
  const double curvature = left - 2.0 * centre + right;
  const double offset = curvature < 0.0 ? 0.5 * (left - right) / curvature : 0.0;
  return (peak + 0.5 + offset) * (2.0 * CV_PI / kOrientationBins);
}

}  // namespace risas
