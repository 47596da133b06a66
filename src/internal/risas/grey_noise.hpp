// The grey image's noise, for the descriptor's ranks (descriptor.grey_noise):
// how far apart two grey levels must be before their order is the scene's
// rather than the sensor's.
#pragma once

#include <opencv2/core.hpp>

namespace risas {

// The standard deviation of the zero-mean noise on an 8-bit grey image, in
// grey levels, by Immerkaer's estimator (J. Immerkaer, "Fast noise variance
// estimation", CVIU 64(2), 1996): the mean absolute response to the 3x3
// mask [1 -2 1; -2 4 -2; 1 -2 1], which cancels any plane of grey, times
// sqrt(pi / 2) / 6. Edges and fine texture add to it, so on a textured image
// it reads somewhat high. 0 for an image under 3 x 3 pixels, which has no
// pixel the mask fits around. gray: CV_8UC1.
double estimateGreyNoise(const cv::Mat& gray);

}  // namespace risas
